/* The table of contributions and the passes the solvers call (include/peri/contribution.h).
 * The order of the table is the order in which loads add to b, so it fixes the rounding of
 * a node that several loads reach. */
#include <stddef.h>
#include "peri/contribution.h"
#include "peri/error.h"

static const peri_contribution_ops *const contributions[] = {
    &peri_contribution_external_loads, /* body forces and tractions (external_loads.c) */
    &peri_contribution_indenter,       /* rigid spherical indenter (indenter.c) */
    &peri_contribution_tools,          /* rigid tools, penalty and friction (tools.c) */
    &peri_contribution_thermal_strain, /* heat advanced to t, thermal strain (thermal_strain.c) */
    &peri_contribution_short_range,    /* short-range contact forces (short_range.c) */
};
#define N_CONTRIBUTIONS (sizeof contributions / sizeof contributions[0])

void peri_apply_loads(peri_sim *s, double t) {
  peri_particles *p = &s->disc.p;
  const peri_contribution_ops *first = NULL;
  for (size_t k = 0; k < N_CONTRIBUTIONS && !first; ++k)
    if (contributions[k]->add_load && contributions[k]->active(s)) first = contributions[k];
  /* a first load that writes every owned node spares the pass that clears them */
  const bool first_sets = first && first->sets_every_node;
  const size_t zero_from = first_sets ? 3 * (size_t)p->n_owned : 0, zero_to = 3 * (size_t)p->n;
#pragma omp parallel for schedule(static) if (zero_to - zero_from > 65536)
  for (size_t c = zero_from; c < zero_to; ++c) p->b[c] = 0.0;
  for (size_t k = 0; k < N_CONTRIBUTIONS; ++k) {
    const peri_contribution_ops *c = contributions[k];
    if (c->add_load && c->active(s)) c->add_load(s, t, first_sets && c == first);
  }
}

int peri_contributions_before_force(peri_sim *s, long step, double t) {
  for (size_t k = 0; k < N_CONTRIBUTIONS; ++k) {
    const peri_contribution_ops *c = contributions[k];
    if (!c->before_force || !c->active(s)) continue;
    const int rc = c->before_force(s, step, t);
    if (rc != PERI_OK) return rc;
  }
  return PERI_OK;
}

bool peri_loads_follow_deformation(const peri_sim *s) {
  for (size_t k = 0; k < N_CONTRIBUTIONS; ++k)
    if (contributions[k]->follows_deformation && contributions[k]->active(s)) return true;
  return false;
}

void peri_contributions_tangent(const peri_sim *s, peri_tangent_add_fn add, void *ctx) {
  for (size_t k = 0; k < N_CONTRIBUTIONS; ++k)
    if (contributions[k]->tangent && contributions[k]->active(s)) contributions[k]->tangent(s, add, ctx);
}
