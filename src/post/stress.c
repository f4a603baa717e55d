/* Stress and strain recovery (docs/model_reference.md 10). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/coupling.h"
#include "peri/error.h"
#include "peri/model.h"
#include "peri/stress.h"
#include "peri/small_matrix.h"

int peri_stress(peri_sim *s, double *sigma) { return peri_stress_of(s, sigma, NULL); }

int peri_stress_of(peri_sim *s, double *sigma, const uint8_t *wanted) {
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  if (!s->mat.model->pair_force) {
    peri_error("stress recovery is not available for the %s model", s->mat.model->name);
    return PERI_ERR_RUN;
  }
  /* the forces refresh the dilatation (LPS) at the current displacement */
  const bool breaking = s->solver.breaking;
  s->solver.breaking = false;
  s->mat.model->force(s);
  s->solver.breaking = breaking;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double sg[9] = {0};
    const int64_t end = !wanted || wanted[i] ? b->offset[i + 1] : b->offset[i];
    for (int64_t k = b->offset[i]; k < end; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double xi[3], dy[3], r2 = 0.0;
      for (int d = 0; d < 3; ++d) {
        xi[d] = p->x[3 * j + d] - p->x[3 * i + d];
        dy[d] = xi[d] + p->u[3 * j + d] - p->u[3 * i + d];
        r2 += dy[d] * dy[d];
      }
      if (!(r2 > 0.0)) continue;
      const double r = sqrt(r2);
      const double half = s->mat.model->own_force ? s->mat.model->own_force(s, i, k, r) /* t_ij */
                                                  : 0.5 * s->mat.model->pair_force(s, i, k, r);
      const double scale = half * peri_bonds_beta(b, peri_bond_length(p->x, i, j)) * p->volume[j] / r;
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) sg[3 * a + c] += scale * dy[a] * xi[c];
    }
    double *out = &sigma[9 * (size_t)i];
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) out[3 * a + c] = 0.5 * (sg[3 * a + c] + sg[3 * c + a]);
  }
  /* PD-FEM coupling: the pass above evaluated the PD model's forces on every node; the
   * coupled model's forces are what the history and the reactions read (docs/coupling.md) */
  if (s->coupling) peri_coupling_force(s);
  return PERI_OK;
}

bool peri_displacement_gradient(const peri_sim *s, int32_t i, double H[9]) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int dim = s->disc.geom.dim;
  double A[9] = {0}, K[9] = {0}, Kinv[9];
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    const int32_t j = b->neighbor[k];
    double xi[3], y[3];
    for (int d = 0; d < 3; ++d) {
      xi[d] = p->x[3 * j + d] - p->x[3 * i + d];
      y[d] = xi[d] + p->u[3 * j + d] - p->u[3 * i + d];
    }
    const double r0 = peri_bond_length(p->x, i, j);
    const double w = peri_bonds_omega(b, r0) * peri_bonds_beta(b, r0) * p->volume[j];
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) {
        A[3 * a + c] += w * y[a] * xi[c];
        K[3 * a + c] += w * xi[a] * xi[c];
      }
  }
  memset(H, 0, 9 * sizeof(double));
  if (!peri_invert_block3(K, dim, 1e-300, Kinv)) return false;
  for (int a = 0; a < dim; ++a)
    for (int c = 0; c < dim; ++c) {
      for (int m = 0; m < dim; ++m) H[3 * a + c] += A[3 * a + m] * Kinv[3 * m + c];
      if (a == c) H[3 * a + c] -= 1.0;
    }
  return true;
}

void peri_strain(const peri_sim *s, double *eps) {
  const peri_particles *p = &s->disc.p;
  const int dim = s->disc.geom.dim;
  const bool plane_stress = dim == 2 && s->disc.geom.plane == PERI_PLANE_STRESS;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double H[9];
    double *e = &eps[9 * (size_t)i];
    memset(e, 0, 9 * sizeof(double));
    if (!peri_displacement_gradient(s, i, H)) continue;
    for (int a = 0; a < dim; ++a)
      for (int c = 0; c < dim; ++c) e[3 * a + c] = 0.5 * (H[3 * a + c] + H[3 * c + a]);
    if (plane_stress) {
      const double nu = s->mat.materials[p->material[i]].nu;
      e[8] = -nu / (1.0 - nu) * (e[0] + e[4]);
    }
  }
}

static double out_of_plane(const peri_sim *s, const double sig[9], double nu) {
  if (s->disc.geom.dim == 2 && s->disc.geom.plane == PERI_PLANE_STRAIN) return nu * (sig[0] + sig[4]);
  if (s->disc.geom.dim == 3) return sig[8];
  return 0.0;
}

double peri_von_mises(const peri_sim *s, const double sig[9], double nu) {
  if (s->disc.geom.dim == 1) return fabs(sig[0]);
  const double s11 = sig[0], s22 = sig[4], s33 = out_of_plane(s, sig, nu);
  const double s12 = sig[1], s23 = s->disc.geom.dim == 3 ? sig[5] : 0.0, s13 = s->disc.geom.dim == 3 ? sig[2] : 0.0;
  const double j2 = 0.5 * ((s11 - s22) * (s11 - s22) + (s22 - s33) * (s22 - s33) + (s33 - s11) * (s33 - s11)) +
                    3.0 * (s12 * s12 + s23 * s23 + s13 * s13);
  return sqrt(fmax(j2, 0.0));
}

static void sort3(double v[3]) {
  for (int a = 0; a < 2; ++a)
    for (int c = 0; c < 2 - a; ++c)
      if (v[c] < v[c + 1]) {
        double t = v[c];
        v[c] = v[c + 1];
        v[c + 1] = t;
      }
}

void peri_principal_stresses(const peri_sim *s, const double sig[9], double nu, double out[3]) {
  const int dim = s->disc.geom.dim;
  if (dim == 1) {
    out[0] = sig[0], out[1] = out[2] = 0.0;
    sort3(out);
    return;
  }
  if (dim == 2) {
    const double c = 0.5 * (sig[0] + sig[4]), r = hypot(0.5 * (sig[0] - sig[4]), sig[1]);
    out[0] = c + r, out[1] = c - r, out[2] = out_of_plane(s, sig, nu);
    sort3(out);
    return;
  }
  /* symmetric 3x3: trigonometric solution of the characteristic cubic */
  const double p1 = sig[1] * sig[1] + sig[2] * sig[2] + sig[5] * sig[5];
  const double q = (sig[0] + sig[4] + sig[8]) / 3.0;
  if (p1 == 0.0) {
    out[0] = sig[0], out[1] = sig[4], out[2] = sig[8];
    sort3(out);
    return;
  }
  const double p2 = (sig[0] - q) * (sig[0] - q) + (sig[4] - q) * (sig[4] - q) + (sig[8] - q) * (sig[8] - q) + 2.0 * p1;
  const double pp = sqrt(p2 / 6.0);
  double B[9];
  for (int k = 0; k < 9; ++k) B[k] = (sig[k] - (k % 4 == 0 ? q : 0.0)) / pp;
  const double detB = B[0] * (B[4] * B[8] - B[5] * B[7]) - B[1] * (B[3] * B[8] - B[5] * B[6]) +
                      B[2] * (B[3] * B[7] - B[4] * B[6]);
  const double rr = fmax(-1.0, fmin(1.0, 0.5 * detB));
  const double phi = acos(rr) / 3.0;
  out[0] = q + 2.0 * pp * cos(phi);
  out[2] = q + 2.0 * pp * cos(phi + 2.0 * M_PI / 3.0);
  out[1] = 3.0 * q - out[0] - out[2];
  sort3(out);
}

void peri_stress_measures(const peri_sim *s, const double *sigma, double *von_mises, double *principal) {
  const peri_particles *p = &s->disc.p;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double nu = s->mat.materials[p->material[i]].nu;
    const double *sg = &sigma[9 * (size_t)i];
    if (von_mises) von_mises[i] = peri_von_mises(s, sg, nu);
    if (principal) peri_principal_stresses(s, sg, nu, &principal[3 * (size_t)i]);
  }
}
