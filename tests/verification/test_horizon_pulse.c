/* Pulse through a horizon transition (docs/variable_horizon.md; Silling, Littlewood and
 * Seleson 2013, "Pulse propagation test"): a 1D bar with delta = 3 dx left of x = 0.3 m and
 * 6 dx right of it carries a Gaussian displacement pulse to the right. Both horizons give the
 * same long-wave speed sqrt(E/rho), so a consistent coupling transmits the pulse without a
 * reflection. The reflected wave is measured as the difference between the run and the same
 * run with delta = 3 dx everywhere (which has the same dispersion left of the transition and
 * no transition), left of the transition once the incident pulse has passed it:
 *   - partial stress in the coupling region: reflected amplitude <= 1% of the incident;
 *   - full peridynamics: measurably larger (>= 2 times the partial-stress reflection: the
 *     ghost forces of the patch test scatter the wave).
 * And the energy of an explicit run with the partial stress stays bounded over 10^4 steps. */
#include "peri/energies.h"
#include "peri/horizon_field.h"
#include "peri/setup.h"
#include "peri/solver.h"
#include <criterion/criterion.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include "support.h"

/* The bar is 30 pulse half-widths long, the transition in its middle, the pulse a quarter
 * of the way. */
#define DX 1.0e-3
#define AMPLITUDE 1e-5
#define E_MOD 70e9
#define RHO 2700.0

static void build(peri_sim *s, double width, const char *coupling, long steps) {
  char deck[4096], horizon[128];
  const double length = 30 * width, x0 = 7.5 * width;
  snprintf(horizon, sizeof horizon, "x < %.17g ? 0.003 : 0.006", 15 * width);
  if (!coupling) snprintf(horizon, sizeof horizon, "0.003 + 0 * x"), coupling = "none"; /* the reference */
  const double c = sqrt(E_MOD / RHO);
  snprintf(deck, sizeof deck,
           "dimension: 1\n"
           "materials:\n  bar: {model: pmb, density: %g, youngs_modulus: %g}\n"
           "discretization:\n  spacing: %g\n  horizon: \"%s\"\n  partial_stress: %s\n"
           "  fill: [{shape: box, min: [0.0], max: [%g]}]\n"
           "boundary_conditions:\n"
           "  - {type: initial_displacement, region: all, x: \"%g * exp(-((x - %g) / %g)^2)\"}\n"
           "  - {type: initial_velocity, region: all, x: \"%g * 2 * (x - %g) / %g^2 * exp(-((x - %g) / %g)^2)\"}\n"
           "solver: {type: explicit, steps: %ld, safety_factor: 0.8, breaking: false}\n"
           "output: {picture: false}\n",
           RHO, E_MOD, DX, horizon, coupling, length, AMPLITUDE, x0, width, c * AMPLITUDE, x0, width, x0, width, steps);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  peri_apply_initial_conditions(s);
}

/* The displacement after the incident pulse's centre has travelled 13.5 half-widths (to 21
 * from the left end), so that a reflection from the transition at 15 is centred near 9; u[k]
 * at x = (k + 1/2) dx. coupling NULL: the reference with 3 dx everywhere. */
static double *pulse_at_arrival(double width, const char *coupling, double dt) {
  peri_sim s;
  build(&s, width, coupling, 1);
  s.solver.dt = dt;
  s.solver.steps = (long)ceil(13.5 * width / sqrt(E_MOD / RHO) / dt);
  cr_assert_eq(peri_solve_explicit(&s, NULL, NULL), 0);
  const int32_t n = s.disc.p.n;
  double *u = calloc((size_t)n, sizeof(double));
  for (int32_t i = 0; i < n; ++i) u[(int32_t)floor(s.disc.p.x[3 * i] / DX)] = s.disc.p.u[3 * i];
  peri_sim_free(&s);
  return u;
}

/* a 1D bar of 600 to 2400 nodes: a second thread costs more in each step's parallel regions
 * than it saves */
static void one_thread(void) { omp_set_num_threads(1); }

/* The pulse's half-width is 80 dx (k delta_max ~ 0.08): the partial-stress reflection left is
 * that of the two operators' different dispersion, of order (k delta)^2 and more, while
 * the ghost forces of full PD scatter at first order in k delta (measured at half-widths of
 * 20, 40 and 80 dx: partial stress 0.64%, 0.14%, 0.030%; full PD 1.06%, 0.33%, 0.12%). */
Test(horizon_pulse, reflection, .init = one_thread) {
  const double width = 0.08;
  /* one time step for the three runs: that of the stiffest, the partial-stress one */
  peri_sim probe;
  build(&probe, width, "auto", 1);
  const double dt = probe.solver.dt;
  peri_sim_free(&probe);
  double *reference = pulse_at_arrival(width, NULL, dt);
  double *coupled = pulse_at_arrival(width, "auto", dt);
  double *full = pulse_at_arrival(width, "none", dt);
  /* left of the transition, beyond the largest horizon from it and from the end */
  double r_ps = 0.0, r_pd = 0.0, incident_left = 0.0;
  const int left = (int)(15 * width / DX) - 10, right = (int)(30 * width / DX) - 20;
  for (int k = 20; k < left; ++k) {
    r_ps = fmax(r_ps, fabs(coupled[k] - reference[k]));
    r_pd = fmax(r_pd, fabs(full[k] - reference[k]));
    incident_left = fmax(incident_left, fabs(reference[k]));
  }
  double transmitted = 0.0;
  for (int k = left + 20; k < right; ++k) transmitted = fmax(transmitted, fabs(coupled[k]));
  r_ps /= AMPLITUDE, r_pd /= AMPLITUDE;
  cr_log_info("reflected amplitude / incident: partial stress %.3e, full PD %.3e; transmitted peak %.3f; reference "
              "left of the transition %.3e", r_ps, r_pd, transmitted / AMPLITUDE, incident_left / AMPLITUDE);
  cr_expect(r_ps <= 0.01, "partial stress: reflected amplitude %.3g%% of the incident (limit 1%%)", 100 * r_ps);
  cr_expect(r_pd >= 2.0 * r_ps,
            "full PD: reflected amplitude %.3g%% of the incident, not measurably larger than partial stress's %.3g%%",
            100 * r_pd, 100 * r_ps);
  cr_expect(transmitted >= 0.9 * AMPLITUDE, "the pulse did not cross the transition (peak %.3g)", transmitted / AMPLITUDE);
  free(reference), free(coupled), free(full);
}

typedef struct {
  long every;
  double first_max, last_max, overall_max;
  long steps;
} energy_log;

static int record_energy(peri_sim *s, void *ctx) {
  energy_log *log = ctx;
  if (s->state.step % log->every) return 0;
  const double e = peri_kinetic_energy(s) + peri_strain_energy(s);
  if (s->state.step <= log->steps / 10) log->first_max = fmax(log->first_max, e);
  if (s->state.step > log->steps - log->steps / 10) log->last_max = fmax(log->last_max, e);
  log->overall_max = fmax(log->overall_max, e);
  return 0;
}

/* 10^4 explicit steps of the short pulse (half-width 20 dx; the pulse crosses the transition
 * about 17 times between the free ends): the total energy stays within 1% of its initial value and does not grow from the
 * first tenth of the run to the last. The bound 1%: the force of the coupling region is not
 * the gradient of the energy, so the energy is not conserved exactly; the patch test shows
 * the coupling's error is round-off for homogeneous strain, and for the pulse the error left
 * is of the order of the reflection (<= 1%). */
Test(horizon_pulse, energy_bounded, .init = one_thread) {
  peri_sim s;
  build(&s, 0.02, "auto", 10000);
  const double e0 = peri_kinetic_energy(&s) + peri_strain_energy(&s);
  energy_log log = {50, 0.0, 0.0, 0.0, s.solver.steps};
  cr_assert_eq(peri_solve_explicit(&s, record_energy, &log), 0);
  cr_log_info("energy / initial: max over the first tenth %.6f, the last tenth %.6f, the run %.6f", log.first_max / e0,
              log.last_max / e0, log.overall_max / e0);
  cr_expect(log.overall_max <= 1.01 * e0, "energy grew to %.4f of the initial", log.overall_max / e0);
  cr_expect(log.last_max <= 1.001 * log.first_max, "energy grows: last tenth %.6f, first tenth %.6f of the initial",
            log.last_max / e0, log.first_max / e0);
  peri_sim_free(&s);
}

/* 10^4 explicit steps in 2D and 3D (docs/variable_horizon.md, "Zero-energy mode control"): a
 * Gaussian velocity pulse in a free plate (cube) whose horizon steps up outside a disc (ball)
 * at its centre, so that the coupling region lies inside the body. With the control's default
 * factor the assembled operator has only real, positive eigenvalues, and the energy oscillates
 * about a level without a trend; with the 1D default (1) complex pairs make it grow by orders
 * of magnitude within the run. The energy read is the peridynamic one, which the partial
 * stress does not conserve exactly (measured up to 1.23 times the initial, in the first tenth
 * as in the last): no growth is read as the largest value over the last tenth of the run at
 * most 1.1 times that over the first tenth, and none above 1.5 times the initial. The runs
 * with factor 1 fail: in 2D the energy reaches about 900 times the initial, in 3D the run
 * stops on a non-finite displacement. */
static void energy_bounded_multi_d(int dim, double kappa) {
  char deck[4096], field[256], bc[512];
  const double half = dim == 2 ? 0.010 : 0.004, core = dim == 2 ? 0.004 : 0.0012, x0 = dim == 2 ? -0.005 : -0.0015,
               w = dim == 2 ? 0.002 : 0.0015;
  const char *r2 = dim == 2 ? "x^2 + y^2" : "x^2 + y^2 + z^2";
  snprintf(field, sizeof field, "sqrt(%s) < %.17g ? %s", r2, core, dim == 2 ? "0.002 : 0.003" : "0.0015 : 0.002");
  snprintf(bc, sizeof bc,
           "  - {type: initial_velocity, region: all, x: \"exp(-((x + %g)^2 + %s - x^2) / %g^2)\", "
           "y: \"0.5 * exp(-((x + %g)^2 + %s - x^2) / %g^2)\"}\n",
           -x0, r2, w, -x0, r2, w);
  char box[160];
  if (dim == 2) snprintf(box, sizeof box, "[%g, %g], max: [%g, %g]", -half, -half, half, half);
  else snprintf(box, sizeof box, "[%g, %g, %g], max: [%g, %g, %g]", -half, -half, -half, half, half, half);
  char kappa_line[64] = "";
  if (kappa > 0.0) snprintf(kappa_line, sizeof kappa_line, "  partial_stress_stabilization: %g\n", kappa);
  snprintf(deck, sizeof deck,
           "dimension: %d\n%s"
           "materials:\n  mat: {model: pmb, density: %g, youngs_modulus: %g}\n"
           "discretization:\n  spacing: 1.0e-3\n  horizon: \"%s\"\n  partial_stress: auto\n%s%s"
           "  fill: [{shape: box, min: %s}]\n"
           "boundary_conditions:\n%s"
           "solver: {type: explicit, steps: 10000, breaking: false}\n"
           "output: {picture: false}\n",
           dim, dim == 2 ? "plane: stress\n" : "", RHO, E_MOD, field, kappa_line, dim == 2 ? "  thickness: 1.0e-3\n" : "",
           box, bc);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0, "deck:\n%s", deck);
  cr_assert_gt(s.disc.horizon_field->n_coupled, 0);
  peri_apply_initial_conditions(&s);
  const double e0 = peri_kinetic_energy(&s) + peri_strain_energy(&s);
  energy_log log = {50, 0.0, 0.0, 0.0, s.solver.steps};
  const int rc = peri_solve_explicit(&s, record_energy, &log);
  cr_log_info("%dD, control factor %g: energy / initial: max over the first tenth %.4f, the last tenth %.4f, the run "
              "%.4f (rc %d)", dim, s.disc.horizon_field->stabilization, log.first_max / e0, log.last_max / e0,
              log.overall_max / e0, rc);
  cr_expect_eq(rc, 0, "the run stopped (rc %d): energy %.4g of the initial", rc, log.overall_max / e0);
  cr_expect(log.overall_max <= 1.5 * e0, "energy grew to %.4f of the initial", log.overall_max / e0);
  cr_expect(log.last_max <= 1.1 * log.first_max, "energy grows: last tenth %.4f, first tenth %.4f of the initial",
            log.last_max / e0, log.first_max / e0);
  peri_sim_free(&s);
}

Test(horizon_pulse, energy_bounded_2d, .init = one_thread) { energy_bounded_multi_d(2, 0.0); }
Test(horizon_pulse, energy_bounded_3d, .init = one_thread) { energy_bounded_multi_d(3, 0.0); }
