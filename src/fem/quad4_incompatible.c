/* The 4-node quadrilateral with incompatible modes, QM6 (Taylor, Beresford & Wilson 1976, "A
 * non-conforming element for stress analysis", IJNME 10:1211-1219): the bilinear field plus
 * the bubbles (1 - xi^2) and (1 - eta^2) per component, their derivatives taken with the
 * Jacobian at the centre and scaled by det J0 / det J so that the element passes the patch test
 * on any shape; the four extra parameters are condensed out. A square of them represents pure
 * bending exactly where the plain Q4 locks in shear (its bending stiffness is too high by a
 * factor that grows with the element's size against the beam's depth). The coarse squares of a
 * graded mesh use it (src/fem/graded_mesh.c). 2x2 Gauss points. */
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/fem.h"

int peri_fem_quad4_incompatible_stiffness(const double xy[8], double E, double nu, peri_plane plane, double h,
                                          double K[64]) {
  static const double xi_a[4] = {-1, 1, 1, -1}, eta_a[4] = {-1, -1, 1, 1};
  const double g = 1.0 / sqrt(3.0);
  double D[3][3];
  peri_fem_plane_elasticity(E, nu, plane, D);
  /* the Jacobian at the centre */
  double J0[2][2] = {{0, 0}, {0, 0}};
  for (int a = 0; a < 4; ++a)
    for (int c = 0; c < 2; ++c) J0[0][c] += 0.25 * xi_a[a] * xy[2 * a + c], J0[1][c] += 0.25 * eta_a[a] * xy[2 * a + c];
  const double det0 = J0[0][0] * J0[1][1] - J0[0][1] * J0[1][0];
  if (!(det0 > 0.0)) return PERI_ERR_INPUT;
  double Kfull[12][12];
  memset(Kfull, 0, sizeof Kfull);
  for (int q = 0; q < 4; ++q) {
    const double xi = xi_a[q] * g, eta = eta_a[q] * g;
    double dN[6][2], J[2][2] = {{0, 0}, {0, 0}};
    for (int a = 0; a < 4; ++a) {
      dN[a][0] = 0.25 * xi_a[a] * (1.0 + eta_a[a] * eta);
      dN[a][1] = 0.25 * eta_a[a] * (1.0 + xi_a[a] * xi);
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) J[r][c] += dN[a][r] * xy[2 * a + c];
    }
    const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    if (!(det > 0.0)) return PERI_ERR_INPUT;
    dN[4][0] = -2.0 * xi, dN[4][1] = 0.0; /* the bubbles */
    dN[5][0] = 0.0, dN[5][1] = -2.0 * eta;
    double B[3][12] = {{0}};
    for (int a = 0; a < 6; ++a) {
      /* the nodal functions with J, the bubbles with J0 scaled by det0 / det (Taylor) */
      const double (*Jm)[2] = a < 4 ? J : J0; /* J0^-1 det0 / det = adj(J0) / det */
      const double dx = (Jm[1][1] * dN[a][0] - Jm[0][1] * dN[a][1]) / det;
      const double dy = (-Jm[1][0] * dN[a][0] + Jm[0][0] * dN[a][1]) / det;
      B[0][2 * a] = dx;
      B[1][2 * a + 1] = dy;
      B[2][2 * a] = dy, B[2][2 * a + 1] = dx;
    }
    const double w = det * h;
    for (int r = 0; r < 12; ++r)
      for (int c = 0; c < 12; ++c) {
        double sum = 0.0;
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l) sum += B[k][r] * D[k][l] * B[l][c];
        Kfull[r][c] += w * sum;
      }
  }
  /* condense the bubbles: K = Kuu - Kua Kaa^-1 Kau */
  double Kaa[4][8]; /* [Kaa | I] reduced to [I | Kaa^-1] (Gauss-Jordan; Kaa is positive definite) */
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 8; ++c) Kaa[r][c] = c < 4 ? Kfull[8 + r][8 + c] : (double)(c - 4 == r);
  for (int k = 0; k < 4; ++k) {
    const double pivot = Kaa[k][k];
    if (!(pivot > 0.0)) return PERI_ERR_INPUT;
    for (int c = 0; c < 8; ++c) Kaa[k][c] /= pivot;
    for (int r = 0; r < 4; ++r)
      if (r != k) {
        const double f = Kaa[r][k];
        for (int c = 0; c < 8; ++c) Kaa[r][c] -= f * Kaa[k][c];
      }
  }
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c) {
      double sum = 0.0;
      for (int k = 0; k < 4; ++k)
        for (int l = 0; l < 4; ++l) sum += Kfull[r][8 + k] * Kaa[k][4 + l] * Kfull[8 + l][c];
      K[8 * r + c] = Kfull[r][c] - sum;
    }
  return PERI_OK;
}
