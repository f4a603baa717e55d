#ifndef PERI_SMALL_MATRIX_H
#define PERI_SMALL_MATRIX_H
#include <stdbool.h>

/* Inverse of the leading dim x dim block (dim 1, 2 or 3) of a 3x3 row-major matrix by
 * cofactors; the rest of inv is zero. False (inv zero) when |det| is not above min_abs_det. */
bool peri_invert_block3(const double a[9], int dim, double min_abs_det, double inv[9]);

#endif
