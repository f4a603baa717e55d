/* Small dense matrices: the 1x1 to 3x3 inverses of the shape tensors of stress recovery and
 * of the partial-stress gradient. */
#include "peri/small_matrix.h"
#include <math.h>
#include <string.h>

bool peri_invert_block3(const double a[9], int dim, double min_abs_det, double inv[9]) {
  memset(inv, 0, 9 * sizeof(double));
  if (dim == 1) {
    if (!(fabs(a[0]) > min_abs_det)) return false;
    inv[0] = 1.0 / a[0];
    return true;
  }
  if (dim == 2) {
    const double det = a[0] * a[4] - a[1] * a[3];
    if (!(fabs(det) > min_abs_det)) return false;
    inv[0] = a[4] / det, inv[1] = -a[1] / det, inv[3] = -a[3] / det, inv[4] = a[0] / det;
    return true;
  }
  const double c00 = a[4] * a[8] - a[5] * a[7], c01 = a[5] * a[6] - a[3] * a[8], c02 = a[3] * a[7] - a[4] * a[6];
  const double det = a[0] * c00 + a[1] * c01 + a[2] * c02;
  if (!(fabs(det) > min_abs_det)) {
    memset(inv, 0, 9 * sizeof(double));
    return false;
  }
  inv[0] = c00 / det, inv[3] = c01 / det, inv[6] = c02 / det;
  inv[1] = (a[2] * a[7] - a[1] * a[8]) / det, inv[4] = (a[0] * a[8] - a[2] * a[6]) / det;
  inv[7] = (a[1] * a[6] - a[0] * a[7]) / det;
  inv[2] = (a[1] * a[5] - a[2] * a[4]) / det, inv[5] = (a[2] * a[3] - a[0] * a[5]) / det;
  inv[8] = (a[0] * a[4] - a[1] * a[3]) / det;
  return true;
}
