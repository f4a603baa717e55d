/* Surface correction (docs/models.md 4.1): bond factors computed once in the reference
 * configuration, and the bond loops of the corrected models.
 *
 * Energy ratio (Madenci and Oterkus 2014, ch. 4; MODELS.md section 6 item 4): under a uniaxial
 * strain of unit size along each axis k, u_k = x_k, every node's PD energy density is compared
 * with the classical one, W_cl = M/2 (M the P-wave, i.e. uniaxial-strain, modulus), giving
 * g_i^(k); a bond gets G_ij = [sum_k (n_k / gbar_k)^2]^(-1/2), gbar_k = (g_i^(k) + g_j^(k))/2,
 * n the unit reference bond vector. LPS first does the same for the dilatation, d_i^(k) =
 * theta_cl / theta_i^(k) with theta_cl = n_theta/dim, giving D_ij; then g_i^(k) corrects the
 * deviatoric energy only: g = (W_cl - K_theta theta_i^2/2) / W_dev,i, theta_i with D.
 * Volume ratio (PMB): g_i = V_H / sum_j beta V_j (V_H the full horizon's volume) and
 * G_ij = (g_i + g_j)/2.
 * The strains are small, so the bond values are the linear ones: stretch n_k^2, extension
 * n_k^2 |xi|. The factors are frozen: bonds that break do not change them.
 *
 * The corrected loops are plain loops over the families (not the node blocks of pmb.c and
 * lps.c, whose per-bond work stays free of the factors): the break test first, as in the
 * default loops (the same stretch from both ends, so symmetric), then the force. The LPS
 * is the peer force state (docs/models.md 3.5) with D on its dilatation term and G on its
 * deviatoric term, and the LPS energy with the same factors:
 *   theta_i = (n/m_i) sum_j D_ij omega e_ij |xi| w_ij,      w = beta V_j over intact bonds
 *   t_ij    = n K'_i theta_i D_ij omega |xi|/m_i + G_ij alpha_i omega (e_ij - theta_i |xi|/3),
 *   K'      = K_theta - (alpha m)(1/n - 1/3)/3,
 *   W_i     = K_theta theta_i^2/2 + (alpha_i/2) sum_j G_ij omega (e^d_ij)^2 w_ij.
 * The force is the gradient of W only where the factors are 1 (docs/models.md 4.1 says why
 * this form and not a variational one). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "bond_kernel.h"
#include "surface_correction.h"

/* The volume of a full horizon: 4/3 pi d^3, pi d^2 h, 2 d A. */
static double horizon_volume(const peri_geometry *g) {
  const double d = g->horizon;
  if (g->dim == 3) return 4.0 / 3.0 * M_PI * d * d * d;
  if (g->dim == 2) return M_PI * d * d * g->thickness;
  return 2.0 * d * g->cross_section;
}

/* Bond factor from the per-direction node factors f (3 per node) of i and j. */
static double bond_factor(const double *f, int32_t i, int32_t j, const double n[3], int dim) {
  double sum = 0.0;
  for (int k = 0; k < dim && k < 3; ++k) {
    const double mean = 0.5 * (f[3 * (size_t)i + k] + f[3 * (size_t)j + k]);
    sum += (n[k] / mean) * (n[k] / mean);
  }
  return sum > 0.0 ? 1.0 / sqrt(sum) : 1.0;
}

int peri_surface_factors(peri_sim *s, bool lps) {
  if (s->disc.surface_correction == PERI_SURFACE_NONE) return PERI_OK;
  peri_particles *p = &s->disc.p;
  peri_bonds *b = &s->disc.bonds;
  const int dim = s->disc.geom.dim;
  if (s->solver.kind == PERI_SOLVER_IMPLICIT) {
    peri_error("discretization.surface_correction: the implicit solver has no tangent of the corrected models; "
               "use adr, nlcg or dynamic_relaxation");
    return PERI_ERR_INPUT;
  }
  if (lps && s->disc.surface_correction == PERI_SURFACE_VOLUME) {
    peri_error("discretization.surface_correction: volume is for pmb; the lps model's discrete weighted volume is "
               "already a family-volume normalization (use energy)");
    return PERI_ERR_INPUT;
  }
  if (s->disc.surface_correction == PERI_SURFACE_POSITION_AWARE) return peri_position_aware_factors(s, lps);
  if (lps) peri_sim_exchange(s, p->wvol, 1); /* the corrected pair force reads m_j */
  const size_t n = (size_t)p->n;
  double *g = peri_calloc(3 * n + 1, sizeof(double)), *d = peri_calloc(3 * n + 1, sizeof(double));
  for (size_t a = 0; a < 3 * n; ++a) g[a] = d[a] = 1.0;
  b->surface_G = peri_malloc(sizeof(double) * (size_t)(b->n_bonds > 0 ? b->n_bonds : 1));
  if (lps) b->surface_D = peri_malloc(sizeof(double) * (size_t)(b->n_bonds > 0 ? b->n_bonds : 1));
  const double VH = horizon_volume(&s->disc.geom);
  /* node factors: the volume ratio, or the dilatation ratios (LPS) */
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    double vol = 0.0, th[3] = {0.0, 0.0, 0.0}, w_pmb[3] = {0.0, 0.0, 0.0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      double xi[3] = {0.0, 0.0, 0.0};
      const double L = peri_bond_xi(p->x, i, j, xi), bV = peri_bonds_beta(b, L) * p->volume[j];
      const double omega = peri_bonds_omega(b, L);
      vol += bV;
      for (int c = 0; c < dim; ++c) {
        const double nk2 = xi[c] * xi[c] / (L * L);
        th[c] += omega * nk2 * L * L * bV;
        const double cij = 0.5 * (mat->micromodulus + s->mat.materials[p->material[j]].micromodulus);
        w_pmb[c] += 0.25 * cij * omega * nk2 * nk2 * L * bV; /* W = 1/2 sum 1/2 c omega s^2 |xi| beta V */
      }
    }
    if (s->disc.surface_correction == PERI_SURFACE_VOLUME) {
      for (int c = 0; c < 3; ++c) g[3 * (size_t)i + c] = vol > 0.0 ? VH / vol : 1.0;
    } else if (!lps) {
      const double W_cl = 0.5 * peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu);
      for (int c = 0; c < dim; ++c) g[3 * (size_t)i + c] = w_pmb[c] > 0.0 ? W_cl / w_pmb[c] : 1.0;
    } else if (mat->n_theta > 0.0) {
      for (int c = 0; c < dim; ++c) {
        const double theta = mat->n_theta * th[c] / p->wvol[i];
        d[3 * (size_t)i + c] = theta > 0.0 ? (mat->n_theta / dim) / theta : 1.0;
      }
    }
  }
  if (lps) { /* D, then the deviatoric ratios with the corrected dilatation */
    peri_sim_exchange(s, d, 3);
#pragma omp parallel for schedule(dynamic, 256)
    for (int32_t i = 0; i < p->n_owned; ++i)
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
        const int32_t j = b->neighbor[k];
        double xi[3] = {0.0, 0.0, 0.0};
        const double L = peri_bond_xi(p->x, i, j, xi);
        for (int c = 0; c < 3; ++c) xi[c] /= L;
        b->surface_D[k] = bond_factor(d, i, j, xi, dim);
      }
#pragma omp parallel for schedule(dynamic, 256)
    for (int32_t i = 0; i < p->n_owned; ++i) {
      const peri_material *mat = &s->mat.materials[p->material[i]];
      const double m = p->wvol[i], alpha = mat->alpha_m / m;
      const double W_cl = 0.5 * peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu);
      for (int c = 0; c < dim; ++c) {
        double sum = 0.0;
        for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
          const int32_t j = b->neighbor[k];
          double xi[3] = {0.0, 0.0, 0.0};
          const double L = peri_bond_xi(p->x, i, j, xi);
          sum += b->surface_D[k] * peri_bonds_omega(b, L) * xi[c] * xi[c] * peri_bonds_beta(b, L) * p->volume[j];
        }
        const double theta = mat->n_theta * sum / m, W_dil = 0.5 * mat->K_theta * theta * theta;
        double W_dev = 0.0; /* (alpha/2) sum omega (e^d)^2 beta V, e = n_k^2 |xi| */
        for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
          const int32_t j = b->neighbor[k];
          double xi[3] = {0.0, 0.0, 0.0};
          const double L = peri_bond_xi(p->x, i, j, xi);
          const double ed = xi[c] * xi[c] / L - theta * L / 3.0;
          W_dev += 0.5 * alpha * peri_bonds_omega(b, L) * ed * ed * peri_bonds_beta(b, L) * p->volume[j];
        }
        g[3 * (size_t)i + c] = W_dev > 0.0 && W_cl > W_dil ? (W_cl - W_dil) / W_dev : 1.0;
      }
    }
  }
  peri_sim_exchange(s, g, 3);
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      double xi[3] = {0.0, 0.0, 0.0};
      const double L = peri_bond_xi(p->x, i, j, xi);
      for (int c = 0; c < 3; ++c) xi[c] /= L;
      b->surface_G[k] = s->disc.surface_correction == PERI_SURFACE_VOLUME
                            ? 0.5 * (g[3 * (size_t)i] + g[3 * (size_t)j])
                            : bond_factor(g, i, j, xi, dim);
    }
  free(g);
  free(d);
  return PERI_OK;
}

/* PMB: f_i = sum_j G_ij c_ij omega s beta V_j (y_j - y_i)/r; W_i = 1/2 sum 1/2 G c omega s^2 |xi| beta V. */
static void pmb_loop(peri_sim *s, double *W) {
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double f[3] = {0.0, 0.0, 0.0}, energy = 0.0;
    const double ci = s->mat.materials[p->material[i]].micromodulus;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double stretch = (r - L) / L - peri_bond_thermal_stretch(s->state.thermal_strain, i, j);
      const double c_bulk = 0.5 * (ci + s->mat.materials[p->material[j]].micromodulus), c = c_bulk * b->surface_G[k];
      const double bV = peri_bonds_beta(b, L) * p->volume[j], omega = peri_bonds_omega(b, L);
      const double own = b->surface_D ? b->surface_D[k] : b->surface_G[k]; /* position_aware: i's own factor */
      energy += 0.25 * c_bulk * own * omega * stretch * stretch * L * bV;
      if (r > 0.0)
        for (int d = 0; d < 3; ++d) f[d] += c * omega * stretch * bV * dy[d] / r;
    }
    if (W) W[i] = energy;
    else
      for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = f[d];
  }
}

long peri_corrected_pmb_force(peri_sim *s, bool update_s0) {
  const long broken = peri_corrected_break(s, update_s0);
  pmb_loop(s, NULL);
  return broken;
}

void peri_corrected_pmb_energy(peri_sim *s, double *W) { pmb_loop(s, W); }

double peri_corrected_pmb_pair(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int32_t j = b->neighbor[k];
  const double L = peri_bond_length(p->x, i, j);
  const double stretch = (r - L) / L - peri_bond_thermal_stretch(s->state.thermal_strain, i, j);
  const double c = 0.5 * (s->mat.materials[p->material[i]].micromodulus + s->mat.materials[p->material[j]].micromodulus);
  return c * b->surface_G[k] * stretch * peri_bonds_omega(b, L);
}

/* LPS: the dilatation of every owned node (with D), exchanged to the ghosts. */
static void lps_dilatation_corrected(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    double sum = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double e = r - L - (eth ? eth[i] : 0.0) * L;
      sum += b->surface_D[k] * peri_bonds_omega(b, L) * e * L * peri_bonds_beta(b, L) * p->volume[j];
    }
    p->theta[i] = mat->n_theta * sum / p->wvol[i];
    p->pstate[i] = 0.0;
  }
  peri_sim_exchange(s, p->theta, 1);
}

/* Node i's half t_ij of the corrected pair force: the peer form (docs/models.md 3.5) with D on
 * its dilatation term and G on its deviatoric term,
 * n (K_theta - (alpha m)(1/n - 1/3)/3) theta D omega |xi|/m + G alpha omega (e - theta |xi|/3). */
static double lps_half(const peri_sim *s, int32_t i, int64_t k, double L, double e_total) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const peri_material *mat = &s->mat.materials[p->material[i]];
  const double m = p->wvol[i], omega = peri_bonds_omega(b, L), theta = p->theta[i];
  const double e = e_total - (s->state.thermal_strain ? s->state.thermal_strain[i] : 0.0) * L;
  const double K_peer = mat->n_theta > 0.0 ? mat->K_theta - mat->alpha_m * (1.0 / mat->n_theta - 1.0 / 3.0) / 3.0 : 0.0;
  return mat->n_theta * K_peer * theta * b->surface_D[k] * omega * L / m +
         b->surface_G[k] * (mat->alpha_m / m) * omega * (e - theta * L / 3.0);
}

double peri_corrected_lps_pair(const peri_sim *s, int32_t i, int64_t k, double r) {
  if (s->disc.bonds.surface_G_rev) return peri_position_aware_lps_pair(s, i, k, r);
  const peri_particles *p = &s->disc.p;
  const int32_t j = s->disc.bonds.neighbor[k];
  const double L = peri_bond_length(p->x, i, j);
  return lps_half(s, i, k, L, r - L) + lps_half(s, j, k, L, r - L); /* G and D are symmetric */
}

long peri_corrected_lps_force(peri_sim *s, bool update_s0) {
  if (s->disc.bonds.surface_G_rev) return peri_position_aware_lps_force(s, update_s0);
  const long broken = peri_corrected_break(s, update_s0);
  lps_dilatation_corrected(s);
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double f[3] = {0.0, 0.0, 0.0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
      if (!(r > 0.0)) continue;
      const double t = lps_half(s, i, k, L, r - L) + lps_half(s, j, k, L, r - L);
      const double bV = peri_bonds_beta(b, L) * p->volume[j];
      for (int d = 0; d < 3; ++d) f[d] += t * bV * dy[d] / r;
    }
    for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = f[d];
  }
  return broken;
}

void peri_corrected_lps_energy(peri_sim *s, double *W) {
  if (s->disc.bonds.surface_G_rev) peri_position_aware_lps_dilatation(s); /* position_aware.c */
  else lps_dilatation_corrected(s);
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double theta = p->theta[i];
    double dev = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double dy[3];
      const double L = peri_bond_length(p->x, i, j), r = peri_deformed_bond(p->x, p->u, i, j, dy);
      const double ed = r - L - (eth ? eth[i] : 0.0) * L - theta * L / 3.0;
      dev += b->surface_G[k] * peri_bonds_omega(b, L) * ed * ed * peri_bonds_beta(b, L) * p->volume[j];
    }
    W[i] = 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / p->wvol[i]) * dev;
  }
}
