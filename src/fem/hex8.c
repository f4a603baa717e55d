/* The 8-node isoparametric hexahedron, trilinear shape functions, 2x2x2 Gauss points (exact
 * for a parallelepiped). Isotropic D with Lame constants lambda = E nu/((1+nu)(1-2nu)),
 * mu = E/(2(1+nu)); strains in the order xx, yy, zz, yz, xz, xy (engineering shear). */
#include <math.h>
#include <string.h>
#include "peri/error.h"
#include "peri/fem.h"

int peri_fem_hex8_stiffness(const double xyz[24], double E, double nu, double K[576]) {
  static const double xa[8] = {-1, 1, 1, -1, -1, 1, 1, -1}, ya[8] = {-1, -1, 1, 1, -1, -1, 1, 1},
                      za[8] = {-1, -1, -1, -1, 1, 1, 1, 1};
  const double g = 1.0 / sqrt(3.0);
  const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), mu = E / (2.0 * (1.0 + nu));
  memset(K, 0, 576 * sizeof(double));
  for (int q = 0; q < 8; ++q) {
    const double r[3] = {xa[q] * g, ya[q] * g, za[q] * g};
    double dN[8][3], J[3][3] = {{0}};
    for (int a = 0; a < 8; ++a) {
      const double fx = 1.0 + xa[a] * r[0], fy = 1.0 + ya[a] * r[1], fz = 1.0 + za[a] * r[2];
      dN[a][0] = 0.125 * xa[a] * fy * fz;
      dN[a][1] = 0.125 * ya[a] * fx * fz;
      dN[a][2] = 0.125 * za[a] * fx * fy;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) J[i][j] += dN[a][i] * xyz[3 * a + j]; /* J_ij = dx_j / dr_i */
    }
    double inv[3][3];
    inv[0][0] = J[1][1] * J[2][2] - J[1][2] * J[2][1];
    inv[0][1] = J[0][2] * J[2][1] - J[0][1] * J[2][2];
    inv[0][2] = J[0][1] * J[1][2] - J[0][2] * J[1][1];
    inv[1][0] = J[1][2] * J[2][0] - J[1][0] * J[2][2];
    inv[1][1] = J[0][0] * J[2][2] - J[0][2] * J[2][0];
    inv[1][2] = J[0][2] * J[1][0] - J[0][0] * J[1][2];
    inv[2][0] = J[1][0] * J[2][1] - J[1][1] * J[2][0];
    inv[2][1] = J[0][1] * J[2][0] - J[0][0] * J[2][1];
    inv[2][2] = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    const double det = J[0][0] * inv[0][0] + J[0][1] * inv[1][0] + J[0][2] * inv[2][0];
    if (!(det > 0.0)) return PERI_ERR_INPUT;
    /* physical gradients: dN/dx_j = sum_i (J^-1)_ji dN/dr_i */
    double G[8][3];
    for (int a = 0; a < 8; ++a)
      for (int j = 0; j < 3; ++j) G[a][j] = (inv[j][0] * dN[a][0] + inv[j][1] * dN[a][1] + inv[j][2] * dN[a][2]) / det;
    /* K_ab,ij = int (lambda dNa_i dNb_j + mu dNa_j dNb_i + mu delta_ij grad Na . grad Nb) */
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const double dot = G[a][0] * G[b][0] + G[a][1] * G[b][1] + G[a][2] * G[b][2];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            K[24 * (3 * a + i) + 3 * b + j] +=
                det * (lambda * G[a][i] * G[b][j] + mu * G[a][j] * G[b][i] + (i == j ? mu * dot : 0.0));
      }
  }
  return PERI_OK;
}
