/* Short-range contact forces (docs/contact.md; MODELS.md 17.1): a repulsive force between any
 * two nodes closer than d_ij = min(0.9 |x_i - x_j|, 1.35 (r_i + r_j)), bonded or not, in the
 * LAMMPS form (pair peri/pmb): force density on i
 *     b_i += (c_S/delta) (d_ij - r) V_j (y_i - y_j)/r,   r = |y_i - y_j| < d_ij,
 * c_S = stiffness_factor x (c_i + c_j)/2 (the half-bond rule, so that the pair's forces
 * V_i b_i and V_j b_j are opposite across materials). Each node sums its own partners in
 * index order (a gather over the full list): no two threads write one node, and the sum is
 * the same on any thread count and whenever the list was built. */
#include <math.h>
#include <stdlib.h>
#include "peri/constants.h"
#include "peri/contact.h"
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
}

double peri_contact_max_reach(const peri_sim *s) {
  return PERI_SHORT_RANGE_RADIUS * s->disc.geom.spacing; /* 1.35 (r_i + r_j), r = dx/2 */
}

int peri_contact_check_ranks(const peri_sim *s, int ranks) {
  if (!s->contact || !s->contact->short_range || ranks <= 1) return PERI_OK;
  peri_error("contact.short_range runs in one process (threads), not on %d MPI ranks: its pair "
             "list does not reach across ranks yet; run without mpirun (docs/contact.md)", ranks);
  return PERI_ERR_INPUT;
}

void peri_contact_free(peri_contact *c) {
  if (!c) return;
  free(c->c_material);
  peri_contact_list_free(&c->list);
  free(c);
}

static void add_short_range(peri_sim *s, double t, bool sets) {
  (void)t;
  (void)sets; /* sets_every_node is false: never the setting load */
  peri_contact *c = s->contact;
  peri_particles *p = &s->disc.p;
  const int32_t n = p->n_owned;
  const peri_contact_reach reach = {PERI_SHORT_RANGE_RATIO, peri_contact_max_reach(s), c->skin};
  if (peri_contact_list_stale(&c->list, p->u, n, c->skin)) peri_contact_list_build(&c->list, p->x, p->u, n, &reach);
  const peri_contact_list *l = &c->list;
  const double scale = c->stiffness_factor / s->disc.geom.horizon;
  const double *x = p->x, *u = p->u, *V = p->volume, *cm = c->c_material;
  const int32_t *mat = p->material;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < n; ++i) {
    const double yi0 = x[3 * (size_t)i] + u[3 * (size_t)i], yi1 = x[3 * (size_t)i + 1] + u[3 * (size_t)i + 1],
                 yi2 = x[3 * (size_t)i + 2] + u[3 * (size_t)i + 2];
    double f0 = 0.0, f1 = 0.0, f2 = 0.0;
    for (int64_t k = l->offset[i]; k < l->offset[i + 1]; ++k) {
      const int32_t j = l->partner[k];
      const double d0 = yi0 - x[3 * (size_t)j] - u[3 * (size_t)j], d1 = yi1 - x[3 * (size_t)j + 1] - u[3 * (size_t)j + 1],
                   d2 = yi2 - x[3 * (size_t)j + 2] - u[3 * (size_t)j + 2];
      const double r2 = d0 * d0 + d1 * d1 + d2 * d2, d = l->reach[k];
      if (!(r2 < d * d) || r2 == 0.0) continue; /* coincident nodes: no direction, as LAMMPS */
      const double r = sqrt(r2);
      const double g = scale * 0.5 * (cm[mat[i]] + cm[mat[j]]) * V[j] * (d - r) / r;
      f0 += g * d0;
      f1 += g * d1;
      f2 += g * d2;
    }
    p->b[3 * (size_t)i] += f0;
    p->b[3 * (size_t)i + 1] += f1;
    p->b[3 * (size_t)i + 2] += f2;
  }
}

static bool short_range_active(const peri_sim *s) { return s->contact && s->contact->short_range; }

const peri_contribution_ops peri_contribution_short_range = {
    .name = "short-range contact",
    .active = short_range_active,
    .add_load = add_short_range,
    .sets_every_node = false,
    .follows_deformation = true,
};
