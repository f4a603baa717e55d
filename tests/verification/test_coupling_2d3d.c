/* The 2D and 3D PD-FEM coupling (002_b20c318388227af9.txt §2.1-2.2, MODELS.md 14;
 * docs/coupling.md), bond-based PD at m = 3 joined to Q4 (plane stress and plane strain) or
 * Hex8 elements:
 *  - linear patch test: u = a + H x imposed on every node of a body with a PD block inside
 *    (the PD block at least delta inside the free surface, where the surface effect of PD
 *    would unbalance it) gives e_r at round-off (1e-13: sums of ~1e3..1e4 terms of relative rounding 1e-16), for
 *    the partial-volume rules linear and none; a quadratic field across the interface does
 *    not (e_r > 1e-6), which shows the check can fail;
 *  - the point-supported plate of Table 2.1 (24 x 34, dx = 1, delta = 3, E = 1, nu = 1/3, plane
 *    stress, F = 10 at the top centre, PD square of side 10 in the middle), solved: the
 *    reactions of the all-FEM and all-PD models sum to F_ext to round-off (1e-10 relative; the
 *    seed prints 9.9999 and 10.0000 with e_rel ~ 1e-13), and those of the coupled model to
 *    10.1425 within 1%. The seed computes the partial volumes by exact cell-disk
 *    intersection; this uses peri's default linear ramp (docs/coupling.md).
 *  - Exact partial volumes (partial_volume: exact; the cell-disk intersection of the seed's
 *    ref. [190]): the discrete nonlocal traction across a horizontal interface at
 *    x0 = (11.5, 24.125) (eq. A.34) for the fields of Table A.3 gives the correction factor
 *    gamma = t2 / tau2_num of Remark A.2, printed as 0.9784710341 (m = 3) and 0.9974762599
 *    (m = 8), to its 10 digits (t2 = 0.25 exactly: sigma_22 = E/(1 - nu^2) u2,y), tau1_num
 *    at round-off, and tau2_num of Table A.4 to its 3 printed digits;
 *  - with them and c scaled by gamma (eq. 2.39), the plate of §2.6.2 (dx = 0.25, delta = 0.75,
 *    PD square [8, 18] x [14, 24]) under the quadratic cap of Case II (Table 2.15) gives
 *    e_ry = 5.00e-4 (Table 2.16) and e_rx at round-off, and under the bilinear field over the
 *    lower right corner, Case III (Table 2.13, X1 = 14.75, X2 = 19.25), e_rx = 4.31e-3 (Table
 *    2.18); its e_ry vanishes up to the 10 printed digits of gamma (the straight parts of the
 *    interface balance a linear field only with the exact gamma), so 1e-9. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "peri/coupling.h"
#include "peri/energies.h"
#include "peri/quasistatic.h"
#include "peri/solver.h"
#include "peri/sim.h"
#include "support.h"

static void build(peri_sim *s, const char *deck) { cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck); }

/* e_r of an imposed field u(x) (a function of the position) */
typedef void (*field_fn)(const double *x, double *u);

static double imposed_ratio(peri_sim *s, field_fn f) {
  for (int32_t i = 0; i < s->disc.p.n; ++i) f(&s->disc.p.x[3 * (size_t)i], &s->disc.p.u[3 * (size_t)i]);
  peri_coupling_force(s);
  double net[3], ratio[4];
  peri_coupling_balance(s, net, ratio);
  return ratio[3];
}

static void linear2(const double *x, double *u) {
  u[0] = 0.1 + 0.01 * x[0] - 0.02 * x[1];
  u[1] = -0.2 + 0.005 * x[0] + 0.013 * x[1];
}

static void quadratic2(const double *x, double *u) {
  u[0] = 0.0;
  u[1] = 1e-3 * x[0] * x[0];
}

static void linear3(const double *x, double *u) {
  u[0] = 0.1 + 0.01 * x[0] - 0.02 * x[1] + 0.003 * x[2];
  u[1] = -0.2 + 0.005 * x[0] + 0.013 * x[1] - 0.007 * x[2];
  u[2] = 0.05 - 0.004 * x[0] + 0.002 * x[1] + 0.011 * x[2];
}

static void quadratic3(const double *x, double *u) {
  u[0] = 1e-3 * x[1] * x[1], u[1] = 0.0, u[2] = 0.0;
}

static const char *plate2d =
    "dimension: 2\n"
    "plane: %s\n"
    "materials: {plate: {model: pmb, density: 1, youngs_modulus: 1}}\n"
    "discretization: {spacing: 1, m: 3, thickness: 1, partial_volume: %s,\n"
    "                 fill: [{shape: rectangle, min: [-8.5, -10.5], max: [8.5, 10.5]}]}\n"
    "regions: {pd: {shape: rectangle, min: [-3.25, -2.25], max: [4.25, 5.25]}}\n"
    "coupling: {pd_region: pd}\n"
    "solver: {type: implicit, load_steps: 1}\n"
    "output: {picture: false}\n";

Test(coupling_2d3d, q4_linear_patch_test) {
  static const char *planes[] = {"stress", "strain"}, *rules[] = {"linear", "none"};
  for (int p = 0; p < 2; ++p)
    for (int r = 0; r < 2; ++r) {
      char deck[1024];
      snprintf(deck, sizeof deck, plate2d, planes[p], rules[r]);
      peri_sim s;
      build(&s, deck);
      cr_assert(s.coupling->n_pd > 0 && s.coupling->n_pd < s.disc.p.n);
      const double e_r = imposed_ratio(&s, linear2);
      cr_expect(e_r <= 1e-13, "plane %s, partial_volume %s: e_r %.3e", planes[p], rules[r], e_r);
      const double control = imposed_ratio(&s, quadratic2);
      cr_expect(control > 1e-6, "a quadratic field across the interface: e_r %.3e", control);
      peri_sim_free(&s);
    }
}

Test(coupling_2d3d, hex8_linear_patch_test) {
  const char *deck =
      "dimension: 3\n"
      "materials: {block: {model: pmb, density: 1, youngs_modulus: 1}}\n"
      "discretization: {spacing: 1, m: 3, fill: [{shape: box, min: [-6.5, -6.5, -6.5], max: [6.5, 6.5, 6.5]}]}\n"
      "regions: {pd: {shape: box, min: [-2.25, -1.25, -2.25], max: [2.25, 3.25, 1.25]}}\n"
      "coupling: {pd_region: pd}\n"
      "solver: {type: implicit, load_steps: 1}\n"
      "output: {picture: false}\n";
  peri_sim s;
  build(&s, deck);
  cr_assert_eq(s.coupling->corners, 8);
  const double e_r = imposed_ratio(&s, linear3);
  cr_expect(e_r <= 1e-13, "e_r %.3e", e_r);
  const double control = imposed_ratio(&s, quadratic3);
  cr_expect(control > 1e-6, "a quadratic field across the interface: e_r %.3e", control);
  peri_sim_free(&s);
}

/* Table 2.1: the sum of the vertical reactions at the two supports. */
static double table_2_1(const char *pd_region) {
  char deck[2048];
  snprintf(deck, sizeof deck,
           "dimension: 2\n"
           "plane: stress\n"
           "materials: {plate: {model: pmb, density: 1, youngs_modulus: 1}}\n"
           "discretization: {spacing: 1, m: 3, thickness: 1,\n"
           "                 fill: [{shape: rectangle, min: [-12.5, -17.5], max: [12.5, 17.5]}]}\n"
           "regions:\n"
           "  pd: {shape: rectangle, min: [-5.25, -5.25], max: [5.25, 5.25]}\n"
           "  left: {shape: rectangle, min: [-9.25, -17.25], max: [-8.75, -16.75]}\n"
           "  right: {shape: rectangle, min: [8.75, -17.25], max: [9.25, -16.75]}\n"
           "  middle: {shape: rectangle, min: [-0.25, -17.25], max: [0.25, -16.75]}\n"
           "  top: {shape: rectangle, min: [-0.25, 16.75], max: [0.25, 17.25]}\n"
           "  nowhere: {shape: rectangle, min: [100, 100], max: [101, 101]}\n" /* all FEM */
           "coupling: {pd_region: %s}\n"
           "boundary_conditions:\n"
           "  - {type: displacement, region: left, y: 0}\n"
           "  - {type: displacement, region: right, y: 0}\n"
           "  - {type: displacement, region: middle, x: 0}\n"
           "  - {type: body_force, region: top, y: -10}\n" /* V = 1: a point force of 10 */
           "solver: {type: implicit, load_steps: 1}\n"
           "output: {picture: false}\n",
           pd_region);
  peri_sim s;
  build(&s, deck);
  cr_assert_eq(s.disc.p.n, 875);
  peri_apply_initial_conditions(&s); /* marks the prescribed components */
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0, "pd_region %s: the solve failed", pd_region);
  double left[3], right[3];
  peri_region_reaction(&s, 2, left);
  peri_region_reaction(&s, 3, right);
  peri_sim_free(&s);
  return left[1] + right[1];
}

Test(coupling_2d3d, point_supported_plate_table_2_1) {
  const double fem = table_2_1("nowhere"), pd = table_2_1("all"), coupled = table_2_1("pd");
  cr_expect(fabs(fem - 10.0) <= 1e-10 * 10.0, "all FEM: sum of reactions %.15g", fem);
  cr_expect(fabs(pd - 10.0) <= 1e-10 * 10.0, "all PD: sum of reactions %.15g", pd);
  cr_expect(fabs(coupled - 10.1425) <= 0.01 * 10.1425, "coupled: sum of reactions %.6g, Table 2.1 10.1425", coupled);
  cr_expect(fabs(coupled - 10.0) > 1e-3, "the coupled model is out of balance");
}

/* got agrees with the printed value to its 3 significant digits */
static void expect_printed(double got, double printed, const char *what) {
  const double unit = pow(10.0, floor(log10(fabs(printed))) - 2);
  cr_expect(fabs(got - printed) <= 0.5 * unit + 1e-12 * fabs(printed), "%s: %.6e, printed %.2e", what, got, printed);
}

/* Table A.3 fields: linear u2 = d (y - Y1)/(YB - Y1) and the quadratic cap */
static void table_a3_linear(const double *x, double *u) { u[0] = 0.0, u[1] = 0.5 * (x[1] - 12.75) / (15.0 - 12.75); }
static void table_a3_quadratic(const double *x, double *u) {
  const double r2 = (x[0] - 11.5) * (x[0] - 11.5) + (x[1] - 23.0) * (x[1] - 23.0);
  u[0] = 0.0, u[1] = r2 <= 2.25 * 2.25 ? (2.25 * 2.25 - r2) / (15.0 * 15.0) : 0.0;
}

/* tau_num at x0 = (11.5, 24.125) on a patch of the lattice with PD nodes below y0 = 24.125,
 * with the discretization's partial-volume rule `rule` and the coupling options `options`
 * (partial volumes, gamma); *gamma: the rows' gamma */
static void traction_with(double m, const char *rule, const char *options, field_fn f, double tau[3],
                          double *gamma, double local[3]) {
  const double delta = 0.75, dx = delta / m, x0 = 11.5, y0 = 24.125;
  const int K = (int)m + 3;
  char deck[1024];
  snprintf(deck, sizeof deck,
           "dimension: 2\n"
           "plane: stress\n"
           "materials: {plate: {model: pmb, density: 1, youngs_modulus: 1}}\n"
           "discretization: {spacing: %.17g, horizon: %.17g, thickness: 1, partial_volume: %s,\n"
           "  fill: [{shape: rectangle, min: [%.17g, %.17g], max: [%.17g, %.17g]}]}\n"
           "regions: {pd: {shape: rectangle, min: [0, 0], max: [100, %.17g]}}\n"
           "coupling: {pd_region: pd, %s, tractions: {x0: {at: [%.17g, %.17g], normal: +y}}}\n"
           "solver: {type: implicit, load_steps: 1}\n"
           "output: {picture: false}\n",
           dx, delta, rule, x0 - (K + 0.5) * dx, y0 - K * dx, x0 + (K + 0.5) * dx, y0 + K * dx, y0, options, x0, y0);
  peri_sim s;
  build(&s, deck);
  for (int32_t i = 0; i < s.disc.p.n; ++i) f(&s.disc.p.x[3 * (size_t)i], &s.disc.p.u[3 * (size_t)i]);
  const double at[3] = {x0, y0, 0};
  peri_coupling_nonlocal_traction(&s, at, 1, +1, tau);
  if (gamma) *gamma = s.coupling->gamma;
  if (local) peri_coupling_local_traction(&s, &s.coupling->traction[0], local);
  peri_sim_free(&s);
}

static void traction_a34(double m, field_fn f, double tau[3], double local[3]) {
  traction_with(m, "linear", "partial_volume: exact", f, tau, NULL, local);
}

Test(coupling_2d3d, correction_factor_and_tractions_table_a_4) {
  static const struct {
    double m, gamma, linear, quadratic;
  } table[] = {{3, 0.9784710341, 2.56e-1, -1.22e-2}, {8, 0.9974762599, 2.51e-1, -1.19e-2}};
  for (int k = 0; k < 2; ++k) {
    double tau[3], t[3];
    traction_a34(table[k].m, table_a3_linear, tau, t);
    /* Table A.4's local traction t(x0, e2) = sigma e2 = -t(x0, -e2): 0 and E/(1 - nu^2) u2,y */
    cr_expect(fabs(t[0]) <= 1e-15 && fabs(-t[1] - 0.25) <= 1e-13, "m %g: linear t = (%.3e, %.15f), Table A.4 (0, 0.25)",
              table[k].m, -t[0], -t[1]);
    const double gamma = 0.25 / tau[1];
    cr_expect(fabs(gamma - table[k].gamma) <= 1e-10 * table[k].gamma, "m %g: gamma %.12f, Remark A.2 %.10f",
              table[k].m, gamma, table[k].gamma);
    cr_expect(fabs(tau[0]) <= 1e-15, "m %g: tau1 %.3e", table[k].m, tau[0]);
    expect_printed(tau[1], table[k].linear, "linear tau2_num (Table A.4)");
    traction_a34(table[k].m, table_a3_quadratic, tau, t);
    /* the stencil's differences are exact for the quadratic: u2,y = -2 (1.125) / 15^2, u2,x = 0 */
    cr_expect(fabs(t[0]) <= 1e-15 && fabs(-t[1] + 0.01125) <= 1e-14,
              "m %g: quadratic t = (%.3e, %.15f), analytic (0, -1.125e-2) (Table A.4 -1.12e-2)", table[k].m, -t[0], -t[1]);
    cr_expect(fabs(tau[0]) <= 1e-15, "m %g: quadratic tau1 %.3e", table[k].m, tau[0]);
    expect_printed(tau[1], table[k].quadratic, "quadratic tau2_num (Table A.4)");
  }
}

/* gamma: auto is Remark A.2's gamma for the family of the rows: with the exact partial volumes
 * the printed 0.9784710341 (m = 3) and 0.9974762599 (m = 8); with the discretization's partial
 * volumes (linear ramp, none) it makes the nonlocal traction of the linear field of Table A.3
 * the classical t2 = E/(1 - nu^2) u2,y = 0.25 (a sum over the bonds that cross the interface,
 * not the lattice sum gamma is computed from), which gamma = 1 misses by more than 1%. */
Test(coupling_2d3d, gamma_auto_is_remark_a2) {
  static const struct {
    double m, gamma;
  } printed[] = {{3, 0.9784710341}, {8, 0.9974762599}};
  for (int k = 0; k < 2; ++k) {
    double tau[3], gamma;
    traction_with(printed[k].m, "linear", "partial_volume: exact, gamma: auto", table_a3_linear, tau, &gamma, NULL);
    cr_expect(fabs(gamma - printed[k].gamma) <= 1e-10 * printed[k].gamma, "m %g: gamma auto %.12f, Remark A.2 %.10f",
              printed[k].m, gamma, printed[k].gamma);
    cr_expect(fabs(tau[1] - 0.25) <= 1e-9, "m %g, exact volumes: traction %.12f with gamma auto", printed[k].m, tau[1]);
  }
  static const char *const rules[] = {"linear", "none"};
  for (int k = 0; k < 2; ++k)
    for (double m = 3; m <= 4; ++m) {
      double tau[3], untouched[3], gamma;
      traction_with(m, rules[k], "gamma: auto", table_a3_linear, tau, &gamma, NULL);
      traction_with(m, rules[k], "gamma: 1", table_a3_linear, untouched, NULL, NULL);
      cr_expect(fabs(tau[1] - 0.25) <= 1e-12, "m %g, %s: traction %.15f with gamma auto %.10f", m, rules[k], tau[1],
                gamma);
      cr_expect(fabs(untouched[1] - 0.25) > 0.01 * 0.25, "m %g, %s: gamma = 1 gives the classical traction %.6f", m,
                rules[k], untouched[1]);
    }
}

/* The local traction of coupling.tractions (eq. 2.107's stencil in 2D and 3D) under a linear
 * field u = a + H x is -sigma n with sigma Hooke's stress of H, to round-off: plane strain
 * (nu = 1/4) at an interior point and at one on the body's edge (one-sided tangential
 * differences); 3D (nu = 1/4) at an interior point and at a corner of the body's faces. */
static void expect_hooke(const peri_sim *s, const double sigma[3][3], const char *what) {
  for (int k = 0; k < s->coupling->n_tractions; ++k) {
    const peri_interface_traction *tr = &s->coupling->traction[k];
    double t[3];
    peri_coupling_local_traction(s, tr, t);
    for (int r = 0; r < s->disc.geom.dim; ++r) {
      const double want = -tr->sign * sigma[r][tr->axis];
      cr_expect(fabs(t[r] - want) <= 1e-15, "%s, point %s: t_%d %.15e, Hooke %.15e", what, tr->name, r + 1, t[r], want);
    }
  }
}

Test(coupling_2d3d, local_traction_of_a_linear_field_is_hookes) {
  const double E = 1.0, nu = 0.25; /* PMB: nu = 1/4 in plane strain and 3D */
  char deck[1024];
  snprintf(deck, sizeof deck, plate2d, "strain", "linear");
  char *at = strstr(deck, "coupling: {pd_region: pd}");
  cr_assert_not_null(at);
  snprintf(at, sizeof deck - (size_t)(at - deck),
           "coupling: {pd_region: pd, tractions: {inside: {at: [4.5, 1], normal: +x}, edge: {at: [8, 5.5], "
           "normal: +y}}}\n"
           "solver: {type: implicit, load_steps: 1}\n"
           "output: {picture: false}\n");
  peri_sim s;
  build(&s, deck);
  cr_assert_eq(s.coupling->n_tractions, 2);
  cr_expect(s.coupling->traction[1].reach[0][0] > 0.0 && s.coupling->traction[1].reach[0][1] == 0.0,
            "the edge point is one-sided along x");
  for (int32_t i = 0; i < s.disc.p.n; ++i) linear2(&s.disc.p.x[3 * (size_t)i], &s.disc.p.u[3 * (size_t)i]);
  /* linear2: H = [[0.01, -0.02], [0.005, 0.013]]; plane strain */
  const double f = E / ((1 + nu) * (1 - 2 * nu)), exx = 0.01, eyy = 0.013, gxy = -0.02 + 0.005;
  const double sigma2[3][3] = {{f * ((1 - nu) * exx + nu * eyy), f * (1 - 2 * nu) / 2 * gxy, 0},
                               {f * (1 - 2 * nu) / 2 * gxy, f * (nu * exx + (1 - nu) * eyy), 0},
                               {0, 0, 0}};
  expect_hooke(&s, sigma2, "plane strain");
  peri_sim_free(&s);

  const char *deck3 =
      "dimension: 3\n"
      "materials: {block: {model: pmb, density: 1, youngs_modulus: 1}}\n"
      "discretization: {spacing: 1, m: 3, fill: [{shape: box, min: [-6.5, -6.5, -6.5], max: [6.5, 6.5, 6.5]}]}\n"
      "regions: {pd: {shape: box, min: [-2.25, -1.25, -2.25], max: [2.25, 3.25, 1.25]}}\n"
      "coupling: {pd_region: pd, tractions: {inside: {at: [0, 3.5, 0], normal: +y}, corner: {at: [-6, 5.5, 6],\n"
      "           normal: -y}}}\n"
      "solver: {type: implicit, load_steps: 1}\n"
      "output: {picture: false}\n";
  build(&s, deck3);
  const peri_interface_traction *corner = &s.coupling->traction[1];
  cr_expect(corner->reach[0][0] == 0.0 && corner->reach[0][1] > 0.0 && corner->reach[2][0] > 0.0 &&
                corner->reach[2][1] == 0.0,
            "the corner point is one-sided along x and z");
  for (int32_t i = 0; i < s.disc.p.n; ++i) linear3(&s.disc.p.x[3 * (size_t)i], &s.disc.p.u[3 * (size_t)i]);
  const double H[3][3] = {{0.01, -0.02, 0.003}, {0.005, 0.013, -0.007}, {-0.004, 0.002, 0.011}};
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu)), trace = 0.01 + 0.013 + 0.011;
  double sigma3[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) sigma3[r][c] = mu * (H[r][c] + H[c][r]) + (r == c ? lambda * trace : 0.0);
  expect_hooke(&s, sigma3, "3D");
  peri_sim_free(&s);
}

static const char *plate_2_6_2 =
    "dimension: 2\n"
    "plane: stress\n"
    "materials: {plate: {model: pmb, density: 1, youngs_modulus: 1}}\n"
    "discretization: {spacing: 0.25, m: 3, thickness: 1,\n"
    "                 fill: [{shape: rectangle, min: [-0.125, -0.125], max: [24.125, 34.125]}]}\n"
    "regions: {pd: {shape: rectangle, min: [7.9, 13.9], max: [18.1, 24.1]}}\n"
    "coupling: {pd_region: pd, partial_volume: exact, gamma: 0.9784710341}\n"
    "solver: {type: implicit, load_steps: 1}\n"
    "output: {picture: false}\n";

/* Case II (Table 2.15): the quadratic cap of radius 2.25 at (11.5, 15) on u2 */
static void case_2(const double *x, double *u) {
  const double r2 = (x[0] - 11.5) * (x[0] - 11.5) + (x[1] - 15.0) * (x[1] - 15.0);
  u[0] = 0.0, u[1] = r2 <= 2.25 * 2.25 ? (2.25 * 2.25 - r2) / (15.0 * 15.0) : 0.0;
}

/* Case III (Table 2.13): the bilinear tent on u2 over the lower right corner */
static void case_3(const double *x, double *u) {
  const double d = 0.5, X1 = 14.75, X2 = 19.25, Y1 = 12.75, Y2 = 17.25, YB = 15.0;
  u[0] = 0.0, u[1] = 0.0;
  if (x[0] <= X1 || x[0] >= X2) return;
  if (x[1] > Y1 && x[1] < YB) u[1] = d * (x[1] - Y1) / (YB - Y1);
  else if (x[1] >= YB && x[1] < Y2) u[1] = d * (1.0 - (x[1] - YB) / (Y2 - YB));
}

Test(coupling_2d3d, cases_2_and_3_tables_2_16_2_18) {
  peri_sim s;
  build(&s, plate_2_6_2);
  cr_assert_eq(s.disc.p.n, 97 * 137);
  double net[3], ratio[4];
  imposed_ratio(&s, case_2);
  peri_coupling_balance(&s, net, ratio);
  cr_expect(ratio[0] <= 1e-13, "Case II e_rx %.3e", ratio[0]);
  expect_printed(ratio[1], 5.00e-4, "Case II e_ry (Table 2.16)");
  imposed_ratio(&s, case_3);
  peri_coupling_balance(&s, net, ratio);
  expect_printed(ratio[0], 4.31e-3, "Case III e_rx (Table 2.18)");
  cr_expect(ratio[1] <= 1e-9, "Case III e_ry %.3e", ratio[1]);
  peri_sim_free(&s);
}

/* The state-based PD side (lps): its rows are the model's tangent at u = 0, kept. */
static const char *plate_lps =
    "dimension: %d\n"
    "materials: {m: {model: lps, density: 1, youngs_modulus: 1, poisson_ratio: 0.3}}\n"
    "discretization: {spacing: 1, m: 3, fill: [{shape: %s, min: %s, max: %s}]}\n"
    "regions: {pd: {shape: %s, min: %s, max: %s}}\n"
    "coupling: {pd_region: %s}\n"
    "solver: {type: implicit, load_steps: 1}\n"
    "output: {picture: false}\n";

static void small_smooth(const double *x, double *u) {
  for (int d = 0; d < 3; ++d) u[d] = 1e-7 * (sin(0.3 * x[0] + d) + cos(0.2 * x[1] - d) + 0.5 * sin(0.25 * x[2]));
}

Test(coupling_2d3d, lps_linear_patch_test_and_linearisation) {
  for (int dim = 2; dim <= 3; ++dim) {
    /* the PD block 2 delta inside the free surface: a state-based row reaches the families of
     * the neighbours, whose dilatation the surface would change */
    char deck[2048];
    const char *shape = dim == 2 ? "rectangle" : "box";
    const char *lo = dim == 2 ? "[-10.5, -12.5]" : "[-8.5, -7.5, -8.5]", *hi = dim == 2 ? "[10.5, 12.5]" : "[8.5, 9.5, 7.5]";
    const char *plo = dim == 2 ? "[-3.25, -2.25]" : "[-2.25, -1.25, -2.25]", *phi = dim == 2 ? "[4.25, 5.25]" : "[2.25, 3.25, 1.25]";
    snprintf(deck, sizeof deck, plate_lps, dim, shape, lo, hi, shape, plo, phi, "pd");
    peri_sim s;
    build(&s, deck);
    const double e_r = imposed_ratio(&s, dim == 2 ? linear2 : linear3);
    cr_expect(e_r <= 1e-13, "lps %dD: linear e_r %.3e", dim, e_r);
    const double control = imposed_ratio(&s, dim == 2 ? quadratic2 : quadratic3);
    cr_expect(control > 1e-6, "lps %dD: a quadratic field across the interface: e_r %.3e", dim, control);
    peri_sim_free(&s);
    /* all PD on a small body: the kept rows are the linearised model, so K u equals the
     * model's force for a small u up to the quadratic remainder, relative O(|grad u|) = 1e-7;
     * 1e-5 leaves room */
    const char *small_lo = dim == 2 ? "[-4.5, -5.5]" : "[-3.5, -3.5, -3.5]", *small_hi = dim == 2 ? "[4.5, 5.5]" : "[3.5, 3.5, 3.5]";
    snprintf(deck, sizeof deck, plate_lps, dim, shape, small_lo, small_hi, shape, plo, phi, "all");
    build(&s, deck);
    const int32_t n = s.disc.p.n;
    for (int32_t i = 0; i < n; ++i) small_smooth(&s.disc.p.x[3 * (size_t)i], &s.disc.p.u[3 * (size_t)i]);
    peri_coupling_force(&s);
    double *linear = malloc(sizeof(double) * 3 * (size_t)n), scale = 0.0, diff = 0.0;
    for (size_t k = 0; k < 3 * (size_t)n; ++k) linear[k] = s.disc.p.f[k], scale = fmax(scale, fabs(linear[k]));
    s.solver.breaking = false;
    s.mat.model->force(&s);
    for (size_t k = 0; k < 3 * (size_t)n; ++k) diff = fmax(diff, fabs(s.disc.p.f[k] - linear[k]));
    cr_expect(scale > 0.0 && diff <= 1e-5 * scale, "lps %dD: |K u - f(u)| %.3e of %.3e", dim, diff, scale);
    free(linear);
    peri_sim_free(&s);
  }
}
