/* The 3-node triangle (constant strain): K = B^T D B A h with the constant B of the linear
 * shape functions. It reproduces every linear field exactly (the patch test); the graded
 * meshes use it in their transition cells (src/fem/graded_mesh.c). */
#include "peri/error.h"
#include "peri/fem.h"

int peri_fem_tri3_stiffness(const double xy[6], double E, double nu, peri_plane plane, double h, double K[36]) {
  /* twice the signed area; shape-function gradients dN_a/dx = b_a / 2A, dN_a/dy = c_a / 2A */
  const double x1 = xy[0], y1 = xy[1], x2 = xy[2], y2 = xy[3], x3 = xy[4], y3 = xy[5];
  const double twice_area = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1);
  if (!(twice_area > 0.0)) return PERI_ERR_INPUT;
  const double b[3] = {y2 - y3, y3 - y1, y1 - y2}, c[3] = {x3 - x2, x1 - x3, x2 - x1};
  double D[3][3];
  peri_fem_plane_elasticity(E, nu, plane, D);
  double B[3][6] = {{0}};
  for (int a = 0; a < 3; ++a) {
    B[0][2 * a] = b[a] / twice_area;
    B[1][2 * a + 1] = c[a] / twice_area;
    B[2][2 * a] = c[a] / twice_area, B[2][2 * a + 1] = b[a] / twice_area;
  }
  const double scale = 0.5 * twice_area * h;
  for (int r = 0; r < 6; ++r)
    for (int q = 0; q < 6; ++q) {
      double sum = 0.0;
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) sum += B[k][r] * D[k][l] * B[l][q];
      K[6 * r + q] = sum * scale;
    }
  return PERI_OK;
}
