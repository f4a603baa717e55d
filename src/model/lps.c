/* Ordinary state-based linear peridynamic solid (LPS): Silling 2007 in 3D, Le's plane
 * stress and plane strain model in 2D (Le 2014 ch. 2), one discrete algorithm for all
 * dimensions (docs/model_reference.md 3.3):
 *   theta_i = (n_theta/m_i) sum_j w e |xi| W_ij,       e^d = e - theta_i |xi|/3
 *   P_i     = sum_j w e^d |xi| W_ij,                   alpha_i = (alpha m)/m_i
 *   t_ij    = n_theta (K_theta theta_i - alpha_i P_i/3) w |xi|/m_i + alpha_i w e^d_ij
 *   f_i     = sum_j (t_ij + t_ji) M_ij W_ij,           W_ij = chi beta V_j
 * Each end uses its own material's constants (half-bond rule, docs/model_reference.md 8). */
#include <math.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/model.h"
#include "bond_kernel.h"

static int lps_init(peri_sim *s) {
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  for (int m = 0; m < s->n_materials; ++m) {
    peri_material *mat = &s->materials[m];
    peri_lps_constants(&s->geom, mat->K, mat->mu, &mat->n_theta, &mat->K_theta, &mat->alpha_m);
    mat->c_stable = peri_stable_micromodulus(
        &s->geom, peri_pwave_modulus(&s->geom, mat->E, mat->nu, mat->K, mat->mu));
  }
  p->theta = peri_calloc(p->n, sizeof(double));
  p->pstate = peri_calloc(p->n, sizeof(double));
  p->wvol = peri_calloc(p->n, sizeof(double));
  if (s->analytic_weighted_volume) {
    double m = peri_weighted_volume_analytic(&s->geom, s->family.influence);
    for (int32_t i = 0; i < p->n; ++i) p->wvol[i] = m;
    return PERI_OK;
  }
  /* Discrete weighted volume over the reference family (not updated as bonds break). */
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double m = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
      m += b->omega[k] * b->length[k] * b->length[k] * b->beta[k] * p->volume[b->neighbor[k]];
    p->wvol[i] = m;
  }
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!(p->wvol[i] > 0.0)) {
      peri_error("node %d at (%g, %g, %g) has no bonds: the LPS model needs a family "
                 "(increase the horizon or check the geometry)",
                 i, p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]);
      return PERI_ERR_INPUT;
    }
  }
  return PERI_OK;
}

/* Pass 1: break bonds beyond their critical stretch, then dilatation theta and P. */
static long lps_dilatation(peri_sim *s) {
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const bool track_smin = s->s0_node != NULL;
  const bool breaking = s->breaking;
  const double *eth = s->thermal_strain; /* e_mech = e - alpha_T dT_i |xi| (docs/model_reference.md 9) */
  long n_broken = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : n_broken)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double we_x = 0.0, w_xx = 0.0, smin = INFINITY;
    const double eth_i = eth ? eth[i] : 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = b->length[k];
      const double e_total = peri_deformed_bond(p->x, p->u, i, j, dy) - L;
      const double s_mech = e_total / L - peri_bond_thermal_stretch(eth, i, j); /* symmetric in i, j */
      if (track_smin && s_mech < smin) smin = s_mech;
      if (breaking && s_mech > peri_bond_s0(s, i, j)) {
        b->broken[k] = 1;
        ++n_broken;
        continue;
      }
      const double e = e_total - eth_i * L;
      const double w = b->omega[k] * L * b->beta[k] * p->volume[j];
      we_x += w * e;
      w_xx += w * L;
    }
    const peri_material *mat = &s->materials[p->material[i]];
    const double theta = mat->n_theta * we_x / p->wvol[i];
    p->theta[i] = theta;
    p->pstate[i] = we_x - theta * w_xx / 3.0;
    if (track_smin) p->smin[i] = smin;
  }
  return n_broken;
}

/* Scalar force state t_ij of node i's half of the bond with extension e, length L. */
static inline double lps_half(const peri_material *mat, double theta, double P, double m,
                              double omega, double L, double e) {
  const double alpha = mat->alpha_m / m;
  return mat->n_theta * (mat->K_theta * theta - alpha * P / 3.0) * omega * L / m +
         alpha * omega * (e - theta * L / 3.0);
}

static long lps_force(peri_sim *s) {
  long n_broken = lps_dilatation(s);
  if (s->s0_node) peri_update_lammps_s0(s);
  peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const peri_material *mats = s->materials;
  const double *eth = s->thermal_strain;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double fi[3] = {0.0, 0.0, 0.0};
    const peri_material *mi = &mats[p->material[i]];
    const double eth_i = eth ? eth[i] : 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = b->length[k];
      const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
      if (r <= 0.0) continue;
      const double e = r - L;
      const double eth_j = eth ? eth[j] : 0.0;
      const double t = lps_half(mi, p->theta[i], p->pstate[i], p->wvol[i], b->omega[k], L, e - eth_i * L) +
                       lps_half(&mats[p->material[j]], p->theta[j], p->pstate[j], p->wvol[j],
                                b->omega[k], L, e - eth_j * L);
      const double scale = t * b->beta[k] * p->volume[j] / r;
      for (int d = 0; d < 3; ++d) fi[d] += scale * dy[d];
    }
    for (int d = 0; d < 3; ++d) p->f[3 * i + d] = fi[d];
  }
  return n_broken;
}

/* W_i = K_theta theta_i^2/2 + (alpha_i/2) sum_j w (e^d)^2 W_ij. */
static void lps_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  bool breaking = s->breaking;
  s->breaking = false;
  lps_dilatation(s);
  s->breaking = breaking;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->materials[p->material[i]];
    const double theta = p->theta[i];
    const double eth_i = s->thermal_strain ? s->thermal_strain[i] : 0.0;
    double sum = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = b->length[k];
      const double ed = peri_deformed_bond(p->x, p->u, i, j, dy) - L - eth_i * L - theta * L / 3.0;
      sum += b->omega[k] * ed * ed * b->beta[k] * p->volume[j];
    }
    W[i] = 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / p->wvol[i]) * sum;
  }
}

static double lps_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_particles *p = &s->p;
  const peri_bonds *b = &s->bonds;
  const int32_t j = b->neighbor[k];
  const double L = b->length[k], e = r - L;
  const double eth_i = s->thermal_strain ? s->thermal_strain[i] : 0.0;
  const double eth_j = s->thermal_strain ? s->thermal_strain[j] : 0.0;
  return lps_half(&s->materials[p->material[i]], p->theta[i], p->pstate[i], p->wvol[i], b->omega[k], L,
                  e - eth_i * L) +
         lps_half(&s->materials[p->material[j]], p->theta[j], p->pstate[j], p->wvol[j], b->omega[k], L,
                  e - eth_j * L);
}

const peri_model_ops peri_model_lps = {
    .name = "lps",
    .description = "ordinary state-based linear peridynamic solid (any Poisson ratio)",
    .fixed_poisson = 0,
    .init = lps_init,
    .force = lps_force,
    .energy = lps_energy,
    .pair_force = lps_pair_force,
};
