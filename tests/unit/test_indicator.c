/* The interface-placement indicator D^2(u) (src/post/second_derivatives.c, 002 eq. 2.115):
 * the weighted least-squares fit over the family with the complete quadratic basis is exact
 * for a quadratic field, at every node including those whose families a surface cuts, so
 * D^2 equals the sum of the absolute second derivatives to round-off amplified by the
 * conditioning of the fit (1e-9 relative); a linear field gives 0 (1e-12 of the quadratic
 * scale). 1D, 2D and 3D. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "peri/indicator.h"
#include "support.h"

static void check(int dim, const char *fill, double expected, void (*field)(const double *, double *, int)) {
  char deck[1024];
  snprintf(deck, sizeof deck,
           "dimension: %d\n"
           "materials: {m: {model: pmb, density: 1, youngs_modulus: 1}}\n"
           "discretization: {spacing: 1, m: 3, fill: [%s]}\n"
           "solver: {type: explicit, steps: 1}\n"
           "output: {picture: false}\n",
           dim, fill);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0, "%s", deck);
  for (int32_t i = 0; i < s.disc.p.n; ++i) field(&s.disc.p.x[3 * (size_t)i], &s.disc.p.u[3 * (size_t)i], 0);
  double *D2 = malloc(sizeof(double) * (size_t)s.disc.p.n);
  peri_second_derivative_indicator(&s, D2);
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    cr_expect(fabs(D2[i] - expected) <= 1e-9 * expected, "%dD node %d: D2 %.12g, expected %.12g", dim, (int)i, D2[i], expected);
  for (int32_t i = 0; i < s.disc.p.n; ++i) field(&s.disc.p.x[3 * (size_t)i], &s.disc.p.u[3 * (size_t)i], 1);
  peri_second_derivative_indicator(&s, D2);
  for (int32_t i = 0; i < s.disc.p.n; ++i) cr_expect(fabs(D2[i]) <= 1e-12 * expected, "%dD linear: node %d D2 %.3g", dim, (int)i, D2[i]);
  free(D2);
  peri_sim_free(&s);
}

/* quadratic (linear = 0) or its linear part (linear = 1) */
static void field1(const double *x, double *u, int linear) { u[0] = 0.01 + 0.02 * x[0] + (linear ? 0.0 : -0.5 * 0.03 * x[0] * x[0]); }
static void field2(const double *x, double *u, int linear) {
  const double q = linear ? 0.0 : 1.0;
  u[0] = 0.1 + 0.02 * x[0] - 0.01 * x[1] + q * (0.5 * 0.004 * x[0] * x[0] - 0.003 * x[0] * x[1] + 0.5 * 0.002 * x[1] * x[1]);
  u[1] = -0.2 + 0.01 * x[0] + 0.03 * x[1] + q * (-0.5 * 0.001 * x[0] * x[0] + 0.005 * x[0] * x[1] - 0.5 * 0.006 * x[1] * x[1]);
}
static void field3(const double *x, double *u, int linear) {
  const double q = linear ? 0.0 : 1.0;
  for (int c = 0; c < 3; ++c)
    u[c] = 0.01 * (c + 1) * x[c] + q * 0.001 * (c + 1) * (0.5 * x[0] * x[0] - x[1] * x[2] + 0.5 * x[2] * x[2]);
}

Test(indicator, exact_for_quadratic_fields) {
  check(1, "{shape: interval, min: [-10.5], max: [10.5]}", 0.03, field1);
  check(2, "{shape: rectangle, min: [-6.5, -5.5], max: [6.5, 7.5]}", 0.004 + 0.003 + 0.002 + 0.001 + 0.005 + 0.006, field2);
  /* per component c: |u,xx| + |u,zz| + |u,yz| = 3 * 0.001 (c + 1) */
  check(3, "{shape: box, min: [-3.5, -3.5, -3.5], max: [3.5, 3.5, 3.5]}", 3 * 0.001 * (1 + 2 + 3), field3);
}
