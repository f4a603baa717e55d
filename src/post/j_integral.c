/* The J-integral of a crack tip (docs/plasticity.md section 6) by the equivalent domain
 * integral (Shih, Moran & Nakamura, Eng. Fract. Mech. 25 (1986) 255; Li, Shih & Needleman
 * 1985): in the crack-tip frame (x1 along the crack, x2 across it)
 *
 *   J = (1/h) sum_i V_i [ sigma_ab du_a/dx1 dq/dx_b - W dq/dx1 ]_i
 *
 * with q = 1 inside the ring's inner square and 0 outside its outer square, linear between
 * (the product of the two axes' ramps), h the thickness, dq/dx averaged over each node's cell. The crack faces are traction-free,
 * so the ring may cross them. sigma is the PD stress (model reference section 10), du/dx the
 * nonlocal displacement gradient over the intact bonds, and W the work density: the stored
 * energy of the model plus, for sublayer plasticity, the work the sublayers dissipated
 * (deformation-theory J, as the J-R curves of ductile fracture use). Only the nodes of the
 * ring add to J: the crack tip region, where the discrete fields are least accurate, has
 * dq = 0. */
#include <math.h>
#include <stdlib.h>
#include "peri/comm.h"
#include "peri/damage_index.h"
#include "peri/decompose.h"
#include "peri/discretize.h"
#include "peri/error.h"
#include "peri/j_integral.h"
#include "peri/plasticity.h"
#include "peri/stress.h"

/* The ring's ramp along one axis, 1 for |t| <= a, 0 for |t| >= b, linear between, and its
 * integral from 0 (odd in t). */
static double ramp(double a, double b, double t) {
  const double r = fabs(t);
  return r <= a ? 1.0 : r >= b ? 0.0 : (b - r) / (b - a);
}
static double ramp_integral(double a, double b, double t) {
  const double r = fmin(fabs(t), b);
  const double v = r <= a ? r : a + 0.5 * ((b - a) * (b - a) - (b - r) * (b - r)) / (b - a);
  return copysign(v, t);
}

/* The gradient of q = ramp(x1) ramp(x2) of the ring (inner half-width a, outer b) averaged
 * over the node's cell [x1 -+ h] x [x2 -+ h] in crack-tip coordinates: exact for any position
 * of the ring's edges between the nodes, so the sum over the nodes integrates dq exactly
 * (a ring whose edges cut cells otherwise weighs those cells wrongly). */
static void ring_gradient(double a, double b, double h, double x1, double x2, double grad[2]) {
  const double d1 = (ramp(a, b, x1 + h) - ramp(a, b, x1 - h)) / (2.0 * h);
  const double d2 = (ramp(a, b, x2 + h) - ramp(a, b, x2 - h)) / (2.0 * h);
  const double m1 = (ramp_integral(a, b, x1 + h) - ramp_integral(a, b, x1 - h)) / (2.0 * h);
  const double m2 = (ramp_integral(a, b, x2 + h) - ramp_integral(a, b, x2 - h)) / (2.0 * h);
  grad[0] = d1 * m2;
  grad[1] = m1 * d2;
}

/* Node i in the crack-tip frame (e1 along the crack, e2 across it, in the plane): its
 * coordinates x1, x2 from the tip and half its cell's width h. */
static void node_frame(const peri_j_integral *jc, const peri_particles *p, int32_t i, const double e1[2],
                       const double e2[2], double *x1, double *x2, double *h) {
  const double dx = p->x[3 * i] - jc->tip[0], dy = p->x[3 * i + 1] - jc->tip[1];
  *x1 = dx * e1[0] + dy * e1[1], *x2 = dx * e2[0] + dy * e2[1];
  *h = 0.5 * peri_grid_node_spacing(p->volume[i], 2, jc->thickness, 1.0);
}

int peri_j_integral_values(peri_sim *s, const peri_j_integral *jc, double *J, double *crack_extension) {
  const peri_particles *p = &s->disc.p;
  const int32_t n = p->n_owned;
  const size_t nn = (size_t)(n > 0 ? n : 1);
  double *sigma = peri_malloc(9 * sizeof(double) * nn), *W = peri_calloc(nn, sizeof(double));
  double *dissipated = s->state.plastic_stretch ? peri_calloc(nn, sizeof(double)) : NULL;
  double *phi = peri_malloc(sizeof(double) * nn);
  const int nc = jc->n_contours;
  double *terms = peri_calloc(nn * (size_t)nc, sizeof(double));
  /* the nodes of the rings (dq != 0 for a contour): only their stress and dissipated work are read */
  const double e1[2] = {jc->direction[0], jc->direction[1]}, e2[2] = {-e1[1], e1[0]};
  uint8_t *in_ring = peri_calloc(nn, 1);
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < n; ++i) {
    double x1, x2, h;
    node_frame(jc, p, i, e1, e2, &x1, &x2, &h);
    for (int c = 0; c < nc && !in_ring[i]; ++c) {
      double g[2];
      ring_gradient(jc->inner[c], jc->outer[c], h, x1, x2, g);
      in_ring[i] = g[0] != 0.0 || g[1] != 0.0;
    }
  }
  int rc = peri_stress_of(s, sigma, in_ring); /* evaluates the forces (LPS: the dilatation) first */
  if (rc == PERI_OK) {
    s->mat.model->energy(s, W);
    if (dissipated) peri_plastic_dissipation(s, dissipated, in_ring);
    peri_damage_index(s, phi);
  }
  double ahead = 0.0;
#pragma omp parallel for schedule(dynamic, 256) reduction(max : ahead)
  for (int32_t i = 0; i < (rc == PERI_OK ? n : 0); ++i) {
    double x1, x2, h;
    node_frame(jc, p, i, e1, e2, &x1, &x2, &h);
    if (phi[i] >= jc->damage_threshold && fabs(x2) <= jc->band && x1 > ahead) ahead = x1;
    if (!in_ring[i]) continue;
    double H[9], du1[2] = {0.0, 0.0};
    bool gradient = false;
    for (int c = 0; c < nc; ++c) {
      double g[2];
      ring_gradient(jc->inner[c], jc->outer[c], h, x1, x2, g);
      if (g[0] == 0.0 && g[1] == 0.0) continue;
      if (!gradient) { /* du/dx1 = H e1 */
        gradient = true;
        if (peri_displacement_gradient(s, i, H))
          for (int a = 0; a < 2; ++a) du1[a] = H[3 * a] * e1[0] + H[3 * a + 1] * e1[1];
      }
      /* grad q in the global frame */
      const double gq[2] = {g[0] * e1[0] + g[1] * e2[0], g[0] * e1[1] + g[1] * e2[1]};
      const double *sg = &sigma[9 * (size_t)i];
      double flux = 0.0;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) flux += sg[3 * a + b] * du1[a] * gq[b];
      const double work = W[i] + (dissipated ? dissipated[i] : 0.0);
      terms[(size_t)i * (size_t)nc + (size_t)c] = p->volume[i] * (flux - work * g[0]) / jc->thickness;
    }
  }
  rc = peri_comm_max_int(rc);
  if (rc == PERI_OK) {
    /* at most 9 components a sum (peri_sum_owned) */
    double *column = peri_malloc(sizeof(double) * nn);
    for (int c = 0; c < nc; ++c) {
      for (int32_t i = 0; i < n; ++i) column[i] = terms[(size_t)i * (size_t)nc + (size_t)c];
      peri_sum_owned(s, column, 1, &J[c]);
    }
    free(column);
    *crack_extension = peri_comm_max(ahead);
  }
  free(sigma), free(W), free(dissipated), free(phi), free(terms), free(in_ring);
  return rc;
}
