/* Bobaru & Duangpanya 2012 Example 2 (Bobaru & Duangpanya 2012, sec. 4.2; docs/verification.md 13): the unit
 * square held at 1 on its left edge, insulated elsewhere, diffusivity 1, m = 6.5, with the
 * paper's scheme (quadrature bobaru2012: conical kernel, Algorithm 1, vertex-centred grid
 * with half and quarter boundary areas, the 8-neighbour self-term at half distance, the
 * zero-flux rule re-imposed after every RK4 stage). The relative differences along
 * y = 0.5 (paper eq. 13) against the series of paper eq. 18 reproduce Table 1 within 3%. */
#include "peri/setup.h"
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include "heat_support.h"

static const char *deck =
    "dimension: 2\n"
    "materials:\n"
    "  plate: {density: 1, conductivity: 1, specific_heat: 1}\n"
    "discretization:\n"
    "  spacing: %.17g\n"
    "  horizon: %.17g\n"
    "  placement: lattice\n"
    "  origin: [0, 0]\n"
    "  fill: [{shape: rectangle, min: [0, 0], max: [1, 1]}]\n"
    "regions:\n"
    "  left: {shape: rectangle, min: [-0.001, -0.001], max: [0.001, 1.001]}\n"
    "thermal: {quadrature: bobaru2012}\n"
    "boundary_conditions:\n"
    "  - {type: temperature, region: left, value: 1}\n"
    "solver: {type: heat, end_time: 0.2}\n"
    "output: {picture: false}\n";

static double exact2(double x, double y, double t, void *ctx) {
  (void)y, (void)ctx;
  return example2_exact(x, t);
}

/* Table 1 of Bobaru & Duangpanya 2012: rows t = 0.05, 0.1, 0.2; columns delta = 13L/120, 13L/240, 13L/480. */
static const double table1[3][3] = {{0.15741, 0.07927, 0.03474}, {0.11342, 0.05301, 0.02302},
                                    {0.07517, 0.03203, 0.01881}};

static void check_column(int column) {
  const int per_unit = 60 << column; /* nodes 61, 121, 241 per side */
  const double dx = 1.0 / per_unit, delta = 6.5 * dx;
  char text[2048];
  snprintf(text, sizeof text, deck, dx, delta);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, text), 0);
  const double times[3] = {0.05, 0.1, 0.2};
  for (int r = 0; r < 3; ++r) {
    cr_assert_eq(advance_to(&s, times[r]), 0);
    double diff = relative_difference(&s, exact2, times[r], NULL);
    double ratio = diff / table1[r][column];
    printf("example 2, delta = 13L/%d, t = %.2f: relative difference %.5f (paper Table 1: %.5f, ratio %.4f)\n",
           120 << column, times[r], diff, table1[r][column], ratio);
    cr_expect(fabs(ratio - 1.0) < 0.03, "delta = 13L/%d, t = %g: %.5f vs Table 1 %.5f", 120 << column,
              times[r], diff, table1[r][column]);
  }
  peri_sim_free(&s);
}

Test(heat_bobaru, table1_delta_13L_120) { check_column(0); }
Test(heat_bobaru, table1_delta_13L_240) { check_column(1); }

/* The finest horizon (241 x 241 nodes) takes a few minutes: run it with
 * PERI_HEAT_FINEST=1 build/tests/verif_test_heat_bobaru (the filter heat_bobaru/table1_delta_13L_480). */
Test(heat_bobaru, table1_delta_13L_480) {
  if (!getenv("PERI_HEAT_FINEST")) cr_skip_test("set PERI_HEAT_FINEST=1 to run the 241 x 241 grid");
  check_column(2);
}
