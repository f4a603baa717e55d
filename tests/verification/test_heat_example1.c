/* Bobaru & Duangpanya 2012 Example 1 (sec. 4.1; docs/verification.md 14): the unit square at 40 with its edges
 * held at 0, diffusivity 1.14, against the analytic series at t = 0.01, 0.025, 0.05, 0.1 s
 * along y = 0.5 (paper eq. 13), at m = 6.5 and two horizons. The relative difference falls
 * at least linearly with delta (paper: rates 1.09-1.11 for m = 5.2-6.9).
 * Default scheme: the bonds' linear partial volumes, the own-cell term, and the Dirichlet
 * condition held on a layer of delta + dx/2 outside the square (docs/model_reference.md 11.3). */
#include "peri/setup.h"
#include <criterion/criterion.h>
#include <stdio.h>
#include "heat_support.h"

static const char *deck_default =
    "dimension: 2\n"
    "materials:\n"
    "  plate: {density: 1, conductivity: 1.14, specific_heat: 1}\n"
    "discretization:\n"
    "  spacing: %.17g\n"
    "  horizon: %.17g\n"
    "  placement: lattice\n"
    "  origin: [0, 0]\n"
    "  fill: [{shape: rectangle, min: [%.17g, %.17g], max: [%.17g, %.17g]}]\n"
    "regions:\n" /* the Dirichlet layer: every node on or outside the square's edges */
    "  west:  {shape: rectangle, min: [-1, -1], max: [1e-9, 2]}\n"
    "  east:  {shape: rectangle, min: [0.999999999, -1], max: [2, 2]}\n"
    "  south: {shape: rectangle, min: [-1, -1], max: [2, 1e-9]}\n"
    "  north: {shape: rectangle, min: [-1, 0.999999999], max: [2, 2]}\n"
    "thermal: {initial_temperature: 40}\n"
    "boundary_conditions:\n"
    "  - {type: temperature, region: west, value: 0}\n"
    "  - {type: temperature, region: east, value: 0}\n"
    "  - {type: temperature, region: south, value: 0}\n"
    "  - {type: temperature, region: north, value: 0}\n"
    "solver: {type: heat, end_time: 0.1}\n"
    "output: {picture: false}\n";

static double exact1(double x, double y, double t, void *ctx) {
  (void)ctx;
  return example1_exact(x, y, t, 1.14);
}

static void run(int level, double diff[4]) {
  const int per_unit = 60 << level;
  const double dx = 1.0 / per_unit, delta = 6.5 * dx, layer = 7 * dx;
  char text[4096];
  snprintf(text, sizeof text, deck_default, dx, delta, -layer, -layer, 1 + layer, 1 + layer);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, text), 0);
  const double times[4] = {0.01, 0.025, 0.05, 0.1};
  for (int r = 0; r < 4; ++r) {
    cr_assert_eq(advance_to(&s, times[r]), 0);
    diff[r] = relative_difference(&s, exact1, times[r], NULL);
  }
  peri_sim_free(&s);
}

Test(heat_example1, delta_convergence_default_scheme) {
  double d[2][4];
  run(0, d[0]);
  run(1, d[1]);
  const double times[4] = {0.01, 0.025, 0.05, 0.1};
  for (int r = 0; r < 4; ++r) {
    double rate = log(d[0][r] / d[1][r]) / log(2.0);
    printf("example 1 (default scheme), t = %.3f: relative difference %.5f (delta = 13L/120), %.5f "
           "(13L/240), rate %.3f\n", times[r], d[0][r], d[1][r], rate);
    cr_expect(rate > 0.9, "t = %g: delta-convergence rate %.3f, expected at least linear", times[r], rate);
  }
}

/* The paper's scheme (quadrature bobaru2012, the edges' boundary nodes held at 0) at
 * t = 0.025 s: the paper reports a delta-convergence rate of 1.112 at m = 6.5 (Fig. 12). */
static const char *deck_seed =
    "dimension: 2\n"
    "materials:\n"
    "  plate: {density: 1, conductivity: 1.14, specific_heat: 1}\n"
    "discretization:\n"
    "  spacing: %.17g\n"
    "  horizon: %.17g\n"
    "  placement: lattice\n"
    "  origin: [0, 0]\n"
    "  fill: [{shape: rectangle, min: [0, 0], max: [1, 1]}]\n"
    "regions:\n"
    "  west:  {shape: rectangle, min: [-1, -1], max: [1e-9, 2]}\n"
    "  east:  {shape: rectangle, min: [0.999999999, -1], max: [2, 2]}\n"
    "  south: {shape: rectangle, min: [-1, -1], max: [2, 1e-9]}\n"
    "  north: {shape: rectangle, min: [-1, 0.999999999], max: [2, 2]}\n"
    "thermal: {quadrature: bobaru2012, initial_temperature: 40}\n"
    "boundary_conditions:\n"
    "  - {type: temperature, region: west, value: 0}\n"
    "  - {type: temperature, region: east, value: 0}\n"
    "  - {type: temperature, region: south, value: 0}\n"
    "  - {type: temperature, region: north, value: 0}\n"
    "solver: {type: heat, end_time: 0.025}\n"
    "output: {picture: false}\n";

Test(heat_example1, delta_convergence_seed_scheme) {
  double d[2];
  for (int level = 0; level < 2; ++level) {
    const double dx = 1.0 / (60 << level);
    char text[4096];
    snprintf(text, sizeof text, deck_seed, dx, 6.5 * dx);
    peri_sim s;
    cr_assert_eq(sim_from_string(&s, text), 0);
    cr_assert_eq(advance_to(&s, 0.025), 0);
    d[level] = relative_difference(&s, exact1, 0.025, NULL);
    peri_sim_free(&s);
  }
  double rate = log(d[0] / d[1]) / log(2.0);
  printf("example 1 (bobaru2012), t = 0.025: relative difference %.5f (13L/120), %.5f (13L/240), rate %.3f "
         "(paper: 1.112)\n", d[0], d[1], rate);
  cr_expect(rate > 0.9, "delta-convergence rate %.3f, expected at least linear", rate);
}
