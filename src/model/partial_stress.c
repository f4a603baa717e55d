/* The partial-stress force L0 = div nu0 (docs/model_reference.md 15.3, docs/variable_horizon.md).
 * nu0_i = sum_j T_i<xi_ij> (x) xi_ij V_j is the stress that node i's own force state carries;
 * under u = a + Hx with T_delta = delta^-(d+1) Z<xi/delta> it does not depend on delta
 * (Silling, Littlewood and Seleson 2013, "Partial stress field"), so its divergence passes
 * the patch test where the full peridynamic force, which reads T at both ends of a bond,
 * does not. The divergence is the least-squares gradient over the nearest neighbours: for
 * node i, grad g = A^-1 sum_j (g_j - g_i) xi_ij with A = sum_j xi_ij xi_ij^T, exact for a
 * linear g; in 1D with its two neighbours it is the central difference of the source. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/horizon_field.h"
#include "bond_kernel.h"
#include "partial_stress.h"

/* stencil radius in spacings: the 2D ring of 8, the 3D shell of 18 (faces and edges) */
#define STENCIL_RADIUS 1.5

/* Inverse of the leading dim x dim block of a (3x3 row-major); false when singular
 * (relative to the block's scale). */
static bool invert_block(const double a[9], int dim, double inv[9]) {
  memset(inv, 0, 9 * sizeof(double));
  double scale = 0.0;
  for (int k = 0; k < 9; ++k) scale = fmax(scale, fabs(a[k]));
  if (!(scale > 0.0)) return false;
  if (dim == 1) {
    inv[0] = 1.0 / a[0];
    return true;
  }
  if (dim == 2) {
    const double det = a[0] * a[4] - a[1] * a[3];
    if (!(fabs(det) > 1e-12 * scale * scale)) return false;
    inv[0] = a[4] / det, inv[1] = -a[1] / det, inv[3] = -a[3] / det, inv[4] = a[0] / det;
    return true;
  }
  const double c00 = a[4] * a[8] - a[5] * a[7], c01 = a[5] * a[6] - a[3] * a[8], c02 = a[3] * a[7] - a[4] * a[6];
  const double det = a[0] * c00 + a[1] * c01 + a[2] * c02;
  if (!(fabs(det) > 1e-12 * scale * scale * scale)) return false;
  inv[0] = c00 / det, inv[3] = c01 / det, inv[6] = c02 / det;
  inv[1] = (a[2] * a[7] - a[1] * a[8]) / det, inv[4] = (a[0] * a[8] - a[2] * a[6]) / det;
  inv[7] = (a[1] * a[6] - a[0] * a[7]) / det;
  inv[2] = (a[1] * a[5] - a[2] * a[4]) / det, inv[5] = (a[2] * a[3] - a[0] * a[5]) / det;
  inv[8] = (a[0] * a[4] - a[1] * a[3]) / det;
  return true;
}

int peri_partial_stress_prepare(peri_sim *s) {
  peri_horizon_field *h = s->disc.horizon_field;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int dim = p->dim;
  const double radius = STENCIL_RADIUS * s->disc.geom.spacing;
  free(h->stencil_offset), free(h->stencil_node), free(h->stencil_weight), free(h->needs_stress);
  h->stencil_offset = peri_calloc((size_t)p->n_owned + 1, sizeof(int64_t));
  h->needs_stress = peri_calloc((size_t)(p->n > 0 ? p->n : 1), 1);
  for (int32_t i = 0; i < p->n_owned; ++i) {
    int64_t count = 0;
    if (h->coupled[i])
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
        count += peri_bond_length(p->x, i, b->neighbor[k]) <= radius * (1 + 1e-9);
    h->stencil_offset[i + 1] = h->stencil_offset[i] + count;
  }
  const int64_t total = h->stencil_offset[p->n_owned];
  h->stencil_node = peri_malloc(sizeof(int32_t) * (size_t)(total > 0 ? total : 1));
  h->stencil_weight = peri_malloc(3 * sizeof(double) * (size_t)(total > 0 ? total : 1));
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!h->coupled[i]) continue;
    h->needs_stress[i] = 1;
    int64_t e = h->stencil_offset[i];
    double a[9] = {0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      double xi[3];
      if (peri_bond_xi(p->x, i, j, xi) > radius * (1 + 1e-9)) continue;
      h->stencil_node[e++] = j;
      h->needs_stress[j] = 1;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) a[3 * r + c] += xi[r] * xi[c];
    }
    double inv[9];
    if (!invert_block(a, dim, inv)) {
      const double *x = p->x + 3 * (size_t)i;
      peri_error("partial stress: the node at (%g, %g, %g) has too few neighbours within %g for a gradient "
                 "(%lld); keep the coupling region away from isolated nodes",
                 x[0], x[1], x[2], radius, (long long)(e - h->stencil_offset[i]));
      return PERI_ERR_INPUT;
    }
    for (int64_t t = h->stencil_offset[i]; t < e; ++t) {
      double xi[3];
      peri_bond_xi(p->x, i, h->stencil_node[t], xi);
      for (int r = 0; r < 3; ++r)
        h->stencil_weight[3 * t + r] = inv[3 * r] * xi[0] + inv[3 * r + 1] * xi[1] + inv[3 * r + 2] * xi[2];
    }
  }
  free(h->partial_stress);
  h->partial_stress = peri_calloc(9 * (size_t)(p->n > 0 ? p->n : 1), sizeof(double));
  return PERI_OK;
}

void peri_partial_stress_force(peri_sim *s) {
  peri_horizon_field *h = s->disc.horizon_field;
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  double *nu = h->partial_stress;
  /* nu0_i = sum_j t_i<xi> (y_j - y_i)/|y_j - y_i| (x) xi V_j over the intact bonds */
#pragma omp parallel for schedule(dynamic, 64)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!h->needs_stress[i]) continue;
    double sum[9] = {0};
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double xi[3], dy[3];
      peri_bond_xi(p->x, i, j, xi);
      const double r = peri_deformed_bond(p->x, p->u, i, j, dy);
      if (!(r > 0.0)) continue;
      const double g = h->state[k] * p->volume[j] / r;
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) sum[3 * a + c] += g * dy[a] * xi[c];
    }
    memcpy(nu + 9 * (size_t)i, sum, sizeof sum);
  }
  /* f_a = sum_b d nu_ab / d x_b */
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!h->coupled[i]) continue;
    double f[3] = {0, 0, 0};
    const double *nu_i = nu + 9 * (size_t)i;
    for (int64_t t = h->stencil_offset[i]; t < h->stencil_offset[i + 1]; ++t) {
      const double *nu_j = nu + 9 * (size_t)h->stencil_node[t], *w = h->stencil_weight + 3 * t;
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) f[a] += (nu_j[3 * a + c] - nu_i[3 * a + c]) * w[c];
    }
    for (int a = 0; a < 3; ++a) p->f[3 * (size_t)i + a] = f[a];
  }
}
