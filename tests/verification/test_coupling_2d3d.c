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
 *    intersection; this uses peri's default linear ramp (docs/coupling.md). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
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
