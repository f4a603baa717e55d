/* Support for the heat conduction verification tests: the analytic series of Bobaru & Duangpanya 2012
 * Examples 1 and 2, the relative difference of Bobaru & Duangpanya 2012 eq. 13 along y = 0.5, and a
 * time loop that lands exactly on the sampling times. */
#ifndef PERI_TEST_HEAT_SUPPORT_H
#define PERI_TEST_HEAT_SUPPORT_H
#include <math.h>
#include "peri/heat.h"
#include "peri/thermal.h"
#include "support.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Example 1 (Bobaru & Duangpanya 2012 sec. 4.1.1): unit square, initial 40, edges at 0, diffusivity a.
 * A_mn = 16 * 40 / (pi^2 m n) for odd m, n. Terms until the next is below 1e-16. */
static inline double example1_exact(double x, double y, double t, double a) {
  double sum = 0.0;
  for (int m = 1; m < 300; m += 2)
    for (int n = 1; n < 300; n += 2) {
      double c = 640.0 / (M_PI * M_PI * m * n) * exp(-a * M_PI * M_PI * (m * m + n * n) * t);
      if (c < 1e-18) break;
      sum += c * sin(m * M_PI * x) * sin(n * M_PI * y);
    }
  return sum;
}

/* Example 2 (Bobaru & Duangpanya 2012 eq. 18): T = 1 + sum b_n exp(-beta_n^2 t) sin(beta_n x),
 * beta_n = (2n - 1) pi / 2, b_n = (cos beta_n - 1) / ((1/2 - sin(2 beta_n)/(4 beta_n)) beta_n). */
static inline double example2_exact(double x, double t) {
  double sum = 1.0;
  for (int n = 1; n < 2000; ++n) {
    double beta = (2 * n - 1) * M_PI / 2.0;
    double b = (cos(beta) - 1.0) / ((0.5 - sin(2.0 * beta) / (4.0 * beta)) * beta);
    double term = b * exp(-beta * beta * t);
    sum += term * sin(beta * x);
    if (fabs(term) < 1e-17) break;
  }
  return sum;
}

/* Bobaru & Duangpanya 2012 eq. 13 over the nodes on y = 0.5 with 0 <= x <= 1 (within 1e-9). */
static inline double relative_difference(const peri_sim *s, double (*exact)(double, double, double, void *),
                                         double t, void *ctx) {
  double num = 0.0, den = 0.0;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
    const double *x = &s->disc.p.x[3 * i];
    if (fabs(x[1] - 0.5) > 1e-9 || x[0] < -1e-9 || x[0] > 1.0 + 1e-9) continue;
    double e = exact(x[0], x[1], t, ctx);
    num += (e - s->thermal->T[i]) * (e - s->thermal->T[i]);
    den += e * e;
  }
  return sqrt(num / den);
}

/* Advances the heat to time t with steps no longer than the sim's step. */
static inline int advance_to(peri_sim *s, double t) {
  double span = t - s->thermal->time;
  if (span <= 0.0) return 0;
  long n = (long)ceil(span / s->solver.dt * (1.0 - 1e-12));
  double h = span / n;
  for (long k = 0; k < n; ++k)
    if (peri_thermal_step(s, h) != 0) return -1;
  s->thermal->time = t;
  return 0;
}

#endif
