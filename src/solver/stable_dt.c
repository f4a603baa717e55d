/* Stable time step estimate (docs/model_reference.md 13.2; Ongaro 2022 eqs. 1.105-1.108). */
#include <math.h>
#include "peri/constants.h"
#include "peri/solver.h"

double peri_node_stiffness_bound(const peri_sim *s, int32_t i) {
  const peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  /* bond-based models carry the influence function in the pair force; state-based ones
   * are bounded by the equivalent PMB micromodulus alone */
  const bool bond_based = s->model->fixed_poisson;
  const peri_material *mi = &s->materials[p->material[i]];
  double stiffness = 0.0;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    const int32_t j = b->neighbor[k];
    const double r0 = peri_bond_length(p->x, i, j);
    const double c = 0.5 * (mi->c_stable + s->materials[p->material[j]].c_stable);
    stiffness += peri_bonds_beta(b, r0) * p->volume[j] * c * (bond_based ? peri_bonds_omega(b, r0) : 1.0) / r0;
  }
  return stiffness;
}

double peri_stable_dt(const peri_sim *s) {
  const peri_particles *p = &s->p;
  double dt_bond = INFINITY;
#pragma omp parallel for schedule(static) reduction(min : dt_bond)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mi = &s->materials[p->material[i]];
    const double stiffness = peri_node_stiffness_bound(s, i);
    if (stiffness > 0.0) dt_bond = fmin(dt_bond, sqrt(2.0 * mi->density / stiffness));
  }
  double dt_cfl = INFINITY;
  for (int m = 0; m < s->n_materials; ++m) {
    const peri_material *mat = &s->materials[m];
    double M = peri_pwave_modulus(&s->geom, mat->E, mat->nu, mat->K, mat->mu);
    dt_cfl = fmin(dt_cfl, s->geom.spacing / sqrt(M / mat->density));
  }
  return fmin(dt_bond, dt_cfl);
}
