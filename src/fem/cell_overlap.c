/* Exact partial volumes of the coupling's PD side (002_b20c318388227af9.txt §1.3.1 ref. [190],
 * App. A.2 eq. A.34; MODELS.md 5(d)): the part of a node's cell (the square of side dx centred
 * on it) inside the horizon disk of another node, computed analytically. */
#include <math.h>
#include "peri/coupling.h"

/* antiderivative of sqrt(r^2 - x^2) on [-r, r] */
static double half_chord_integral(double x, double r) {
  x = fmax(-r, fmin(r, x));
  return 0.5 * (x * sqrt(fmax(r * r - x * x, 0.0)) + r * r * asin(x / r));
}

double peri_disk_rectangle_area(double x0, double x1, double y0, double y1, double r) {
  /* integrate over x the length of [y0, y1] within the chord [-h(x), h(x)], h = sqrt(r^2 - x^2),
   * piecewise between the points where h meets y0 or y1 or the disk ends: on each piece the
   * bounds are constants or -h, h, whose integrals are exact */
  double cut[8];
  int n = 0;
  cut[n++] = x0;
  const double candidates[2] = {-r, r};
  for (int k = 0; k < 2; ++k)
    if (candidates[k] > x0 && candidates[k] < x1) cut[n++] = candidates[k];
  const double ys[2] = {y0, y1};
  for (int k = 0; k < 2; ++k)
    if (fabs(ys[k]) < r) {
      const double w = sqrt(r * r - ys[k] * ys[k]);
      if (-w > x0 && -w < x1) cut[n++] = -w;
      if (w > x0 && w < x1) cut[n++] = w;
    }
  cut[n++] = x1;
  for (int a = 1; a < n; ++a) /* insertion sort of at most 8 points */
    for (int b = a; b > 0 && cut[b] < cut[b - 1]; --b) {
      const double t = cut[b];
      cut[b] = cut[b - 1], cut[b - 1] = t;
    }
  double area = 0.0;
  for (int k = 0; k + 1 < n; ++k) {
    const double a = cut[k], b = cut[k + 1], m = 0.5 * (a + b);
    if (!(b > a) || fabs(m) >= r) continue;
    const double h = sqrt(r * r - m * m);
    if (fmin(y1, h) <= fmax(y0, -h)) continue; /* the chord misses [y0, y1] here */
    const double chord = half_chord_integral(b, r) - half_chord_integral(a, r);
    const double upper = h <= y1 ? chord : y1 * (b - a);
    const double lower = -h >= y0 ? -chord : y0 * (b - a);
    area += upper - lower;
  }
  return area;
}
