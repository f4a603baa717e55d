/* Local-nonlocal coupling with a vanishing horizon (docs/variable_horizon.md "A vanishing
 * horizon: the local model"; Silling, Littlewood and Seleson 2013, "Local-nonlocal coupling
 * idea", "Continuum patch test with coupling"). Where the horizon expression is 0 the nodes
 * are local: their partial stress is the Cauchy stress C : eps of their least-squares strain,
 * the delta -> 0 limit of nu0 = sum_j T<xi> (x) xi V_j under T = delta^-(d+1) Z<xi/delta>, and
 * their force is its divergence, as in the coupling region.
 *   - Patch test u = a + Hx (1D any H, 2D and 3D the dilatation H = h I, as for the partial
 *     stress alone, tests/verification/test_variable_horizon.c; a general H in 2D and 3D is
 *     tests/verification/test_shear_patch.c): the interior force vanishes
 *     to round-off at the full-PD, the coupled and the local nodes. The per-node calibration
 *     makes nu0 of a PD node under this H exactly the Cauchy stress of the same strain (1D:
 *     E H; 2D/3D: the bulk stress of the dilatation), so a local side with other elastic
 *     constants (a wrong E or nu) leaves a force of the order of the difference at the
 *     interface: the test checks that the two sides have the same constants (in 2D and 3D
 *     the bulk modulus, which is all a dilatation sees; a local E 1% off fails every case).
 *   - Pulse from the PD region into the local one: reflection <= 1% of the incident.
 *   - Energy of a pulse crossing the interface back and forth over 10^4 steps: bounded.
 *   - A local-only bar carries a pulse at sqrt(E/rho).
 *   - Quasi-static solves (adr, dynamic_relaxation) converge with local nodes: a bar under an
 *     end load, a plate in tension with free local edges, a gripped plate with a PD square. */
#include "peri/energies.h"
#include "peri/horizon_field.h"
#include "peri/quasistatic.h"
#include "peri/setup.h"
#include "peri/solver.h"
#include <criterion/criterion.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include "support.h"

#define DX 1.0e-3
#define E_MOD 70.0e9
#define RHO 2700.0
#define STRAIN 0.02
#define AMPLITUDE 1e-5

static void one_thread(void) { omp_set_num_threads(1); }

/* ---------------------------------------------------------------- patch test */

typedef struct {
  int dim;
  const char *model;
  const char *horizon; /* 0 where the nodes are local */
  double delta_max;
  int n[3];
} patch_case;

static void build_patch(peri_sim *s, const patch_case *c) {
  char lo[128], hi[128], mat[192], deck[4096];
  double h[3];
  for (int d = 0; d < 3; ++d) h[d] = 0.5 * c->n[d] * DX;
  if (c->dim == 1) snprintf(lo, sizeof lo, "[%.17g]", -h[0]), snprintf(hi, sizeof hi, "[%.17g]", h[0]);
  if (c->dim == 2)
    snprintf(lo, sizeof lo, "[%.17g, %.17g]", -h[0], -h[1]), snprintf(hi, sizeof hi, "[%.17g, %.17g]", h[0], h[1]);
  if (c->dim == 3)
    snprintf(lo, sizeof lo, "[%.17g, %.17g, %.17g]", -h[0], -h[1], -h[2]),
        snprintf(hi, sizeof hi, "[%.17g, %.17g, %.17g]", h[0], h[1], h[2]);
  if (c->model[0] == 'l')
    snprintf(mat, sizeof mat, "{model: lps, density: %g, youngs_modulus: %.17g, poisson_ratio: 0.3}", RHO, E_MOD);
  else
    snprintf(mat, sizeof mat, "{model: pmb, density: %g, youngs_modulus: %.17g}", RHO, E_MOD);
  snprintf(deck, sizeof deck,
           "dimension: %d\n%s"
           "materials:\n  mat: %s\n"
           "discretization:\n  spacing: %.17g\n  horizon: \"%s\"\n%s"
           "  fill: [{shape: box, min: %s, max: %s}]\n"
           "solver: {type: explicit, steps: 1, breaking: false}\n"
           "output: {picture: false}\n",
           c->dim, c->dim == 2 ? "plane: stress\n" : "", mat, DX, c->horizon,
           c->dim == 2 ? "  thickness: 1.0e-3\n" : "", lo, hi);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  cr_assert_not_null(s->disc.horizon_field);
  cr_assert_gt(s->disc.horizon_field->n_local, 0);
}

/* the force scale of test_variable_horizon.c: 1D 4E/delta, plane stress 9E/delta, 3D 24K/delta */
static double force_scale(const patch_case *c) {
  const double K = c->model[0] == 'l' ? E_MOD / (3.0 * (1.0 - 2.0 * 0.3)) : E_MOD / (3.0 * (1.0 - 2.0 * 0.25));
  if (c->dim == 3) return 24.0 * K / c->delta_max;
  return (c->dim == 1 ? 4.0 : 9.0) * E_MOD / c->delta_max;
}

/* The largest interior |f| over S |H| of each kind of node (full PD, coupled PD, local), the
 * nodes farther than 2 delta_max + 2 dx from every face. */
static void check_patch(patch_case c) {
  peri_sim s;
  build_patch(&s, &c);
  const peri_horizon_field *h = s.disc.horizon_field;
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    for (int a = 0; a < 3; ++a) s.disc.p.u[3 * i + a] = a < c.dim ? 1.0e-4 + STRAIN * s.disc.p.x[3 * i + a] : 0.0;
  s.mat.model->force(&s);
  double worst[3] = {0, 0, 0};
  int count[3] = {0, 0, 0};
  const double limit = 2.0 * c.delta_max + 2.0 * DX, scale = force_scale(&c) * STRAIN;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    double depth = INFINITY;
    for (int k = 0; k < c.dim; ++k) depth = fmin(depth, 0.5 * c.n[k] * DX - fabs(s.disc.p.x[3 * i + k]));
    if (depth <= limit) continue;
    const int kind = h->local[i] ? 2 : h->coupled[i] ? 1 : 0;
    const double *f = &s.disc.p.f[3 * i];
    worst[kind] = fmax(worst[kind], sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) / scale);
    count[kind]++;
  }
  cr_log_info("%s %dD horizon %s: interior |f| / (S |H|): full PD %.2e (%d nodes), coupled %.2e (%d), local %.2e (%d)",
              c.model, c.dim, c.horizon, worst[0], count[0], worst[1], count[1], worst[2], count[2]);
  static const char *const kind_name[3] = {"full PD", "coupled", "local"};
  for (int k = 0; k < 3; ++k) {
    cr_assert_gt(count[k], 0, "no interior %s node: the test would be vacuous", kind_name[k]);
    cr_expect(worst[k] <= 1e-10, "%s %dD: the %s nodes' interior |f| = %.3g S|H| > 1e-10", c.model, c.dim, kind_name[k],
              worst[k]);
  }
  peri_sim_free(&s);
}

/* PD (3 dx) in the middle of the bar, local ends; and a ramp from 6 dx down to 2 dx, then 0 */
#define STEP_1D "abs(x) < 0.02 ? 0.003 : 0"
#define RAMP_1D "abs(x) < 0.01 ? 0.006 : abs(x) < 0.02 ? 0.006 - 0.4 * (abs(x) - 0.01) : 0"

Test(local_coupling, patch_pmb_1d_step) { check_patch((patch_case){1, "pmb", STEP_1D, 0.003, {100, 1, 1}}); }
Test(local_coupling, patch_pmb_1d_ramp) { check_patch((patch_case){1, "pmb", RAMP_1D, 0.006, {100, 1, 1}}); }
Test(local_coupling, patch_lps_1d_step) { check_patch((patch_case){1, "lps", STEP_1D, 0.003, {100, 1, 1}}); }
Test(local_coupling, patch_lps_1d_ramp) { check_patch((patch_case){1, "lps", RAMP_1D, 0.006, {100, 1, 1}}); }
Test(local_coupling, patch_pmb_2d) {
  check_patch((patch_case){2, "pmb", "abs(x) < 0.009 ? 0.003 : 0", 0.003, {50, 30, 1}});
}
Test(local_coupling, patch_lps_2d) {
  check_patch((patch_case){2, "lps", "abs(x) < 0.009 ? 0.003 : 0", 0.003, {50, 30, 1}});
}
Test(local_coupling, patch_pmb_3d) {
  check_patch((patch_case){3, "pmb", "abs(x) < 0.006 ? 0.002 : 0", 0.002, {30, 14, 14}});
}

/* ---------------------------------------------------------------- waves in 1D */

/* A PMB bar [0, length] with the horizon expression `horizon` carrying a right-going Gaussian
 * displacement pulse of half-width w centred at x0 (velocity -c u' with c = sqrt(E/rho)). */
static void build_pulse(peri_sim *s, const char *horizon, double length, double x0, double w, long steps) {
  char deck[4096];
  const double c = sqrt(E_MOD / RHO);
  snprintf(deck, sizeof deck,
           "dimension: 1\n"
           "materials:\n  bar: {model: pmb, density: %g, youngs_modulus: %g}\n"
           "discretization:\n  spacing: %g\n  horizon: \"%s\"\n"
           "  fill: [{shape: box, min: [0.0], max: [%.17g]}]\n"
           "boundary_conditions:\n"
           "  - {type: initial_displacement, region: all, x: \"%g * exp(-((x - %.17g) / %.17g)^2)\"}\n"
           "  - {type: initial_velocity, region: all, x: \"%.17g * 2 * (x - %.17g) / %.17g^2 * exp(-((x - %.17g) / "
           "%.17g)^2)\"}\n"
           "solver: {type: explicit, steps: %ld, safety_factor: 0.8, breaking: false}\n"
           "output: {picture: false}\n",
           RHO, E_MOD, DX, horizon, length, AMPLITUDE, x0, w, c * AMPLITUDE, x0, w, x0, w, steps);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  peri_apply_initial_conditions(s);
}

/* u by cell after `steps` steps of dt (u[k] at x = (k + 1/2) dx) */
static double *pulse_after(const char *horizon, double length, double x0, double w, double dt, long steps) {
  peri_sim s;
  build_pulse(&s, horizon, length, x0, w, steps);
  s.solver.dt = dt;
  cr_assert_eq(peri_solve_explicit(&s, NULL, NULL), 0);
  double *u = calloc((size_t)s.disc.p.n, sizeof(double));
  for (int32_t i = 0; i < s.disc.p.n; ++i) u[(int32_t)floor(s.disc.p.x[3 * i] / DX)] = s.disc.p.u[3 * i];
  peri_sim_free(&s);
  return u;
}

/* Seed 003's 1D picture: PD (delta = 3 dx) left of x = 15 w, local right of it. The pulse
 * (half-width w = 40 dx) starts at 7.5 w and travels 13.5 w; the reflection is the difference
 * from the same run with 3 dx everywhere, left of the interface (the method of
 * test_horizon_pulse.c). Both sides have the long-wave speed sqrt(E/rho); what reflects comes
 * from their different dispersion (order (k dx)^2) and the coupling: asserted <= 1% of the
 * incident amplitude, and the pulse must have crossed (transmitted peak >= 0.9). */
Test(local_coupling, pulse_into_local_region, .init = one_thread) {
  const double w = 0.04, length = 30 * w, c = sqrt(E_MOD / RHO);
  char coupled_field[128];
  snprintf(coupled_field, sizeof coupled_field, "x < %.17g ? 0.003 : 0", 15 * w);
  peri_sim probe;
  build_pulse(&probe, coupled_field, length, 7.5 * w, w, 1);
  const double dt = probe.solver.dt;
  peri_sim_free(&probe);
  const long steps = (long)ceil(13.5 * w / c / dt);
  double *reference = pulse_after("0.003 + 0 * x", length, 7.5 * w, w, dt, steps);
  double *coupled = pulse_after(coupled_field, length, 7.5 * w, w, dt, steps);
  const int left = (int)(15 * w / DX) - 10, right = (int)(length / DX) - 20;
  double reflected = 0.0, transmitted = 0.0;
  for (int k = 20; k < left; ++k) reflected = fmax(reflected, fabs(coupled[k] - reference[k]));
  for (int k = left + 20; k < right; ++k) transmitted = fmax(transmitted, fabs(coupled[k]));
  cr_log_info("PD -> local: reflected amplitude / incident %.3e, transmitted peak %.4f (dt %.3g s, %ld steps)",
              reflected / AMPLITUDE, transmitted / AMPLITUDE, dt, steps);
  cr_expect(reflected <= 0.01 * AMPLITUDE, "reflected amplitude %.3g%% of the incident (limit 1%%)",
            100 * reflected / AMPLITUDE);
  cr_expect(transmitted >= 0.9 * AMPLITUDE, "the pulse did not cross into the local region (peak %.3g)",
            transmitted / AMPLITUDE);
  free(reference), free(coupled);
}

typedef struct {
  long every, steps;
  double first_max, last_max, overall_max;
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

/* 10^4 explicit steps of a short pulse (half-width 20 dx) in a free bar, local (horizon 0) in
 * its middle third and PD (3 dx) either side, so that the pulse crosses the two interfaces
 * 25 times and reflects at free ends that are peridynamic (a local node at a free surface is
 * not traction-free: docs/variable_horizon.md "Limits"). The coupled force is not the gradient
 * of the energy read (kinetic, PD and local 1/2 sigma : eps), so that energy is not conserved
 * exactly; the coupling's error for the pulse is of the order of its reflection (<= 1%, as in
 * test_horizon_pulse.c): asserted within 1% of the initial, and no growth, the largest over the
 * last tenth at most 1.001 times that over the first tenth (an unstable coupling grows by
 * orders of magnitude in such a run). */
Test(local_coupling, energy_bounded, .init = one_thread) {
  const double w = 0.02, length = 30 * w;
  char field[128];
  snprintf(field, sizeof field, "abs(x - %.17g) < %.17g ? 0 : 0.003", 0.5 * length, length / 6);
  peri_sim s;
  build_pulse(&s, field, length, 7.5 * w, w, 10000);
  const double e0 = peri_kinetic_energy(&s) + peri_strain_energy(&s);
  energy_log log = {50, s.solver.steps, 0.0, 0.0, 0.0};
  cr_assert_eq(peri_solve_explicit(&s, record_energy, &log), 0);
  const double crossings = s.solver.steps * s.solver.dt * sqrt(E_MOD / RHO) / (length / 3);
  cr_log_info("energy / initial: first tenth %.6f, last tenth %.6f, the run %.6f (%.0f interface crossings)",
              log.first_max / e0, log.last_max / e0, log.overall_max / e0, crossings);
  cr_expect(log.overall_max <= 1.01 * e0, "energy grew to %.4f of the initial", log.overall_max / e0);
  cr_expect(log.last_max <= 1.001 * log.first_max, "energy grows: last tenth %.6f, first tenth %.6f", log.last_max / e0,
            log.first_max / e0);
  peri_sim_free(&s);
}

/* A bar that is local everywhere (horizon 0): the pulse moves at sqrt(E/rho). The centroid
 * sum x u / sum u of a right-going pulse moves at d omega / dk at k = 0, which the stencil's
 * dispersion does not change (omega = c k (1 - O((k dx)^2)) for a consistent gradient, and
 * the leapfrog's omega = (2/dt) asin(omega dt / 2) has the same slope at 0): asserted within
 * 0.2% of sqrt(E/rho) (a modulus 1% off fails it). The peak moves at the group velocity of
 * the pulse's wavenumbers, slower by the stencil's dispersion: with the gradient weights
 * w1 : w2 = 1 : 1/4 of the 2 dx stencil (beta V / |xi|, the node at 2 dx with the partial
 * volume 1/2 of the linear rule), omega / (c k) = (sin(k dx) + sin(2 k dx) / 2) / (2 k dx)
 * = 1 - 5 (k dx)^2 / 12 + ..., so the group velocity is 1 - 5 (k dx)^2 / 4; the pulse
 * exp(-(x/w)^2) has its energy at k ~ sqrt(2)/w (k dx = 0.035 for w = 40 dx): 0.16% slower,
 * asserted below c and within 0.5% of it. */
Test(local_coupling, local_wave_speed, .init = one_thread) {
  const double w = 0.04, length = 1.0, x0 = 0.3, c = sqrt(E_MOD / RHO);
  peri_sim s;
  build_pulse(&s, "0 * x", length, x0, w, 1);
  cr_assert_eq(s.disc.horizon_field->n_local, s.disc.p.n);
  const long steps = (long)ceil(0.4 / c / s.solver.dt);
  s.solver.steps = steps;
  cr_assert_eq(peri_solve_explicit(&s, NULL, NULL), 0);
  const double t = steps * s.solver.dt;
  double sum_u = 0.0, sum_xu = 0.0, peak = 0.0;
  int32_t at = 0;
  for (int32_t i = 0; i < s.disc.p.n; ++i) {
    const double u = s.disc.p.u[3 * i], x = s.disc.p.x[3 * i];
    sum_u += u, sum_xu += x * u;
    if (u > peak) peak = u, at = i;
  }
  /* the peak by the parabola through the largest value and its two neighbours (the nodes
   * are in space-filling-curve order: find them by position) */
  double um = 0.0, up = 0.0;
  for (int32_t i = 0; i < s.disc.p.n; ++i) {
    if (fabs(s.disc.p.x[3 * i] - (s.disc.p.x[3 * at] - DX)) < 1e-9) um = s.disc.p.u[3 * i];
    if (fabs(s.disc.p.x[3 * i] - (s.disc.p.x[3 * at] + DX)) < 1e-9) up = s.disc.p.u[3 * i];
  }
  const double x_peak = s.disc.p.x[3 * at] + 0.5 * DX * (um - up) / (um - 2.0 * peak + up);
  const double c_centroid = (sum_xu / sum_u - x0) / t, c_peak = (x_peak - x0) / t;
  cr_log_info("local bar: centroid speed / sqrt(E/rho) %.6f, peak speed %.6f (t %.3g s, %ld steps)", c_centroid / c,
              c_peak / c, t, steps);
  cr_expect(fabs(c_centroid / c - 1.0) <= 2e-3, "centroid speed %.5f of sqrt(E/rho)", c_centroid / c);
  cr_expect(c_peak < c && c_peak >= 0.995 * c, "peak speed %.5f of sqrt(E/rho), expected in [0.995, 1)", c_peak / c);
  peri_sim_free(&s);
}

/* ---------------------------------------------------------------- quasi-static solves */

/* Solves the deck (adr or dynamic_relaxation) and returns the iterations; asserts convergence. */
static long solve_static(peri_sim *s, const char *deck, const char *what) {
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  cr_assert_gt(s->disc.horizon_field->n_local, 0);
  peri_apply_initial_conditions(s);
  cr_assert_eq(peri_solve_quasi_static(s, NULL, NULL), 0, "%s did not converge", what);
  return s->solver.qs.iterations;
}

/* A bar 0.25 m long, local (horizon 0) within 0.075 m of each end and PD (3 dx) between, held
 * on its first three nodes and pulled by a traction T on its last node, solved by adr and by
 * dynamic_relaxation. The local nodes' force is variational there (-dU/du of their energy), and
 * the PD and partial-stress forces in between pass the patch test, so the axial force in every
 * cross-section away from the ends is T A and the strain there is T / E: asserted over the span
 * from 20 dx to L - 20 dx, which crosses both interfaces, within 1e-6 (the residual forces on
 * one side of a section, at the tolerance 1e-8 of the load, sum to at most sqrt(n) 1e-8 =
 * 1.6e-7 of it; eps = 1e-3, since the rounding of the PD stretch at positions ~0.1 m leaves a
 * residual floor of about 3e-8 at eps = 1.4e-5, the same without local nodes). The ends carry a boundary
 * layer of the stencil's width (2 dx) whose displacement is of the order of eps dx: the end
 * displacement is T (L - x_h) / E, x_h the last held node, within 2 dx / L = 0.8%. */
static void check_bar_end_load(const char *solver) {
  const double length = 0.25, traction = 7.0e7, eps = traction / E_MOD; /* eps = 1e-3 */
  char deck[2048];
  snprintf(deck, sizeof deck,
           "dimension: 1\n"
           "materials:\n  bar: {model: pmb, density: %g, youngs_modulus: %.17g}\n"
           "discretization:\n  spacing: %g\n  horizon: \"abs(x - 0.125) < 0.05 ? 0.003 : 0\"\n"
           "  fill: [{shape: box, min: [0.0], max: [%g]}]\n"
           "regions:\n  held: {shape: box, min: [0.0], max: [0.003]}\n"
           "  pulled: {shape: box, min: [0.249], max: [0.25]}\n"
           "boundary_conditions:\n  - {type: displacement, region: held, x: 0}\n"
           "  - {type: traction, region: pulled, x: %g}\n"
           "solver: {type: %s, end_time: 1, load_steps: 1, tolerance: 1e-8, max_iterations: 50000, max_cutbacks: 0, "
           "breaking: false}\n"
           "output: {picture: false}\n",
           RHO, E_MOD, DX, length, traction, solver);
  peri_sim s;
  const long iterations = solve_static(&s, deck, solver);
  double ua = NAN, ub = NAN, end = NAN;
  const double xa = 20.5 * DX, xb = length - 19.5 * DX, x_held = 2.5 * DX;
  for (int32_t i = 0; i < s.disc.p.n; ++i) {
    const double x = s.disc.p.x[3 * i], u = s.disc.p.u[3 * i];
    if (fabs(x - xa) < 1e-9) ua = u;
    if (fabs(x - xb) < 1e-9) ub = u;
    if (fabs(x - (length - 0.5 * DX)) < 1e-9) end = u;
  }
  const double strain = (ub - ua) / (xb - xa), end_expected = eps * (length - 0.5 * DX - x_held);
  cr_log_info("bar, local ends, end load, %s: %ld iterations; strain over [20 dx, L - 20 dx] / (T/E) - 1 = %.2e, "
              "end displacement / (T (L - x_h) / E) - 1 = %.2e", solver, iterations, strain / eps - 1.0,
              end / end_expected - 1.0);
  cr_expect(fabs(strain / eps - 1.0) <= 1e-6, "%s: interior strain %.8g of T/E", solver, strain / eps);
  cr_expect(fabs(end / end_expected - 1.0) <= 2.0 * DX / length, "%s: end displacement %.6g of T (L - x_h)/E",
            solver, end / end_expected);
  peri_sim_free(&s);
}

Test(local_coupling, bar_end_load_adr, .init = one_thread) { check_bar_end_load("adr"); }
/* damping: twice the lowest angular frequency of the held-free bar, pi c / (2 L) */
Test(local_coupling, bar_end_load_dr, .init = one_thread) { check_bar_end_load("dynamic_relaxation, damping: 6.4e4"); }

/* Plane stress plates of 24 x 12 mm (24 x 24 with the PD square) whose outer parts are held at
 * the exact displacement of a homogeneous strain, so the solution is that strain at every node
 * and the solve must reach it: max |u - u_exact| <= 1e-8 of eps L/2 (tolerance 1e-10).
 *   - tension: u = (eps x, -nu eps y) (nu = 1/3, the PMB plane stress value), local
 *     everywhere, held on the 4 dx at each end, the top and bottom edges free: the variational
 *     local force leaves a free edge traction-free under this state (the divergence of the
 *     collocated stress did not, and converged to another state);
 *   - dilatation u = eps (x, y), PD (3 dx) in the square |x|, |y| < 4 mm, local around it, held
 *     on the outer 4 dx: the partial-stress coupling and the PD square inside. */
static void check_plate(const char *solver, bool pd_square) {
  const double eps = 1e-4;
  char deck[4096];
  const char *held_u = pd_square ? "x: \"1e-4 * x * t\", y: \"1e-4 * y * t\""
                                 : "x: \"1e-4 * x * t\", y: \"-1e-4 / 3 * y * t\"";
  const double half_y = pd_square ? 0.012 : 0.006;
  char ring[1024] = "";
  if (pd_square)
    snprintf(ring, sizeof ring,
             "  bottom: {shape: box, min: [-0.012, -0.012], max: [0.012, -0.008]}\n"
             "  top: {shape: box, min: [-0.012, 0.008], max: [0.012, 0.012]}\n");
  snprintf(deck, sizeof deck,
           "dimension: 2\nplane: stress\n"
           "materials:\n  plate: {model: pmb, density: %g, youngs_modulus: %.17g}\n"
           "discretization:\n  spacing: %g\n  thickness: 1.0e-3\n  horizon: \"%s\"\n"
           "  fill: [{shape: box, min: [-0.012, %g], max: [0.012, %g]}]\n"
           "regions:\n  left: {shape: box, min: [-0.012, -0.012], max: [-0.008, 0.012]}\n"
           "  right: {shape: box, min: [0.008, -0.012], max: [0.012, 0.012]}\n%s"
           "boundary_conditions:\n  - {type: displacement, region: left, %s}\n"
           "  - {type: displacement, region: right, %s}\n%s%s"
           "solver: {type: %s, end_time: 1, load_steps: 1, tolerance: 1e-10, max_iterations: 200000, breaking: false}\n"
           "output: {picture: false}\n",
           RHO, E_MOD, DX, pd_square ? "abs(x) < 0.004 && abs(y) < 0.004 ? 0.003 : 0" : "0 * x", -half_y, half_y,
           ring, held_u, held_u, pd_square ? "  - {type: displacement, region: bottom, " : "",
           pd_square ? "x: \"1e-4 * x * t\", y: \"1e-4 * y * t\"}\n  - {type: displacement, region: top, x: \"1e-4 * x "
                       "* t\", y: \"1e-4 * y * t\"}\n" : "",
           solver);
  peri_sim s;
  const long iterations = solve_static(&s, deck, solver);
  const double nu_y = pd_square ? 1.0 : -1.0 / 3.0;
  double worst = 0.0;
  int pd = 0;
  for (int32_t i = 0; i < s.disc.p.n; ++i) {
    const double *x = &s.disc.p.x[3 * i], *u = &s.disc.p.u[3 * i];
    worst = fmax(worst, hypot(u[0] - eps * x[0], u[1] - nu_y * eps * x[1]));
    pd += !s.disc.horizon_field->local[i];
  }
  worst /= eps * 0.012;
  cr_log_info("plate, %s, %s: %ld iterations, max |u - u_exact| / (eps L/2) = %.2e (%d PD nodes)",
              pd_square ? "dilatation, PD square" : "tension, free local edges", solver, iterations, worst, pd);
  cr_assert_eq(pd > 0, pd_square, "the PD square is missing or a local plate has PD nodes");
  cr_expect(worst <= 1e-8, "%s: |u - u_exact| reaches %.3g of eps L/2", solver, worst);
  peri_sim_free(&s);
}

Test(local_coupling, plate_tension_adr, .init = one_thread) { check_plate("adr", false); }
Test(local_coupling, plate_pd_square_adr, .init = one_thread) { check_plate("adr", true); }
/* damping: twice the lowest angular frequency of the held plate, about pi c / (16 mm) */
Test(local_coupling, plate_tension_dr, .init = one_thread) { check_plate("dynamic_relaxation, damping: 2e6", false); }
Test(local_coupling, plate_pd_square_dr, .init = one_thread) { check_plate("dynamic_relaxation, damping: 2e6", true); }

/* ---------------------------------------------------------------- a free local end */

typedef struct {
  int32_t end;    /* the node at the free end */
  double largest; /* the largest u there so far */
} end_log;

static int record_end(peri_sim *s, void *ctx) {
  end_log *log = ctx;
  log->largest = fmax(log->largest, s->disc.p.u[3 * log->end]);
  return 0;
}

/* A bar 0.6 m long, PD (3 dx) for x < 0.2 and local beyond, to a free local end at x = 0.6: a
 * right-going Gaussian pulse (half-width 40 dx) from x = 0.35 reflects there. At a free end the
 * displacement doubles as the pulse arrives and the pulse returns with the same sign (the
 * traction-free condition: u = f(x - ct) + f(2L - x - ct)). Asserted: the largest u at the end
 * within 1% of 2A (the stencil's dispersion at k dx ~ sqrt(2)/40 moves the pulse by 0.16% of
 * its travel, 0.4 mm against w = 40 mm, which changes the sum by about (0.4/40)^2), and when
 * the reflected pulse is centred at x = 0.4 its peak within 2% of A and no inverted lobe (u
 * nowhere below -1% of A). The collocated divergence at a free local end returned -0.09 A at
 * the end with an inverted lobe of -0.27 A. */
Test(local_coupling, free_local_end_reflection, .init = one_thread) {
  const double w = 0.04, length = 0.6, x0 = 0.35, c = sqrt(E_MOD / RHO);
  peri_sim s;
  build_pulse(&s, "x < 0.2 ? 0.003 : 0", length, x0, w, 1);
  end_log log = {-1, -INFINITY};
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    if (fabs(s.disc.p.x[3 * i] - (length - 0.5 * DX)) < 1e-9) log.end = i;
  cr_assert_geq(log.end, 0);
  cr_assert(s.disc.horizon_field->local[log.end]);
  s.solver.steps = (long)ceil((2.0 * length - 0.4 - x0) / c / s.solver.dt);
  cr_assert_eq(peri_solve_explicit(&s, record_end, &log), 0);
  double peak = -INFINITY, lowest = INFINITY;
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    if (s.disc.p.x[3 * i] > 0.25) peak = fmax(peak, s.disc.p.u[3 * i]), lowest = fmin(lowest, s.disc.p.u[3 * i]);
  cr_log_info("free local end: largest u at the end / A %.4f (2 expected), reflected peak / A %.4f, lowest u / A %.2e",
              log.largest / AMPLITUDE, peak / AMPLITUDE, lowest / AMPLITUDE);
  cr_expect(fabs(log.largest / (2.0 * AMPLITUDE) - 1.0) <= 0.01, "the free end reached %.4f A, not 2 A",
            log.largest / AMPLITUDE);
  cr_expect(fabs(peak / AMPLITUDE - 1.0) <= 0.02, "reflected peak %.4f A", peak / AMPLITUDE);
  cr_expect(lowest >= -0.01 * AMPLITUDE, "an inverted lobe of %.3f A after the reflection", lowest / AMPLITUDE);
  peri_sim_free(&s);
}
