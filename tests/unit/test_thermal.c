/* Heat conduction: micro-conductivity constants (docs/model_reference.md 11.2), the discrete operator on
 * linear fields, conservation of heat, cut bonds, deck errors (docs/heat.md). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "peri/conduction.h"
#include "peri/heat.h"
#include "peri/heat_quantities.h"
#include "peri/setup.h"
#include "peri/thermal.h"
#include "support.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* The flux of T = g.x into a point over H+ (Bobaru & Duangpanya 2012 eq. 7), evaluated as a continuum
 * integral, equals kappa g (the into-flux; the Fourier flux is -kappa g) in 1D, 2D and 3D
 * for both kernels. This checks the constants of docs/model_reference.md 11.2 (1D and 3D derived). */
Test(thermal, flux_of_linear_field_matches_conductivity) {
  const double kappa = 2.7, delta = 0.013;
  const double grads[3][3] = {{1.0, 0.0, 0.0}, {0.3, -1.7, 0.0}, {-0.4, 0.9, 2.2}};
  for (int dim = 1; dim <= 3; ++dim)
    for (int kernel = 0; kernel < 2; ++kernel)
      for (int gi = 0; gi < 3; ++gi) {
        double g[3] = {0, 0, 0};
        for (int d = 0; d < dim; ++d) g[d] = grads[gi][d];
        double q[3];
        peri_thermal_flux_integral((peri_thermal_kernel)kernel, dim, kappa, delta, g, q);
        double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        for (int d = 0; d < 3; ++d)
          cr_expect(fabs(q[d] - kappa * g[d]) <= 1e-10 * kappa * gn, "dim %d kernel %d: q[%d] = %.15g, expected %.15g",
                    dim, kernel, d, q[d], kappa * g[d]);
      }
}

/* The printed constants (docs/model_reference.md 11.2 table; Bobaru & Duangpanya 2012 sec. 2.3 with the erratum). */
Test(thermal, kernel_constants) {
  const double k = 1.3, d = 0.2;
  struct { int dim, kernel; double expected; } cases[] = {
      {1, PERI_TKERNEL_CONSTANT, k / d},
      {1, PERI_TKERNEL_CONICAL, 2 * k / d},
      {2, PERI_TKERNEL_CONSTANT, 4 * k / (M_PI * d * d)},
      {2, PERI_TKERNEL_CONICAL, 12 * k / (M_PI * d * d)},
      {3, PERI_TKERNEL_CONSTANT, 9 * k / (2 * M_PI * d * d * d)},
      {3, PERI_TKERNEL_CONICAL, 18 * k / (M_PI * d * d * d)},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
    double got = peri_thermal_k_constant((peri_thermal_kernel)cases[c].kernel, cases[c].dim, k, d);
    cr_expect(fabs(got / cases[c].expected - 1) < 1e-14, "dim %d kernel %d: %g vs %g", cases[c].dim,
              cases[c].kernel, got, cases[c].expected);
  }
  /* conical: k1 (1 - r/delta), zero beyond delta */
  cr_expect(fabs(peri_thermal_k(PERI_TKERNEL_CONICAL, 2, k, d, 0.25 * d) - 0.75 * 12 * k / (M_PI * d * d)) < 1e-12);
  cr_expect(peri_thermal_k(PERI_TKERNEL_CONICAL, 2, k, d, 1.1 * d) == 0.0);
  /* bond conductivity between materials: lower (Bobaru & Duangpanya 2012 sec. 5.4) or harmonic mean */
  cr_expect(peri_thermal_bond_kappa(PERI_TBOND_LOWER, 1.14, 0.0114) == 0.0114);
  cr_expect(fabs(peri_thermal_bond_kappa(PERI_TBOND_HARMONIC, 1.0, 3.0) - 1.5) < 1e-15);
}

static const char *box_deck =
    "dimension: %d\n"
    "materials:\n"
    "  a: {density: 2, conductivity: 3, specific_heat: 5}\n"
    "discretization:\n"
    "  spacing: 0.1\n"
    "  m: %g\n"
    "  fill: [{shape: box, min: [0, 0, 0], max: [%s]}]\n"
    "%s"
    "thermal: {initial_temperature: \"%s\"%s}\n"
    "solver: {type: heat, steps: 10}\n"
    "output: {picture: false}\n";

static int build(peri_sim *s, int dim, double m, const char *extent, const char *init, const char *extra,
                 const char *more) {
  char text[4096];
  snprintf(text, sizeof text, box_deck, dim, m, extent, more, init, extra);
  return sim_from_string(s, text);
}

/* On a linear field the discrete operator gives zero net heat at nodes whose family is
 * complete (>= delta + dx from the boundary): symmetric lattice families cancel. */
static void check_linear(int dim, const char *extent, double lo, double hi, const char *extra) {
  peri_sim s;
  cr_assert_eq(build(&s, dim, 3.0, extent, "2*x - 3*y + 0.5*z + 7", extra, ""), 0);
  double *rate = calloc(s.disc.p.n_owned, sizeof(double));
  peri_thermal_rate(&s, s.thermal->T, 0.0, rate);
  int checked = 0;
  const double margin = s.disc.geom.horizon + s.disc.geom.spacing;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    bool inside = true;
    for (int d = 0; d < dim; ++d) inside = inside && s.disc.p.x[3 * i + d] > lo + margin && s.disc.p.x[3 * i + d] < hi - margin;
    if (!inside) continue;
    /* scale: one bond's worth of heat, sum |H| * |dT| */
    double scale = 0.0;
    for (int64_t k = s.disc.bonds.offset[i]; k < s.disc.bonds.offset[i + 1]; ++k)
      scale += s.thermal->H[k] * fabs(s.thermal->T[s.disc.bonds.neighbor[k]] - s.thermal->T[i]);
    cr_expect(fabs(rate[i] * s.thermal->rhoc[i]) <= 1e-12 * scale, "dim %d node %d: rate %g (scale %g)", dim, i,
              rate[i], scale);
    checked++;
  }
  cr_expect(checked > 0, "dim %d: no interior node", dim);
  free(rate);
  peri_sim_free(&s);
}

Test(thermal, linear_field_zero_net_heat) {
  check_linear(1, "2", 0.0, 2.0, "");
  check_linear(2, "1.2, 1.2", 0.0, 1.2, "");
  check_linear(3, "1, 1, 1", 0.0, 1.0, "");
  check_linear(2, "1.2, 1.2", 0.0, 1.2, ", kernel: constant, self_term: none");
}

/* Insulated body (natural insulation, default quadrature): the symmetric weights
 * H_ip A_i = H_pi A_p conserve sum rho c T A to round-off, with a pre-crack too. */
Test(thermal, conservation_of_heat_insulated) {
  peri_sim s;
  cr_assert_eq(build(&s, 2, 3.0, "1.5, 1.0", "100*exp(-10*((x-0.4)^2+(y-0.6)^2)) + 20*x", "",
                     "precracks: [{from: [0.75, 0.2], to: [0.75, 1.1]}]\n"),
               0);
  double q0 = peri_thermal_total_heat(&s);
  for (int k = 0; k < 200; ++k) cr_assert_eq(peri_thermal_step(&s, s.solver.dt), 0);
  double q1 = peri_thermal_total_heat(&s);
  cr_expect(fabs(q1 - q0) <= 1e-13 * fabs(q0), "total heat %.17g -> %.17g", q0, q1);
  /* and the field did change */
  double spread = 0.0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) spread = fmax(spread, fabs(s.thermal->T[i]));
  cr_expect(spread < 100.0);
  peri_sim_free(&s);
  /* 3D, Euler */
  cr_assert_eq(build(&s, 3, 2.0, "0.6, 0.5, 0.4", "x*y + 3*z", ", integrator: euler", ""), 0);
  q0 = peri_thermal_total_heat(&s);
  for (int k = 0; k < 100; ++k) cr_assert_eq(peri_thermal_step(&s, s.solver.dt), 0);
  q1 = peri_thermal_total_heat(&s);
  cr_expect(fabs(q1 - q0) <= 1e-13 * fabs(q0), "3D total heat %.17g -> %.17g", q0, q1);
  peri_sim_free(&s);
}

/* A crack across the whole plate cuts every bond between the halves: the cold half keeps
 * exactly its temperature (a cut bond carries no heat). With crack_conductance 1/2 heat
 * crosses. */
Test(thermal, cut_bond_carries_no_heat) {
  const char *crack = "precracks: [{from: [0.5, -0.1], to: [0.5, 1.1]}]\n";
  for (int variant = 0; variant < 2; ++variant) {
    peri_sim s;
    cr_assert_eq(build(&s, 2, 3.0, "1, 1", "x < 0.5 ? 100 : 0", variant ? ", crack_conductance: 0.5" : "", crack), 0);
    for (int k = 0; k < 50; ++k) cr_assert_eq(peri_thermal_step(&s, s.solver.dt), 0);
    double right = 0.0;
    for (int32_t i = 0; i < s.disc.p.n_owned; ++i)
      if (s.disc.p.x[3 * i] > 0.5) right = fmax(right, fabs(s.thermal->T[i]));
    if (variant == 0) cr_expect(right == 0.0, "heat crossed the crack: max T on the cold side %g", right);
    else cr_expect(right > 1.0, "partial conduction: the cold side stays at %g", right);
    peri_sim_free(&s);
  }
}

/* A single bond: two nodes, one cut bond, nothing flows; uncut, the pair relaxes to the
 * mean with dT/dt = -H (T_i - T_p) / (rho c) at the first instant. */
Test(thermal, two_nodes) {
  peri_sim s;
  cr_assert_eq(build(&s, 1, 1.0, "0.2", "x < 0.1 ? 10 : 4", ", kernel: constant, self_term: none", ""), 0);
  cr_assert_eq(s.disc.p.n_owned, 2);
  double rate[2];
  peri_thermal_rate(&s, s.thermal->T, 0.0, rate);
  /* 1D constant kernel k0 = kappa/delta, beta = 1/2 at |xi| = delta = dx, A_p = dx */
  double H = (3.0 / 0.1) * 0.5 * 0.1 / (0.1 * 0.1);
  int hot = s.thermal->T[0] > s.thermal->T[1] ? 0 : 1;
  cr_expect(fabs(rate[hot] - (-H * 6.0 / 10.0)) < 1e-12 * H, "rate %g, expected %g", rate[hot], -H * 6.0 / 10.0);
  s.disc.bonds.broken[0] = s.disc.bonds.broken[1] = 1;
  peri_thermal_rate(&s, s.thermal->T, 0.0, rate);
  cr_expect(rate[0] == 0.0 && rate[1] == 0.0);
  peri_sim_free(&s);
}

/* Deck errors are reported with their position (exit status 2). */
Test(thermal, deck_errors) {
  peri_sim s;
  const char *bad_kernel =
      "dimension: 2\nmaterials:\n  a: {density: 1, conductivity: 1, specific_heat: 1}\n"
      "discretization: {spacing: 0.1, m: 3, fill: [{shape: box, min: [0, 0], max: [1, 1]}]}\n"
      "thermal: {kernel: conic}\nsolver: {type: heat, steps: 1}\n";
  cr_expect_eq(sim_from_string(&s, bad_kernel), 2);
  peri_sim_free(&s);
  const char *missing_c =
      "dimension: 2\nmaterials:\n  a: {density: 1, conductivity: 1}\n"
      "discretization: {spacing: 0.1, m: 3, fill: [{shape: box, min: [0, 0], max: [1, 1]}]}\n"
      "solver: {type: heat, steps: 1}\n";
  cr_expect_eq(sim_from_string(&s, missing_c), 2);
  peri_sim_free(&s);
  const char *mech_key =
      "dimension: 2\nmaterials:\n  a: {density: 1, conductivity: 1, specific_heat: 1, youngs_modulus: 1e9}\n"
      "discretization: {spacing: 0.1, m: 3, fill: [{shape: box, min: [0, 0], max: [1, 1]}]}\n"
      "solver: {type: heat, steps: 1}\n";
  cr_expect_eq(sim_from_string(&s, mech_key), 2);
  peri_sim_free(&s);
  const char *no_section =
      "dimension: 2\nmaterials:\n  a: {model: pmb, density: 1, youngs_modulus: 1e9, conductivity: 1}\n"
      "discretization: {spacing: 0.1, m: 3, fill: [{shape: box, min: [0, 0], max: [1, 1]}]}\n"
      "solver: {type: explicit, steps: 1}\n";
  cr_expect_eq(sim_from_string(&s, no_section), 2);
  peri_sim_free(&s);
  const char *bobaru_centers =
      "dimension: 2\nmaterials:\n  a: {density: 1, conductivity: 1, specific_heat: 1}\n"
      "discretization: {spacing: 0.1, m: 3, fill: [{shape: box, min: [0, 0], max: [1, 1]}]}\n"
      "thermal: {quadrature: bobaru2012}\nsolver: {type: heat, steps: 1}\n";
  cr_expect_eq(sim_from_string(&s, bobaru_centers), 2);
  peri_sim_free(&s);
  const char *bad_region =
      "dimension: 2\nmaterials:\n  a: {density: 1, conductivity: 1, specific_heat: 1}\n"
      "discretization: {spacing: 0.1, m: 3, fill: [{shape: box, min: [0, 0], max: [1, 1]}]}\n"
      "regions: {left: {shape: box, min: [0, 0], max: [0.1, 1]}}\n"
      "boundary_conditions: [{type: temperature, region: lefт, value: 1}]\n"
      "solver: {type: heat, steps: 1}\n";
  cr_expect_eq(sim_from_string(&s, bad_region), 2);
  peri_sim_free(&s);
  const char *bad_expr =
      "dimension: 2\nmaterials:\n  a: {density: 1, conductivity: 1, specific_heat: 1}\n"
      "discretization: {spacing: 0.1, m: 3, fill: [{shape: box, min: [0, 0], max: [1, 1]}]}\n"
      "boundary_conditions: [{type: heat_source, region: all, value: \"w*2\"}]\n"
      "solver: {type: heat, steps: 1}\n";
  cr_expect_eq(sim_from_string(&s, bad_expr), 2);
  peri_sim_free(&s);
}

/* docs/verification.md 15: a grid row on the crack line. The crack is shifted by 1e-6 dx along
 * its normal (+y for a crack drawn left to right), so a node on the line belongs to the
 * side below: its bonds up across the crack are cut, its bonds down and along the line
 * are not; a bond through a crack tip crosses the shifted crack just inside the tip and is
 * cut; one that crosses the line beside the tip is not. */
static int32_t node_at(const peri_sim *s, double x, double y) {
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i)
    if (fabs(s->disc.p.x[3 * i] - x) < 1e-9 && fabs(s->disc.p.x[3 * i + 1] - y) < 1e-9) return i;
  return -1;
}

static bool cut(const peri_sim *s, double x1, double y1, double x2, double y2) {
  int32_t a = node_at(s, x1, y1), b = node_at(s, x2, y2);
  cr_assert(a >= 0 && b >= 0);
  int64_t k = peri_bonds_find(&s->disc.bonds, a, b), r = peri_bonds_find(&s->disc.bonds, b, a);
  cr_assert(k >= 0 && r >= 0);
  cr_assert_eq(s->thermal->cut[k], s->thermal->cut[r], "cut flags of the two directions differ");
  return s->thermal->cut[k];
}

Test(thermal, crack_on_a_node_row) {
  const char *deck =
      "dimension: 2\nmaterials:\n  a: {density: 1, conductivity: 1, specific_heat: 1}\n"
      "discretization: {spacing: 0.1, m: 3, placement: lattice, origin: [0, 0],\n"
      "                 fill: [{shape: box, min: [0, 0], max: [1, 1]}]}\n"
      "precracks: [{from: [0.25, 0.5], to: [0.75, 0.5]}]\n"
      "solver: {type: heat, steps: 1}\noutput: {picture: false}\n";
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  cr_expect(cut(&s, 0.5, 0.5, 0.5, 0.6), "on-line node to the node above: cut");
  cr_expect(!cut(&s, 0.5, 0.5, 0.5, 0.4), "on-line node to the node below: intact");
  cr_expect(!cut(&s, 0.5, 0.5, 0.6, 0.5), "along the crack line: intact");
  cr_expect(cut(&s, 0.5, 0.4, 0.5, 0.6), "across the crack: cut");
  cr_expect(cut(&s, 0.4, 0.5, 0.6, 0.6), "on-line node to a node above, inclined: cut");
  cr_expect(!cut(&s, 0.8, 0.4, 0.8, 0.6), "beyond the crack tip: intact");
  cr_expect(cut(&s, 0.2, 0.4, 0.3, 0.6), "through the crack tip (0.25, 0.5): cut (it crosses the shifted crack)");
  cr_expect(!cut(&s, 0.1, 0.4, 0.2, 0.6), "crossing the line at x = 0.15, beside the tip: intact");
  peri_sim_free(&s);
}
