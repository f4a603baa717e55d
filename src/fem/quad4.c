/* The 4-node isoparametric quadrilateral, bilinear shape functions, 2x2 Gauss points (exact
 * for a parallelogram: the integrand B^T D B det J is then a polynomial of degree 2 per
 * direction). Plane stress: D = E/(1-nu^2) [[1,nu,0],[nu,1,0],[0,0,(1-nu)/2]]; plane strain:
 * D = E/((1+nu)(1-2nu)) [[1-nu,nu,0],[nu,1-nu,0],[0,0,(1-2nu)/2]] (engineering shear strain). */
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/fem.h"

void peri_fem_plane_elasticity(double E, double nu, peri_plane plane, double D[3][3]) {
  memset(D, 0, 9 * sizeof(double));
  if (plane == PERI_PLANE_STRAIN) {
    const double f = E / ((1.0 + nu) * (1.0 - 2.0 * nu));
    D[0][0] = D[1][1] = f * (1.0 - nu);
    D[0][1] = D[1][0] = f * nu;
    D[2][2] = f * (1.0 - 2.0 * nu) / 2.0;
  } else {
    const double f = E / (1.0 - nu * nu);
    D[0][0] = D[1][1] = f;
    D[0][1] = D[1][0] = f * nu;
    D[2][2] = f * (1.0 - nu) / 2.0;
  }
}

int peri_fem_quad4_stiffness(const double xy[8], double E, double nu, peri_plane plane, double h, double K[64]) {
  static const double xi_a[4] = {-1, 1, 1, -1}, eta_a[4] = {-1, -1, 1, 1};
  const double g = 1.0 / sqrt(3.0); /* Gauss points +-1/sqrt(3), weights 1 */
  double D[3][3];
  peri_fem_plane_elasticity(E, nu, plane, D);
  memset(K, 0, 64 * sizeof(double));
  for (int q = 0; q < 4; ++q) {
    const double xi = xi_a[q] * g, eta = eta_a[q] * g;
    double dN[4][2], J[2][2] = {{0, 0}, {0, 0}};
    for (int a = 0; a < 4; ++a) {
      dN[a][0] = 0.25 * xi_a[a] * (1.0 + eta_a[a] * eta);
      dN[a][1] = 0.25 * eta_a[a] * (1.0 + xi_a[a] * xi);
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) J[r][c] += dN[a][r] * xy[2 * a + c]; /* J_rc = dx_c / dxi_r */
    }
    const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    if (!(det > 0.0)) return PERI_ERR_INPUT;
    double B[3][8] = {{0}};
    for (int a = 0; a < 4; ++a) {
      const double dx = (J[1][1] * dN[a][0] - J[0][1] * dN[a][1]) / det;
      const double dy = (-J[1][0] * dN[a][0] + J[0][0] * dN[a][1]) / det;
      B[0][2 * a] = dx;
      B[1][2 * a + 1] = dy;
      B[2][2 * a] = dy, B[2][2 * a + 1] = dx;
    }
    double DB[3][8];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 8; ++c) DB[r][c] = D[r][0] * B[0][c] + D[r][1] * B[1][c] + D[r][2] * B[2][c];
    const double w = det * h;
    for (int r = 0; r < 8; ++r)
      for (int c = 0; c < 8; ++c) K[8 * r + c] += w * (B[0][r] * DB[0][c] + B[1][r] * DB[1][c] + B[2][r] * DB[2][c]);
  }
  return PERI_OK;
}
