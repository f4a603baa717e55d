/* Heat conduction: the steady state of a 1D bar is linear, the thermal time step bound
 * from the largest row sum of the conduction operator is sharp (docs/verification.md 16), and
 * RK4 converges in time at fourth order. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/conduction.h"
#include "peri/setup.h"
#include "peri/solver.h"
#include "heat_support.h"

/* A 1D bar on [0, 1] with the temperature held at T = x on layers delta + dx/2 thick
 * beyond both ends (docs/model_reference.md 11.3): the linear field is the steady state, reached from
 * T = 0 to within exp(-pi^2 t) of the slowest mode. */
Test(heat, steady_state_of_a_bar_is_linear) {
  const char *deck =
      "dimension: 1\n"
      "materials:\n"
      "  bar: {density: 1, conductivity: 1, specific_heat: 1}\n"
      "discretization: {spacing: 0.02, m: 3, fill: [{shape: interval, min: [-0.08], max: [1.08]}]}\n"
      "regions:\n"
      "  cold: {shape: interval, min: [-1], max: [0]}\n"
      "  hot: {shape: interval, min: [1], max: [2]}\n"
      "boundary_conditions:\n"
      "  - {type: temperature, region: cold, value: x}\n"
      "  - {type: temperature, region: hot, value: x}\n"
      "solver: {type: heat, end_time: 4}\n";
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  cr_assert_eq(advance_to(&s, 4.0), 0);
  double worst = 0.0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) worst = fmax(worst, fabs(s.thermal->T[i] - s.disc.p.x[3 * i]));
  /* slowest mode of the (nonlocal) bar ~ exp(-pi^2 t) = 7e-18 at t = 4 */
  cr_expect(worst < 1e-10, "steady state departs from T = x by %g", worst);
  peri_sim_free(&s);
}

/* Nearest-neighbour 1D chain (m = 1, insulated): the alternating mode has eigenvalue
 * -2 x (row sum) up to O(1/N^2), so the Gershgorin bound of docs/model_reference.md 11.6 is sharp: 2% above it
 * the mode grows, 2% below it decays, for forward Euler and RK4. */
static double run_chain(const char *integrator, double factor) {
  char deck[2048];
  snprintf(deck, sizeof deck,
           "dimension: 1\n"
           "materials:\n"
           "  bar: {density: 1, conductivity: 1, specific_heat: 1}\n"
           "discretization: {spacing: 0.01, m: 1, fill: [{shape: interval, min: [0], max: [2]}]}\n"
           "thermal: {integrator: %s, initial_temperature: \"sin(pi*x/0.01) + 0.5\"}\n"
           "solver: {type: heat, steps: 1}\n",
           integrator);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  const double dt = factor * peri_thermal_stable_dt(s.thermal);
  double amplitude = 0.0;
  for (int k = 0; k < 3000; ++k) {
    if (peri_thermal_step(&s, dt) != 0) {
      amplitude = INFINITY;
      break;
    }
  }
  if (amplitude == 0.0)
    for (int32_t i = 0; i < s.disc.p.n_owned; ++i) amplitude = fmax(amplitude, fabs(s.thermal->T[i] - 0.5));
  peri_sim_free(&s);
  return amplitude;
}

Test(heat, stable_time_step_is_sharp) {
  const char *integrators[] = {"euler", "rk4"};
  for (int k = 0; k < 2; ++k) {
    double below = run_chain(integrators[k], 0.98), above = run_chain(integrators[k], 1.02);
    printf("%s: amplitude after 3000 steps %.3g at 0.98 x bound, %.3g at 1.02 x bound\n", integrators[k], below,
           above);
    cr_expect(below <= 1.0, "%s: 0.98 x the bound grew to %g", integrators[k], below);
    cr_expect(above > 1e6, "%s: 1.02 x the bound did not blow up (%g)", integrators[k], above);
  }
}

/* RK4 is fourth order in time: halving dt cuts the error (against a reference with
 * dt/16) by 2^4, within 20%. */
Test(heat, rk4_fourth_order) {
  const char *deck =
      "dimension: 1\n"
      "materials:\n"
      "  bar: {density: 1, conductivity: 1, specific_heat: 1}\n"
      "discretization: {spacing: 0.05, m: 3, fill: [{shape: interval, min: [0], max: [1]}]}\n"
      "thermal: {initial_temperature: \"exp(-30*(x-0.3)^2)\"}\n"
      "solver: {type: heat, steps: 1}\n";
  double *T[3];
  double dts[3];
  for (int k = 0; k < 3; ++k) {
    peri_sim s;
    cr_assert_eq(sim_from_string(&s, deck), 0);
    const double base = 0.5 * peri_thermal_stable_dt(s.thermal);
    dts[k] = k == 2 ? base / 16 : base / (1 << k);
    const long n = (long)llround(40 * base / dts[k]);
    for (long j = 0; j < n; ++j) cr_assert_eq(peri_thermal_step(&s, dts[k]), 0);
    T[k] = malloc(sizeof(double) * s.disc.p.n_owned);
    memcpy(T[k], s.thermal->T, sizeof(double) * s.disc.p.n_owned);
    if (k == 2) {
      double e0 = 0.0, e1 = 0.0;
      for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
        e0 = fmax(e0, fabs(T[0][i] - T[2][i]));
        e1 = fmax(e1, fabs(T[1][i] - T[2][i]));
      }
      double order = log(e0 / e1) / log(2.0);
      printf("rk4: errors %.3g (dt), %.3g (dt/2): order %.3f\n", e0, e1, order);
      cr_expect(fabs(order - 4.0) < 0.8, "RK4 order %.3f", order);
    }
    peri_sim_free(&s);
  }
  for (int k = 0; k < 3; ++k) free(T[k]);
}

/* Thermomechanics in time: a free 1D steel bar heated uniformly by 100 K (one-way coupling,
 * insulated, so T stays uniform) expands, and with damping settles at the strain
 * alpha dT = 1.2e-3 between its ends (exact: the free expansion is an exact equilibrium). */
Test(heat, free_bar_expands_by_alpha_dT) {
  const char *deck =
      "dimension: 1\n"
      "materials:\n"
      "  steel: {model: pmb, density: 7850, youngs_modulus: 200e9, conductivity: 50, specific_heat: 450,"
      " thermal_expansion: 1.2e-5}\n"
      "discretization: {spacing: 0.001, m: 3, fill: [{shape: interval, min: [0], max: [0.1]}]}\n"
      "thermal: {initial_temperature: 120, reference_temperature: 20, coupling: one_way}\n"
      "solver: {type: explicit, end_time: 2.0e-3, damping: 2.0e5}\n";
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_explicit(&s, NULL, NULL), 0);
  int32_t lo = 0, hi = 0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    if (s.disc.p.x[3 * i] < s.disc.p.x[3 * lo]) lo = i;
    if (s.disc.p.x[3 * i] > s.disc.p.x[3 * hi]) hi = i;
  }
  double strain = (s.disc.p.u[3 * hi] - s.disc.p.u[3 * lo]) / (s.disc.p.x[3 * hi] - s.disc.p.x[3 * lo]);
  printf("free bar: strain %.6e (alpha dT = 1.2e-3), temperature %g\n", strain, s.thermal->T[0]);
  cr_expect(fabs(strain / 1.2e-3 - 1.0) < 1e-4, "strain %.8g, expected 1.2e-3", strain);
  peri_sim_free(&s);
}
