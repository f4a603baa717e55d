/* The implicit solver (Newton + PETSc, docs/solvers.md):
 *  - uniform tension of a 1D bar (PMB and LPS) and of a 2D plate (plane stress, PMB): the
 *    elongation of a gauge in the bulk is F L / (E A) within 2%, as with the other
 *    quasi-static solvers (tests/verification/test_quasistatic.c); the LPS plate, whose free
 *    edges stiffen it, equals the nlcg solution;
 *  - Newton converges quadratically on a geometrically nonlinear problem (a PMB plate
 *    whose end is rotated by 0.6 rad and stretched by 20%), with exact linear solves (LU):
 *    in the asymptotic range the relative residuals obey rho_{k+1} <= C rho_k^2;
 *  - adr, nlcg and implicit agree on the small plate with a hole: the maximum von Mises
 *    stress within 1% (the solvers solve the same discrete equations to 1e-8);
 *  - through fracture (a pre-cracked plate torn apart in load steps) implicit and nlcg break
 *    the same bonds at every load step. */
#include <criterion/criterion.h>
#include <math.h>
#include <time.h>
#include "peri/damage.h"
#include "peri/energies.h"
#include "peri/implicit.h"
#include "peri/probe.h"
#include "peri/quasistatic.h"
#include "peri/setup.h"
#include "support.h"

static double wall(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* Mean x-displacement of the nodes within dx/2 of the plane x = x0. */
static double section_u(const peri_sim *s, double x0) {
  double sum = 0.0;
  int count = 0;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    if (fabs(s->disc.p.x[3 * i] - x0) < 0.5 * s->disc.geom.spacing + 1e-12) sum += s->disc.p.u[3 * i], ++count;
  return count ? sum / count : NAN;
}

static void solve_deck(peri_sim *s, const char *deck, double *seconds) {
  cr_assert_eq(sim_from_string(s, deck), 0);
  peri_apply_initial_conditions(s);
  double t0 = wall();
  cr_assert_eq(peri_solve_quasi_static(s, NULL, NULL), 0, "implicit did not converge");
  *seconds = wall() - t0;
}

/* The bar of test_quasistatic.c: 1 m, A = 0.01 m^2, E = 200 GPa, 2 MN on the end layer. */
static const char *bar1d =
    "dimension: 1\n"
    "materials:\n"
    "  steel: {model: %s, density: 7850, youngs_modulus: 200e9%s}\n"
    "discretization: {spacing: 0.005, m: 3, cross_section: 0.01, fill: [{shape: interval, min: [0], max: [1]}]}\n"
    "regions:\n"
    "  held: {shape: interval, min: [-1], max: [0.005]}\n"
    "  pulled: {shape: interval, min: [0.995], max: [2]}\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: held, x: 0}\n"
    "  - {type: traction, region: pulled, x: 2.0e8, layer: 0.005}\n"
    "solver: {type: implicit%s}\n"
    "output: {picture: false}\n";

static void check_tension_1d(const char *model, const char *nu, const char *extra) {
  char deck[2048];
  snprintf(deck, sizeof deck, bar1d, model, nu, extra);
  peri_sim s;
  double seconds;
  solve_deck(&s, deck, &seconds);
  const double dx = 0.005, expected = 2.0e6 * 1.0 / (200e9 * 0.01);
  const double xa = 0.25 + 0.5 * dx, xb = 0.75 + 0.5 * dx;
  const double dl = (section_u(&s, xb) - section_u(&s, xa)) / (xb - xa);
  const double end = section_u(&s, 1.0 - 0.5 * dx);
  cr_log_info("implicit 1D %s%s: Delta l %.6g mm (gauge, %.3f%%), end %.6g mm (%.3f%%); %ld Newton, %ld Krylov "
              "iterations, residual %.2g, %.3f s", model, extra, dl * 1e3, 100 * (dl / expected - 1), end * 1e3,
              100 * (end / expected - 1), s.solver.qs.iterations, s.solver.qs.linear_iterations, s.solver.qs.residual, seconds);
  cr_expect(fabs(dl / expected - 1.0) < 0.02, "%s: gauge Delta l = %g m, FL/(EA) = %g m", model, dl, expected);
  cr_expect(fabs(end / expected - 1.0) < 0.02, "%s: end displacement %g m, FL/(EA) = %g m", model, end, expected);
  cr_expect(s.solver.qs.residual <= s.solver.qs.tolerance);
  peri_sim_free(&s);
}

Test(implicit, tension_1d_pmb) { check_tension_1d("pmb", "", ""); }
Test(implicit, tension_1d_lps) { check_tension_1d("lps", ", poisson_ratio: 0.3", ""); }
Test(implicit, tension_1d_pmb_gmres_jacobi) {
  check_tension_1d("pmb", "", ", linear_solver: gmres, petsc_preconditioner: jacobi");
}
Test(implicit, tension_1d_lps_direct) { check_tension_1d("lps", ", poisson_ratio: 0.3", ", linear_solver: direct"); }

/* 2D plate 0.1 x 0.04 m, plane stress, 1 mm thick, E = 70 GPa, 10 MPa pulling the right
 * band (3 mm deep), the left band held in x, the middle node row held in y (no rigid
 * motion, free lateral contraction). The stress is uniaxial, sigma_xx = 10 MPa, so the mean
 * displacement of two node columns 50 mm apart differs by 50 mm sigma / E, within 2%.
 * PMB at m = 4 (dx = 0.75 mm): the quadrature error of the bond sums is below 1% from m = 4
 * on (at m = 3 the plate is 2.8% stiff). LPS has, in addition, the skin effect of the free
 * edges y = 0, 0.04 (the plate is ~3% stiffer than E, docs/solvers.md): there the reference
 * is the same discrete problem solved by nlcg, within 1e-4. */
static const char *plate2d =
    "dimension: 2\n"
    "plane: stress\n"
    "materials:\n"
    "  al: {model: %s, density: 2700, youngs_modulus: 70e9%s}\n"
    "discretization:\n"
    "  spacing: %g\n"
    "  m: %d\n"
    "  thickness: 1e-3\n"
    "  fill: [{shape: rectangle, min: [0, 0], max: [0.1, 0.04]}]\n"
    "regions:\n"
    "  held: {shape: rectangle, min: [-1, -1], max: [0.003, 1]}\n"
    "  mid_row: {shape: rectangle, min: [-1, 0.0195], max: [1, 0.0205]}\n"
    "  pulled: {shape: rectangle, min: [0.097, -1], max: [1, 1]}\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: held, x: 0}\n"
    "  - {type: displacement, region: mid_row, y: 0}\n"
    "  - {type: traction, region: pulled, x: 1.0e7, layer: 3e-3}\n"
    "solver: {type: %s, breaking: false}\n"
    "output: {picture: false}\n";

/* Gauge strain between the node columns at x = 25 and 75 mm (cell centres (k + 1/2) dx). */
static double plate_strain(const char *model, const char *nu, double dx, int m, const char *solver, long *its) {
  char deck[2048];
  snprintf(deck, sizeof deck, plate2d, model, nu, dx, m, solver);
  peri_sim s;
  double seconds;
  solve_deck(&s, deck, &seconds);
  const double xa = (floor(0.025 / dx) + 0.5) * dx, xb = (floor(0.075 / dx) + 0.5) * dx;
  const double measured = (section_u(&s, xb) - section_u(&s, xa)) / (xb - xa), strain = 1.0e7 / 70e9;
  cr_log_info("2D %s %s m = %d: gauge strain %.6g (sigma/E = %.6g, %.3f%%); %ld iterations (%ld Krylov), %.3f s",
              model, solver, m, measured, strain, 100 * (measured / strain - 1), s.solver.qs.iterations,
              s.solver.qs.linear_iterations, seconds);
  *its = s.solver.qs.iterations;
  peri_sim_free(&s);
  return measured;
}

Test(implicit, tension_2d_pmb) {
  long its;
  const double strain = plate_strain("pmb", "", 0.75e-3, 4, "implicit", &its), expected = 1.0e7 / 70e9;
  cr_expect(fabs(strain / expected - 1.0) < 0.02, "gauge strain %g, sigma/E = %g", strain, expected);
}

Test(implicit, tension_2d_lps_agrees_with_nlcg) {
  long its_implicit, its_nlcg;
  const double a = plate_strain("lps", ", poisson_ratio: 0.3", 1e-3, 3, "implicit", &its_implicit);
  const double b = plate_strain("lps", ", poisson_ratio: 0.3", 1e-3, 3, "nlcg", &its_nlcg);
  cr_expect(fabs(a / b - 1.0) < 1e-4, "gauge strain: implicit %g, nlcg %g", a, b);
  cr_expect(its_implicit < its_nlcg / 10, "Newton took %ld iterations, nlcg %ld", its_implicit, its_nlcg);
}

/* Geometric nonlinearity: a PMB plate 30 x 10 mm, the left band held, whose right band is
 * moved to y = R(0.6 t) [(1 + 0.2 t) x, y - 5 mm] + [0, 5 mm] (stretched by 20% and turned
 * by 0.6 rad about the middle of the held end) in 2 load steps. With LU the linear solves are exact, so Newton's local
 * convergence is quadratic: rho_{k+1} <= C rho_k^2 once rho_k is small (here below 0.1)
 * and while rho_{k+1} is above round-off (1e-13). C is set from the problem's scale: the
 * ratio of the second to the first derivative of the force times the displacement, which
 * for a stretch of 20% is O(1); 10 allows for the line search and the boundary layer. */
static const char *rotate2d =
    "dimension: 2\n"
    "plane: stress\n"
    "materials:\n"
    "  m: {model: pmb, density: 1000, youngs_modulus: 1e9}\n"
    "discretization: {spacing: 1e-3, m: 3, fill: [{shape: rectangle, min: [0, 0], max: [0.03, 0.01]}]}\n"
    "regions:\n"
    "  held: {shape: rectangle, min: [-1, -1], max: [0.003, 1]}\n"
    "  turned: {shape: rectangle, min: [0.027, -1], max: [1, 1]}\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: held, x: 0, y: 0}\n"
    "  - {type: displacement, region: turned,\n"
    "     x: \"cos(0.6*t)*(1 + 0.2*t)*x - sin(0.6*t)*(y - 0.005) - x\",\n"
    "     y: \"sin(0.6*t)*(1 + 0.2*t)*x + cos(0.6*t)*(y - 0.005) + 0.005 - y\"}\n"
    "solver: {type: implicit, load_steps: 2, linear_solver: direct, tolerance: 1e-12, breaking: false}\n"
    "output: {picture: false}\n";

Test(implicit, newton_quadratic) {
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, rotate2d), 0);
  peri_apply_initial_conditions(&s);
  /* first load step through the driver, the second by hand to read its residual history */
  s.solver.qs.load_steps = 1;
  s.solver.end_time = 0.5;
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0);
  peri_qs_apply_loading(&s, 1.0);
  cr_assert_eq(peri_solve_equilibrium(&s), PERI_QS_CONVERGED, "residual %g", s.solver.qs.residual);
  double rho[64];
  const int n = peri_implicit_residual_history(rho, 64);
  cr_assert(n >= 3 && n <= 64, "%d Newton iterations", n);
  /* the end turned by 0.6 rad: the largest displacement is about 0.6 x 0.03 m */
  double umax = 0.0;
  for (int32_t i = 0; i < s.disc.p.n; ++i) umax = fmax(umax, hypot(s.disc.p.u[3 * i], s.disc.p.u[3 * i + 1]));
  int pairs = 0;
  double worst = 0.0;
  for (int k = 0; k + 1 < n; ++k) {
    cr_log_info("Newton %d: relative residual %.3e", k, rho[k]);
    if (rho[k] < 0.1 && rho[k + 1] > 1e-13) {
      ++pairs;
      worst = fmax(worst, rho[k + 1] / (rho[k] * rho[k]));
    }
  }
  cr_log_info("Newton %d: relative residual %.3e; %d asymptotic pairs, max rho_{k+1}/rho_k^2 = %.3g; max |u| %.4g m",
              n - 1, rho[n - 1], pairs, worst, umax);
  cr_expect(umax > 0.015, "the end did not turn: max |u| = %g m", umax);
  cr_expect(pairs >= 2, "only %d iterations in the asymptotic range", pairs);
  cr_expect(worst < 10.0, "rho_{k+1} / rho_k^2 reached %g: not quadratic", worst);
  peri_sim_free(&s);
}

/* The plate with a hole of test_stress.c (delta = 3 mm, m = 3, 4684 nodes). */
static double plate_max_von_mises(const char *solver, long *iterations, double *seconds) {
  char type[64];
  snprintf(type, sizeof type, "solver.type=%s", solver);
  const char *sets[] = {"discretization.horizon=3e-3", "discretization.spacing=1e-3", "regions.left_edge.max=[0.003, 1]",
                        "regions.right_edge.min=[0.097, -1]", "boundary_conditions.1.layer=3e-3", type};
  peri_sim s;
  cr_assert_eq(peri_sim_from_deck_with(&s, "examples/plate_with_hole.yaml", 6, sets), 0);
  peri_apply_initial_conditions(&s);
  double t0 = wall();
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0, "%s: not converged", solver);
  *seconds = wall() - t0;
  *iterations = s.solver.qs.iterations;
  double vm = NAN;
  cr_assert_eq(peri_probe(&s, "max_von_mises", &vm), 0);
  if (s.solver.kind == PERI_SOLVER_IMPLICIT)
    cr_log_info("plate with hole, implicit: %ld Newton, %ld Krylov iterations", s.solver.qs.iterations,
                s.solver.qs.linear_iterations);
  peri_sim_free(&s);
  return vm;
}

Test(implicit, plate_with_hole_three_solvers_agree) {
  const char *solvers[] = {"implicit", "nlcg", "adr"};
  double vm[3], sec[3];
  long it[3];
  for (int k = 0; k < 3; ++k) vm[k] = plate_max_von_mises(solvers[k], &it[k], &sec[k]);
  cr_log_info("plate with hole: max von Mises implicit %.8g (%ld it, %.2f s), nlcg %.8g (%ld it, %.2f s), adr %.8g "
              "(%ld it, %.2f s)", vm[0], it[0], sec[0], vm[1], it[1], sec[1], vm[2], it[2], sec[2]);
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      cr_expect(fabs(vm[a] / vm[b] - 1) < 0.01, "max von Mises: %s %g, %s %g", solvers[a], vm[a], solvers[b], vm[b]);
}

/* Fracture through load steps: a small LPS glass plate (16 x 10 mm, 1 mm spacing) with an
 * edge pre-crack, opened by a displacement of its top band in 4 load steps, breaks into
 * pieces. Solved to the same tolerance, implicit and nlcg break the same bonds at every step
 * and give the same reaction (to 1e-5 of its peak: both solve to a relative residual 1e-8,
 * with the condition number of the cracked plate). */
static const char *crack2d =
    "dimension: 2\n"
    "plane: stress\n"
    "materials:\n"
    "  glass: {model: lps, density: 2440, youngs_modulus: 72.0e9, poisson_ratio: 0.22, fracture_energy: 3.8}\n"
    "discretization: {spacing: 1.0e-3, m: 3, thickness: 1.0e-3, fill: [{shape: rectangle, min: [0, 0], max: [0.016, 0.010]}]}\n"
    "precracks: [{from: [-0.001, 0.005], to: [0.007, 0.005]}]\n"
    "regions:\n"
    "  top: {shape: rectangle, min: [-0.001, 0.007], max: [0.017, 0.011]}\n"
    "  bottom: {shape: rectangle, min: [-0.001, -0.001], max: [0.017, 0.003]}\n"
    "boundary_conditions:\n"
    "  - {type: displacement, region: top, y: \"1.2e-5*t\"}\n"
    "  - {type: displacement, region: bottom, x: 0, y: 0}\n"
    "solver: {type: %s, load_steps: 4}\n"
    "output: {picture: false}\n";

typedef struct crack_path {
  long broken[8];
  double reaction[8];
  int steps;
} crack_path;

static int record_step(peri_sim *s, void *ctx) {
  crack_path *c = ctx;
  double r[3];
  peri_region_reaction(s, 1, r); /* regions in deck order after the whole body: 1 is top */
  if (c->steps < 8) c->broken[c->steps] = peri_broken_count(&s->disc.bonds), c->reaction[c->steps] = r[1];
  c->steps++;
  return 0;
}

static crack_path crack(const char *solver) {
  char deck[2048];
  snprintf(deck, sizeof deck, crack2d, solver);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  peri_apply_initial_conditions(&s);
  crack_path c = {0};
  double t0 = wall();
  cr_assert_eq(peri_solve_quasi_static(&s, record_step, &c), 0, "%s: not converged", solver);
  cr_log_info("crack %s: %ld solves, %ld iterations, %.2f s; broken %ld %ld %ld %ld, reaction %.6g %.6g %.6g %.6g N",
              solver, s.solver.qs.solves, s.solver.qs.iterations, wall() - t0, c.broken[0], c.broken[1], c.broken[2], c.broken[3],
              c.reaction[0], c.reaction[1], c.reaction[2], c.reaction[3]);
  peri_sim_free(&s);
  return c;
}

Test(implicit, fracture_2d_agrees_with_nlcg) {
  const crack_path a = crack("implicit"), b = crack("nlcg");
  cr_assert_eq(a.steps, 4);
  cr_assert_eq(b.steps, 4);
  double peak = 0.0;
  for (int k = 0; k < 4; ++k) peak = fmax(peak, fabs(b.reaction[k]));
  cr_assert(a.broken[3] > a.broken[0] && a.broken[0] > 0, "the crack did not grow");
  for (int k = 0; k < 4; ++k) {
    cr_expect_eq(a.broken[k], b.broken[k], "load step %d: implicit broke %ld bonds, nlcg %ld", k + 1, a.broken[k],
                 b.broken[k]);
    cr_expect(fabs(a.reaction[k] - b.reaction[k]) < 1e-5 * peak, "load step %d: reaction implicit %g, nlcg %g N",
              k + 1, a.reaction[k], b.reaction[k]);
  }
}
