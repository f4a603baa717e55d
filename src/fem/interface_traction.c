/* The local traction of the FEM side at a point of a straight PD-FEM interface
 * (002_b20c318388227af9.txt eq. 2.107; docs/coupling.md "Interface tractions"). The point
 * lies on a line of nodes, midway between the PD node and the FEM node that straddle the
 * interface. In 1D the traction is -(E/dx)(u_FEM - u_PD) n, eq. 2.107. In 2D and 3D it is
 * -sigma n with sigma the stress of the bilinear field of the lattice nodes around the point:
 * the normal derivative from the two straddling nodes, each tangential one by the central
 * difference of the two rows of nodes (the mean of the two elements that share the point),
 * one-sided at a body's edge. The gradient is a weighted sum of nodal displacements, summed
 * over the owned nodes in peri_sum_owned's fixed blocks, so it does not depend on threads or
 * ranks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "peri/coupling.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/fem.h"
#include "peri/sim.h"

/* The node at y within tol on every axis, or -1 (a scan: called once per traction at setup). */
static int32_t node_at(const peri_particles *p, const double y[3], double tol) {
  for (int32_t i = 0; i < p->n; ++i)
    if (fabs(p->x[3 * (size_t)i] - y[0]) <= tol && fabs(p->x[3 * (size_t)i + 1] - y[1]) <= tol &&
        fabs(p->x[3 * (size_t)i + 2] - y[2]) <= tol)
      return i;
  return -1;
}

static void describe(int dim, const double y[3], char *out, size_t n) {
  if (dim == 1) snprintf(out, n, "(%g)", y[0]);
  else if (dim == 2) snprintf(out, n, "(%g, %g)", y[0], y[1]);
  else snprintf(out, n, "(%g, %g, %g)", y[0], y[1], y[2]);
}

int peri_coupling_traction_locate(const peri_sim *s, peri_interface_traction *tr, char *why, size_t n) {
  const peri_particles *p = &s->disc.p;
  const int dim = s->disc.geom.dim, a = tr->axis;
  const double dx = s->disc.geom.spacing, tol = 1e-6 * dx;
  double side[2][3]; /* [0] the PD side's node, [1] the FEM side's */
  int32_t node[2];
  for (int k = 0; k < 2; ++k) {
    for (int d = 0; d < 3; ++d) side[k][d] = tr->at[d];
    side[k][a] += (k == 0 ? -0.5 : 0.5) * tr->sign * dx;
    node[k] = node_at(p, side[k], tol);
    if (node[k] < 0) {
      char where[96];
      describe(dim, side[k], where, sizeof where);
      snprintf(why, n, "no node at %s: 'at' must lie on a line of nodes, half a spacing (%g) from a node on each "
                       "side of the interface",
               where, 0.5 * dx);
      return PERI_ERR_INPUT;
    }
  }
  tr->material = p->material[node[1]];
  for (int d = 0; d < dim; ++d) {
    tr->reach[d][0] = tr->reach[d][1] = 0.0;
    if (d == a) continue;
    for (int k = 0; k < 2; ++k) { /* both rows must hold the tangential neighbour */
      bool both = true;
      for (int row = 0; row < 2; ++row) {
        double y[3] = {side[row][0], side[row][1], side[row][2]};
        y[d] += (k == 0 ? -1.0 : 1.0) * dx;
        both = both && node_at(p, y, tol) >= 0;
      }
      tr->reach[d][k] = both ? dx : 0.0;
    }
    if (tr->reach[d][0] == 0.0 && tr->reach[d][1] == 0.0) {
      snprintf(why, n, "the body is one node wide along %c at the point: no tangential derivative", "xyz"[d]);
      return PERI_ERR_INPUT;
    }
  }
  return PERI_OK;
}

/* The displacement gradient H[c][d] = du_c/dx_d at the point, from the stencil's nodes. */
static void stencil_gradient(const peri_sim *s, const peri_interface_traction *tr, double H[9]) {
  const peri_particles *p = &s->disc.p;
  const int dim = s->disc.geom.dim, a = tr->axis;
  const double dx = s->disc.geom.spacing, tol = 1e-6 * dx;
  double *terms = peri_calloc(9 * (size_t)(p->n_owned > 0 ? p->n_owned : 1), sizeof(double));
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double rel[3];
    for (int d = 0; d < 3; ++d) rel[d] = p->x[3 * (size_t)i + d] - tr->at[d];
    if (fabs(fabs(rel[a]) - 0.5 * dx) > tol) continue; /* not on the two rows that straddle the point */
    double w[3] = {0, 0, 0};
    for (int d = 0; d < dim; ++d) {
      bool others_zero = true; /* on the row through the point along d (along the normal for d = a) */
      for (int e = 0; e < dim; ++e)
        if (e != a && e != d && fabs(rel[e]) > tol) others_zero = false;
      if (!others_zero) continue;
      if (d == a) { /* one of the two nodes that straddle the point */
        w[d] = (rel[a] > 0.0 ? 1.0 : -1.0) / dx;
        continue;
      }
      /* the mean over the two rows of (u(+reach) - u(-reach)) / (reach- + reach+) */
      const double span = 2.0 * (tr->reach[d][0] + tr->reach[d][1]);
      if (fabs(rel[d] - tr->reach[d][1]) <= tol) w[d] += 1.0 / span;
      if (fabs(rel[d] + tr->reach[d][0]) <= tol) w[d] -= 1.0 / span;
    }
    for (int c = 0; c < 3; ++c)
      for (int d = 0; d < 3; ++d) terms[9 * (size_t)i + 3 * c + d] = p->u[3 * (size_t)i + c] * w[d];
  }
  peri_sum_owned(s, terms, 9, H);
  free(terms);
}

void peri_coupling_local_traction(const peri_sim *s, const peri_interface_traction *tr, double out[3]) {
  const peri_geometry *g = &s->disc.geom;
  const peri_material *m = &s->mat.materials[tr->material];
  double H[9], sigma[3][3] = {{0}};
  stencil_gradient(s, tr, H);
  if (g->dim == 1) {
    sigma[0][0] = m->E * H[0];
  } else if (g->dim == 2) { /* the FEM side's plane elasticity (src/fem/quad4.c) */
    double D[3][3];
    peri_fem_plane_elasticity(m->E, m->nu, g->plane, D);
    const double eps[3] = {H[0], H[4], H[1] + H[3]};
    double v[3];
    for (int r = 0; r < 3; ++r) v[r] = D[r][0] * eps[0] + D[r][1] * eps[1] + D[r][2] * eps[2];
    sigma[0][0] = v[0], sigma[1][1] = v[1], sigma[0][1] = sigma[1][0] = v[2];
  } else { /* isotropic, the Lame constants of src/fem/hex8.c */
    const double lambda = m->E * m->nu / ((1.0 + m->nu) * (1.0 - 2.0 * m->nu)), mu = m->E / (2.0 * (1.0 + m->nu));
    const double trace = H[0] + H[4] + H[8];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) sigma[r][c] = mu * (H[3 * r + c] + H[3 * c + r]) + (r == c ? lambda * trace : 0.0);
  }
  for (int r = 0; r < 3; ++r) out[r] = -tr->sign * sigma[r][tr->axis]; /* t(x0, -n) = -sigma n */
}
