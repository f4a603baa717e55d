/* Element centroids and measures. Tetrahedra and triangles in closed form; pyramids, wedges
 * and hexahedra as (degenerate) trilinear hexahedra, integrated with 2x2x2 Gauss points,
 * which is exact: det J of a trilinear map has degree 2 in each variable, x det J degree 3. */
#include <math.h>
#include "element_geometry.h"

int peri_element_dim(peri_element_shape shape) {
  switch (shape) {
  case PERI_ELEMENT_LINE: return 1;
  case PERI_ELEMENT_TRI:
  case PERI_ELEMENT_QUAD: return 2;
  default: return 3;
  }
}

int peri_element_corners(peri_element_shape shape) {
  static const int corners[] = {2, 3, 4, 4, 5, 6, 8};
  return corners[shape];
}

static void sub(const double *a, const double *b, double *out) {
  for (int d = 0; d < 3; ++d) out[d] = a[d] - b[d];
}
static void cross(const double *a, const double *b, double *out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The trilinear hexahedron through the 8 points h (ordered as an Exodus HEX8). */
static void hexahedron(const double *h, double *volume, double c[3]) {
  static const double s[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                 {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const double g = 1.0 / sqrt(3.0);
  double v = 0.0, m[3] = {0, 0, 0};
  for (int q = 0; q < 8; ++q) {
    const double xi[3] = {s[q][0] * g, s[q][1] * g, s[q][2] * g};
    double J[3][3] = {{0}}, x[3] = {0, 0, 0};
    for (int a = 0; a < 8; ++a) {
      const double f[3] = {1 + s[a][0] * xi[0], 1 + s[a][1] * xi[1], 1 + s[a][2] * xi[2]};
      const double N = f[0] * f[1] * f[2] / 8.0;
      const double dN[3] = {s[a][0] * f[1] * f[2] / 8.0, s[a][1] * f[0] * f[2] / 8.0, s[a][2] * f[0] * f[1] / 8.0};
      for (int i = 0; i < 3; ++i) {
        x[i] += N * h[3 * a + i];
        for (int j = 0; j < 3; ++j) J[i][j] += h[3 * a + i] * dN[j];
      }
    }
    const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                       J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                       J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
    v += det; /* unit weights */
    for (int i = 0; i < 3; ++i) m[i] += det * x[i];
  }
  *volume = fabs(v);
  for (int i = 0; i < 3; ++i) c[i] = v != 0.0 ? m[i] / v : 0.0;
}

void peri_element_measure(peri_element_shape shape, const double *p, double *measure, double c[3]) {
  double a[3], b[3], n[3];
  switch (shape) {
  case PERI_ELEMENT_LINE:
    sub(p + 3, p, a);
    *measure = sqrt(dot(a, a));
    for (int d = 0; d < 3; ++d) c[d] = 0.5 * (p[d] + p[3 + d]);
    return;
  case PERI_ELEMENT_TRI:
    sub(p + 3, p, a);
    sub(p + 6, p, b);
    cross(a, b, n);
    *measure = 0.5 * sqrt(dot(n, n));
    for (int d = 0; d < 3; ++d) c[d] = (p[d] + p[3 + d] + p[6 + d]) / 3.0;
    return;
  case PERI_ELEMENT_QUAD: {
    /* a plane quadrilateral: the two triangles 012 and 023, signed along the normal of the
     * diagonals, so that a non-convex quadrilateral is measured right too */
    double d1[3], d2[3], t1[3], t2[3];
    sub(p + 6, p, d1);
    sub(p + 9, p + 3, d2);
    cross(d1, d2, n);
    const double nn = sqrt(dot(n, n));
    *measure = 0.5 * nn;
    if (nn == 0.0) {
      for (int d = 0; d < 3; ++d) c[d] = 0.25 * (p[d] + p[3 + d] + p[6 + d] + p[9 + d]);
      return;
    }
    sub(p + 3, p, a);
    cross(a, d1, t1);
    sub(p + 9, p, b);
    cross(d1, b, t2);
    const double A1 = 0.5 * dot(t1, n) / nn, A2 = 0.5 * dot(t2, n) / nn;
    for (int d = 0; d < 3; ++d)
      c[d] = (A1 * (p[d] + p[3 + d] + p[6 + d]) + A2 * (p[d] + p[6 + d] + p[9 + d])) / (3.0 * (A1 + A2));
    return;
  }
  case PERI_ELEMENT_TET: {
    double e[3];
    sub(p + 3, p, a);
    sub(p + 6, p, b);
    sub(p + 9, p, e);
    cross(a, b, n);
    *measure = fabs(dot(n, e)) / 6.0;
    for (int d = 0; d < 3; ++d) c[d] = 0.25 * (p[d] + p[3 + d] + p[6 + d] + p[9 + d]);
    return;
  }
  case PERI_ELEMENT_PYRAMID:
  case PERI_ELEMENT_WEDGE:
  case PERI_ELEMENT_HEX: {
    static const int pyramid[8] = {0, 1, 2, 3, 4, 4, 4, 4}, wedge[8] = {0, 1, 2, 2, 3, 4, 5, 5},
                     hex[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    const int *map = shape == PERI_ELEMENT_PYRAMID ? pyramid : shape == PERI_ELEMENT_WEDGE ? wedge : hex;
    double h[24];
    for (int k = 0; k < 8; ++k)
      for (int d = 0; d < 3; ++d) h[3 * k + d] = p[3 * map[k] + d];
    hexahedron(h, measure, c);
    return;
  }
  }
}
