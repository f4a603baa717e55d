/* Short-range contact forces (docs/contact.md; MODELS.md 17.1): a repulsive force between any
 * two nodes closer than d_ij = min(0.9 |x_i - x_j|, 1.35 (r_i + r_j)), bonded or not, in the
 * LAMMPS form (pair peri/pmb): force density on i
 *     b_i += (c_S/delta) (d_ij - r) V_j (y_i - y_j)/r,   r = |y_i - y_j| < d_ij,
 * c_S = stiffness_factor x (c_i + c_j)/2 (the half-bond rule, so that the pair's forces
 * V_i b_i and V_j b_j are opposite across materials). Each owned node sums its own partners
 * in index order (a gather over the full list, pruned): no two threads write one node, and
 * the sum is the same on any thread count and whenever the list was built or pruned. On MPI
 * ranks the partners of other ranks are contact ghosts (include/peri/contact_ghosts.h)
 * numbered in the global order, so each node sums the same terms in the same order as in one
 * process: the forces are the same, bit for bit, on any rank count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/constants.h"
#include "peri/contact.h"
#include "peri/short_range.h"
#include "peri/contribution.h"
#include "peri/error.h"

void peri_contact_init(peri_sim *s) {
  peri_contact *c = s->contact;
  free(c->c_material);
  c->c_material = peri_malloc(sizeof(double) * (size_t)(s->mat.n_materials > 0 ? s->mat.n_materials : 1));
  for (int m = 0; m < s->mat.n_materials; ++m) {
    const peri_material *mat = &s->mat.materials[m];
    /* the PMB micromodulus of the dimension (LAMMPS: 18 K / (pi delta^4) in 3D, or c given) */
    c->c_material[m] = mat->micromodulus_given ? mat->micromodulus : peri_pmb_micromodulus(&s->disc.geom, mat->E, mat->K);
  }
  c->min_ratio = 1.0; /* no pair in contact before the first evaluation */
}

double peri_contact_max_reach(const peri_sim *s) {
  return PERI_SHORT_RANGE_RADIUS * s->disc.geom.spacing; /* 1.35 (r_i + r_j), r = dx/2 */
}

double peri_contact_min_ratio(const peri_sim *s) { return peri_comm_min(s->contact->min_ratio); }

long peri_contact_pairs(const peri_sim *s) {
  const peri_contact_list *l = &s->contact->list;
  return peri_comm_sum_long(l->offset ? (long)l->offset[l->n] : 0L);
}

long peri_contact_pruned_pairs(const peri_sim *s) {
  const peri_contact_list *l = &s->contact->list;
  long pairs = 0;
  for (int32_t i = 0; l->pruned_end && i < l->n; ++i) pairs += (long)(l->pruned_end[i] - l->offset[i]);
  return peri_comm_sum_long(pairs);
}

long peri_contact_ghost_count(const peri_sim *s) { return peri_comm_sum_long(s->contact->ghosts.ghosts); }

void peri_contact_free(peri_contact *c) {
  if (!c) return;
  free(c->c_material);
  free(c->y_owned);
  peri_contact_list_free(&c->list);
  peri_contact_ghosts_free(&c->ghosts, &c->nodes);
  free(c);
}

/* The contact nodes' deformed positions: the owned ones from x + u, the ghosts' from their
 * owners. When some node of any rank has moved half the skin, the ghosts are found again
 * and the list is rebuilt, then pruned; when some node has moved half the prune skin, the
 * list is pruned. Every rank takes the same decision, so the builds and prunes are those of
 * one process. */
static void update_nodes(peri_sim *s) {
  peri_contact *c = s->contact;
  const peri_particles *p = &s->disc.p;
  const int32_t n = p->n_owned;
  if (!c->y_owned || c->y_owned_n != n) {
    free(c->y_owned);
    c->y_owned = peri_malloc(sizeof(double) * 3 * (n > 0 ? (size_t)n : 1));
    c->y_owned_n = n;
  }
  double *y = c->y_owned;
  const peri_contact_list_need need = (peri_contact_list_need)peri_comm_max_int(
      (int)peri_contact_list_needs(&c->list, p->x, p->u, n, c->skin, c->prune_skin, y));
  if (need == PERI_CONTACT_LIST_BUILD) {
    const peri_contact_reach reach = {PERI_SHORT_RANGE_RATIO, peri_contact_max_reach(s), c->skin};
    peri_contact_ghosts_build(&c->ghosts, &c->nodes, n, p->x, y, p->volume, p->material, reach.max_reach + reach.skin);
    peri_contact_list_build(&c->list, c->nodes.x, c->nodes.y, c->nodes.n, c->nodes.first_owned, n, p->u, &reach);
  } else {
    memcpy(&c->nodes.y[3 * (size_t)c->nodes.first_owned], y, sizeof(double) * 3 * (size_t)n);
    peri_contact_ghosts_refresh(&c->ghosts, &c->nodes);
  }
  if (need != PERI_CONTACT_LIST_FRESH) peri_contact_list_prune(&c->list, c->nodes.y, c->nodes.first_owned, p->u, c->prune_skin);
}

static void add_short_range(peri_sim *s, double t, bool sets) {
  (void)t;
  (void)sets; /* sets_every_node is false: never the setting load */
  peri_contact *c = s->contact;
  peri_particles *p = &s->disc.p;
  update_nodes(s);
  const int32_t n = p->n_owned, first = c->nodes.first_owned;
  const peri_contact_list *l = &c->list;
  const double scale = c->stiffness_factor / s->disc.geom.horizon;
  const double *y = c->nodes.y, *V = c->nodes.volume, *cm = c->c_material;
  const int32_t *mat = c->nodes.material;
  double min_ratio = 1.0;
#pragma omp parallel for schedule(static) reduction(min : min_ratio)
  for (int32_t row = 0; row < n; ++row) {
    if (l->pruned_end[row] == l->offset[row]) continue; /* most rows of a body at rest */
    const size_t i = (size_t)first + (size_t)row;
    const double yi0 = y[3 * i], yi1 = y[3 * i + 1], yi2 = y[3 * i + 2];
    double f0 = 0.0, f1 = 0.0, f2 = 0.0;
    for (int64_t k = l->offset[row]; k < l->pruned_end[row]; ++k) {
      const int32_t j = l->pruned_partner[k];
      const double d0 = yi0 - y[3 * (size_t)j], d1 = yi1 - y[3 * (size_t)j + 1], d2 = yi2 - y[3 * (size_t)j + 2];
      const double r2 = d0 * d0 + d1 * d1 + d2 * d2, d = l->pruned_reach[k];
      if (!(r2 < d * d)) continue;
      const double r = sqrt(r2);
      min_ratio = fmin(min_ratio, r / d);
      if (r2 == 0.0) continue; /* coincident nodes: no direction, as LAMMPS */
      const double g = scale * 0.5 * (cm[mat[i]] + cm[mat[j]]) * V[j] * (d - r) / r;
      f0 += g * d0;
      f1 += g * d1;
      f2 += g * d2;
    }
    p->b[3 * (size_t)row] += f0;
    p->b[3 * (size_t)row + 1] += f1;
    p->b[3 * (size_t)row + 2] += f2;
  }
  c->min_ratio = min_ratio;
}

static bool short_range_active(const peri_sim *s) { return s->contact && s->contact->short_range; }

const peri_contribution_ops peri_contribution_short_range = {
    .name = "short-range contact",
    .active = short_range_active,
    .add_load = add_short_range,
    .sets_every_node = false,
    .follows_deformation = true,
};
