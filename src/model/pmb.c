/* Bond-based prototype microelastic brittle (PMB) model (docs/model_reference.md 2; Le 2014 eqs. 1.3-1.8):
 * pair force f = c omega s M, with the micromodulus c of each end (half-bond rule,
 * c_ij = (c_i + c_j)/2, docs/model_reference.md 8). */
#include <math.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/model.h"
#include "bond_kernel.h"

static int pmb_init(peri_sim *s) {
  double calibration = peri_influence_calibration(s->family.influence, s->geom.dim, s->geom.horizon);
  for (int m = 0; m < s->n_materials; ++m) {
    peri_material *mat = &s->materials[m];
    if (!mat->micromodulus_given)
      mat->micromodulus = peri_pmb_micromodulus(&s->geom, mat->E, mat->K) * calibration;
    mat->c_stable = mat->micromodulus;
  }
  return PERI_OK;
}

static long pmb_force(peri_sim *s) {
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const double *x = p->x, *u = p->u, *V = p->volume;
  const peri_material *mats = s->materials;
  const bool track_smin = s->s0_node != NULL;
  const bool breaking = s->breaking;
  const double *eth = s->thermal_strain; /* thermal strain (docs/model_reference.md 9), NULL without */
  long n_broken = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : n_broken)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double fi[3] = {0.0, 0.0, 0.0};
    double smin = INFINITY;
    const double ci = mats[p->material[i]].micromodulus;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double r = peri_deformed_bond(x, u, i, j, dy);
      const double stretch = (r - b->length[k]) / b->length[k] - peri_bond_thermal_stretch(eth, i, j);
      if (track_smin && stretch < smin) smin = stretch;
      if (breaking && stretch > peri_bond_s0(s, i, j)) {
        b->broken[k] = 1;
        ++n_broken;
        continue;
      }
      if (r <= 0.0) continue;
      const double c = 0.5 * (ci + mats[p->material[j]].micromodulus);
      const double scale = c * stretch * b->omega[k] * b->beta[k] * V[j] / r;
      for (int d = 0; d < 3; ++d) fi[d] += scale * dy[d];
    }
    for (int d = 0; d < 3; ++d) p->f[3 * i + d] = fi[d];
    if (track_smin) p->smin[i] = smin;
  }
  if (track_smin) peri_update_lammps_s0(s);
  return n_broken;
}

/* W_i = 1/2 sum_j w_ij beta V_j with the micropotential w = c omega s^2 |xi| / 2. */
static void pmb_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double sum = 0.0;
    const double ci = s->materials[p->material[i]].micromodulus;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double stretch = (r - b->length[k]) / b->length[k] - peri_bond_thermal_stretch(s->thermal_strain, i, j);
      const double c = 0.5 * (ci + s->materials[p->material[j]].micromodulus);
      sum += 0.5 * c * b->omega[k] * stretch * stretch * b->length[k] * b->beta[k] * p->volume[j];
    }
    W[i] = 0.5 * sum;
  }
}

static double pmb_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const int32_t j = b->neighbor[k];
  const double stretch = (r - b->length[k]) / b->length[k] - peri_bond_thermal_stretch(s->thermal_strain, i, j);
  const double c = 0.5 * (s->materials[p->material[i]].micromodulus + s->materials[p->material[j]].micromodulus);
  return c * stretch * b->omega[k];
}

const peri_model_ops peri_model_pmb = {
    .name = "pmb",
    .description = "bond-based PMB (Poisson ratio fixed: 1/4 in 1D, 3D and plane strain, 1/3 in plane stress)",
    .fixed_poisson = 1,
    .init = pmb_init,
    .force = pmb_force,
    .energy = pmb_energy,
    .pair_force = pmb_pair_force,
};
