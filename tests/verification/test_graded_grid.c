/* Graded grids (docs/variable_horizon.md, "Graded grids"): zones of different node spacing
 * given as fill boxes with their own `spacing`, each tiled by its own cells, and the horizon
 * delta_i = m dx_i following the spacing.
 *
 * Tiling: each zone is a box whose sides are whole multiples of its spacing and whose cells
 * start at its lower corner, so the node volumes sum to the body's volume up to round-off
 * (a relative 1e-12 here, a few eps per node summed over < 10^4 nodes). Nearest nodes: inside
 * a zone two nodes are dx apart; across a face two cell centres are at least
 * (dx_a + dx_b) / 2 >= the finer spacing apart, so no two nodes are closer than the finest
 * spacing (asserted with a relative 1e-9 for the positions' rounding).
 *
 * Patch test: the graded 1D bar under u = a + H x, partial stress in the transition (the
 * nodes whose family holds another horizon), interior force <= 1e-10 of the force scale,
 * and full peridynamics on the same grid shows ghost forces above 1e-4 of it (the reasoning
 * of tests/verification/test_variable_horizon.c, whose bounds these are: in 1D the per-node
 * constants are calibrated on each node's own family, volumes included, so the partial
 * stress is E H at every node whatever its spacing). */
#include "peri/discretize.h"
#include "peri/horizon_field.h"
#include "peri/setup.h"
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include "support.h"

#define FINE 1.0e-3
#define COARSE 2.0e-3
#define M_RATIO 3.0 /* delta / dx */
#define E_MOD 70.0e9
#define STRAIN 0.02

/* 1D: coarse [-0.05, -0.01], fine [-0.01, 0.01], coarse [0.01, 0.05] (cross-section 1e-4 m^2).
 * 2D: a fine band |y| < 0.006 across a plate 0.04 x 0.03, coarse above and below. */
static void build(peri_sim *s, int dim, const char *model, const char *coupling) {
  char deck[4096], mat[192];
  if (model[0] == 'l')
    snprintf(mat, sizeof mat, "{model: lps, density: 2700, youngs_modulus: %.17g, poisson_ratio: 0.3}", E_MOD);
  else
    snprintf(mat, sizeof mat, "{model: pmb, density: 2700, youngs_modulus: %.17g}", E_MOD);
  const char *fill1 = "    - {shape: box, min: [-0.05], max: [-0.01], spacing: 2.0e-3}\n"
                      "    - {shape: box, min: [-0.01], max: [0.01]}\n"
                      "    - {shape: box, min: [0.01], max: [0.05], spacing: 2.0e-3}\n";
  const char *fill2 = "    - {shape: box, min: [-0.02, -0.016], max: [0.02, -0.006], spacing: 2.0e-3}\n"
                      "    - {shape: box, min: [-0.02, -0.006], max: [0.02, 0.006]}\n"
                      "    - {shape: box, min: [-0.02, 0.006], max: [0.02, 0.014], spacing: 2.0e-3}\n";
  snprintf(deck, sizeof deck,
           "dimension: %d\n%s"
           "materials:\n  mat: %s\n"
           "discretization:\n  spacing: %.17g\n  m: %g\n  partial_stress: %s\n%s"
           "  fill:\n%s"
           "solver: {type: explicit, steps: 1, breaking: false}\n"
           "output: {picture: false}\n",
           dim, dim == 2 ? "plane: stress\n" : "", mat, FINE, M_RATIO, coupling,
           dim == 2 ? "  thickness: 1.0e-3\n" : "  cross_section: 1.0e-4\n", dim == 1 ? fill1 : fill2);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
}

static double volume_sum(const peri_sim *s) {
  double v = 0.0;
  for (int32_t i = 0; i < s->disc.p.n; ++i) v += s->disc.p.volume[i];
  return v;
}

static double nearest_pair(const peri_sim *s) {
  double best = INFINITY;
  const double *x = s->disc.p.x;
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    for (int32_t j = i + 1; j < s->disc.p.n; ++j) {
      const double a = x[3 * i] - x[3 * j], b = x[3 * i + 1] - x[3 * j + 1], c = x[3 * i + 2] - x[3 * j + 2];
      best = fmin(best, sqrt(a * a + b * b + c * c));
    }
  return best;
}

/* every node's horizon is m times its zone's spacing */
static void check_horizons(const peri_sim *s, int dim, double fine_zone_half_width) {
  const peri_horizon_field *h = s->disc.horizon_field;
  cr_assert_not_null(h, "m on a graded grid gives a horizon per node");
  int fine = 0, coarse = 0;
  for (int32_t i = 0; i < s->disc.p.n; ++i) {
    const double coord = s->disc.p.x[3 * i + (dim == 1 ? 0 : 1)];
    const double dx = fabs(coord) < fine_zone_half_width ? FINE : COARSE;
    fine += dx == FINE, coarse += dx == COARSE;
    cr_assert_float_eq(h->delta[i], M_RATIO * dx, 1e-12 * dx, "node %d at %g: delta %g", i, coord, h->delta[i]);
  }
  cr_assert(fine > 0 && coarse > 0);
}

Test(graded_grid, tiling_1d) {
  peri_sim s;
  build(&s, 1, "pmb", "auto");
  const double body = 0.1 * 1.0e-4;
  cr_log_info("graded 1D: %d nodes, sum V / body - 1 = %.2e, nearest pair / fine dx = %.6f", s.disc.p.n,
              volume_sum(&s) / body - 1.0, nearest_pair(&s) / FINE);
  cr_assert_eq(s.disc.p.n, 20 + 20 + 20, "20 coarse, 20 fine, 20 coarse cells");
  cr_assert_float_eq(volume_sum(&s), body, 1e-12 * body);
  cr_assert_geq(nearest_pair(&s), FINE * (1.0 - 1e-9));
  check_horizons(&s, 1, 0.01);
  peri_sim_free(&s);
}

Test(graded_grid, tiling_2d) {
  peri_sim s;
  build(&s, 2, "pmb", "none");
  const double body = 0.04 * 0.03 * 1.0e-3;
  cr_log_info("graded 2D: %d nodes, sum V / body - 1 = %.2e, nearest pair / fine dx = %.6f", s.disc.p.n,
              volume_sum(&s) / body - 1.0, nearest_pair(&s) / FINE);
  cr_assert_eq(s.disc.p.n, 20 * 5 + 40 * 12 + 20 * 4);
  cr_assert_float_eq(volume_sum(&s), body, 1e-12 * body);
  cr_assert_geq(nearest_pair(&s), FINE * (1.0 - 1e-9));
  check_horizons(&s, 2, 0.006);
  peri_sim_free(&s);
}

/* largest interior |f| under u = 1e-4 + 0.02 x, over the nodes farther than 2 delta_max + 2 dx
 * from both ends; the coupled nodes among them */
static double patch_force(const char *model, const char *coupling, int *coupled) {
  peri_sim s;
  build(&s, 1, model, coupling);
  const double limit = 2.0 * M_RATIO * COARSE + 2.0 * COARSE;
  for (int32_t i = 0; i < s.disc.p.n; ++i) s.disc.p.u[3 * i] = 1.0e-4 + STRAIN * s.disc.p.x[3 * i];
  s.mat.model->force(&s);
  double worst = 0.0;
  *coupled = 0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    if (0.05 - fabs(s.disc.p.x[3 * i]) <= limit) continue;
    worst = fmax(worst, fabs(s.disc.p.f[3 * i]));
    *coupled += s.disc.horizon_field->coupled[i];
  }
  peri_sim_free(&s);
  return worst;
}

/* force scale S |H|: S = 4E / delta at the largest horizon (test_variable_horizon.c) */
static void check_patch(const char *model) {
  const double scale = 4.0 * E_MOD / (M_RATIO * COARSE) * STRAIN;
  int coupled = 0, unused = 0;
  const double ps = patch_force(model, "auto", &coupled), pd = patch_force(model, "none", &unused);
  cr_log_info("%s graded 1D bar: interior |f| / (S |H|) partial stress %.2e, full PD %.2e (%d coupled interior)",
              model, ps / scale, pd / scale, coupled);
  cr_assert_gt(coupled, 0, "the transition has no interior coupled node: the test would be vacuous");
  cr_expect(ps <= 1e-10 * scale, "%s partial stress: %.3g S|H| > 1e-10", model, ps / scale);
  cr_expect(pd >= 1e-4 * scale, "%s full PD: %.3g S|H|: the ghost forces are missing", model, pd / scale);
}

Test(graded_grid, patch_pmb_1d) { check_patch("pmb"); }
Test(graded_grid, patch_lps_1d) { check_patch("lps"); }

/* Breaking on the graded 1D bar (full PD, the one-pass PMB loop): a critical stretch from a
 * fracture energy scales as delta^-1/2 (docs/variable_horizon.md, "Bonds and per-node
 * constants"), so a bond's is that of its larger horizon, s0_c at the coarse 6 mm and
 * sqrt(2) s0_c between two fine 3 mm nodes. Under u = H x every bond has the stretch H: with
 * s0_c < H = 1.2 s0_c < sqrt(2) s0_c exactly the bonds with a coarse end break, in both
 * directions, and none between two fine nodes. */
Test(graded_grid, breaking_follows_the_horizon) {
  char deck[2048];
  snprintf(deck, sizeof deck,
           "dimension: 1\n"
           "materials:\n  mat: {model: pmb, density: 2700, youngs_modulus: %.17g, fracture_energy: 100.0}\n"
           "discretization:\n  spacing: %.17g\n  m: %g\n  partial_stress: none\n  cross_section: 1.0e-4\n"
           "  fill:\n"
           "    - {shape: box, min: [-0.05], max: [-0.01], spacing: 2.0e-3}\n"
           "    - {shape: box, min: [-0.01], max: [0.01]}\n"
           "    - {shape: box, min: [0.01], max: [0.05], spacing: 2.0e-3}\n"
           "solver: {type: explicit, steps: 1}\n"
           "output: {picture: false}\n",
           E_MOD, FINE, M_RATIO);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0, "deck:\n%s", deck);
  const peri_horizon_field *h = s.disc.horizon_field;
  const double s0_coarse = s.mat.pair_s0[0] * sqrt(h->max / (M_RATIO * COARSE)); /* the table is at max */
  for (int32_t i = 0; i < s.disc.p.n; ++i) s.disc.p.u[3 * i] = 1.2 * s0_coarse * s.disc.p.x[3 * i];
  const long broken = s.mat.model->force(&s);
  const peri_bonds *b = &s.disc.bonds;
  long expected = 0, wrong = 0;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const bool coarse_end = h->delta[i] > 1.5 * M_RATIO * FINE || h->delta[j] > 1.5 * M_RATIO * FINE;
      expected += coarse_end;
      wrong += (b->broken[k] != 0) != coarse_end;
    }
  cr_log_info("graded 1D bar at 1.2 s0_c: %ld of %ld directed bonds broken, %ld expected", broken,
              (long)b->n_bonds, expected);
  cr_assert_gt(expected, 0);
  cr_assert_lt(expected, b->n_bonds, "no fine-fine bond: the test would be vacuous");
  cr_expect_eq(wrong, 0, "%ld directed bonds broken against the delta^-1/2 scaling", wrong);
  cr_expect_eq(broken, expected);
  peri_sim_free(&s);
}
