/* External loads of the deck's boundary_conditions: body forces (force density) and tractions
 * (spread over a layer of the surface, b = T / layer), expressions of x, y, z and t. */
#include "peri/contribution.h"

static bool is_load(const peri_bc *bc) { return bc->kind == PERI_BC_BODY_FORCE || bc->kind == PERI_BC_TRACTION; }

static bool loads_active(const peri_sim *s) {
  for (int k = 0; k < s->cond.n_bcs; ++k)
    if (is_load(&s->cond.bcs[k])) return true;
  return false;
}

static void add_loads(peri_sim *s, double t, bool sets) {
  (void)sets; /* reaches the nodes of its regions only: never asked to set every node */
  peri_particles *p = &s->disc.p;
  for (int k = 0; k < s->cond.n_bcs; ++k) {
    const peri_bc *bc = &s->cond.bcs[k];
    if (!is_load(bc)) continue;
    const double scale = bc->kind == PERI_BC_TRACTION ? 1.0 / bc->layer : 1.0;
    const peri_region *r = &s->cond.regions[bc->region];
    for (int32_t a = 0; a < r->count; ++a) {
      int32_t i = r->nodes[a];
      const double *x = &p->x[3 * i];
      for (int d = 0; d < 3; ++d)
        if (bc->value[d]) p->b[3 * i + d] += scale * peri_expr_eval(bc->value[d], x[0], x[1], x[2], t);
    }
  }
}

const peri_contribution_ops peri_contribution_external_loads = {
    .name = "external_loads",
    .active = loads_active,
    .add_load = add_loads,
};
