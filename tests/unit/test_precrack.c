/* Pre-cracks remove exactly the bonds that cross them (docs/verification.md; docs/model_reference.md 7.4). */
#include <criterion/criterion.h>
#include <math.h>
#include "peri/damage.h"
#include "peri/setup.h"
#include "support.h"

/* Independent crossing test by parametric intersection: the segments p + s(q - p) and
 * a + t(b - a) cross when both parameters lie strictly inside (0, 1). */
static bool crosses(const double p[2], const double q[2], const double a[2], const double b[2]) {
  double r[2] = {q[0] - p[0], q[1] - p[1]}, d[2] = {b[0] - a[0], b[1] - a[1]};
  double den = r[0] * d[1] - r[1] * d[0];
  if (den == 0.0) return false;
  double s = ((a[0] - p[0]) * d[1] - (a[1] - p[1]) * d[0]) / den;
  double t = ((a[0] - p[0]) * r[1] - (a[1] - p[1]) * r[0]) / den;
  return s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0;
}

static const char *deck2d =
    "dimension: 2\n"
    "materials: {m: {model: pmb, density: 1000, youngs_modulus: 1e9}}\n"
    "discretization:\n"
    "  spacing: 1.0\n"
    "  m: 3.015\n"
    "  fill: [{shape: rectangle, min: [0, 0], max: [30, 20]}]\n"
    "precracks:\n"
    "  - {from: [%g, %g], to: [%g, %g]}\n"
    "solver: {type: explicit, steps: 1}\n"
    "output: {picture: false}\n";

/* A crack whose ends and line avoid the nodes (cell centres at k + 1/2) and whose ends
 * lie on no bond cuts exactly the bonds that geometrically cross it, in both directions. */
static void check_exact(double ax, double ay, double bx, double by) {
  char deck[1024];
  snprintf(deck, sizeof deck, deck2d, ax, ay, bx, by);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  double a[2] = {ax, ay}, b[2] = {bx, by};
  long expected = 0, mismatched = 0;
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    for (int64_t k = s.disc.bonds.offset[i]; k < s.disc.bonds.offset[i + 1]; ++k) {
      int32_t j = s.disc.bonds.neighbor[k];
      bool cut = crosses(&s.disc.p.x[3 * i], &s.disc.p.x[3 * j], a, b);
      expected += cut;
      mismatched += cut != (bool)s.disc.bonds.broken[k];
    }
  cr_expect(expected > 0);
  cr_expect_eq(mismatched, 0, "%ld bonds differ from the geometric crossing test", mismatched);
  cr_expect_eq(peri_broken_count(&s.disc.bonds), expected);
  peri_sim_free(&s);
}

Test(precrack, horizontal_between_rows) { check_exact(0.0, 10.0, 15.2, 10.0); }
Test(precrack, inclined) { check_exact(3.31, 2.13, 24.77, 17.29); }

/* A crack exactly on a row of nodes: the 1e-6 dx offset puts the row on one side, so the
 * bonds from that row to the other side are cut and bonds along the row are not. */
Test(precrack, on_a_row_of_nodes) {
  char deck[1024];
  snprintf(deck, sizeof deck, deck2d, 0.0, 10.5, 30.0, 10.5);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  long wrong = 0;
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    for (int64_t k = s.disc.bonds.offset[i]; k < s.disc.bonds.offset[i + 1]; ++k) {
      int32_t j = s.disc.bonds.neighbor[k];
      double yi = s.disc.p.x[3 * i + 1], yj = s.disc.p.x[3 * j + 1];
      /* the shift is along the normal (0, +1): the row y = 10.5 is below the crack */
      bool should = (yi <= 10.5 && yj > 10.5) || (yj <= 10.5 && yi > 10.5);
      wrong += should != (bool)s.disc.bonds.broken[k];
    }
  cr_expect_eq(wrong, 0);
  peri_sim_free(&s);
}

/* 3D: a rectangle cuts the bonds that pass through it and no others. */
Test(precrack, rectangle_3d) {
  const char *deck =
      "dimension: 3\n"
      "materials: {m: {model: pmb, density: 1000, youngs_modulus: 1e9}}\n"
      "discretization:\n"
      "  spacing: 1.0\n"
      "  m: 2.015\n"
      "  fill: [{shape: box, min: [0, 0, 0], max: [12, 12, 12]}]\n"
      "precracks:\n"
      "  - {corner: [6, 3.2, -1], edge1: [0, 5, 0], edge2: [0, 0, 14]}\n"
      "solver: {type: explicit, steps: 1}\n"
      "output: {picture: false}\n";
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  long wrong = 0;
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    for (int64_t k = s.disc.bonds.offset[i]; k < s.disc.bonds.offset[i + 1]; ++k) {
      int32_t j = s.disc.bonds.neighbor[k];
      const double *P = &s.disc.p.x[3 * i], *Q = &s.disc.p.x[3 * j];
      bool should = false;
      if ((P[0] - 6.0) * (Q[0] - 6.0) < 0.0) {
        double t = (6.0 - P[0]) / (Q[0] - P[0]);
        double y = P[1] + t * (Q[1] - P[1]);
        should = y >= 3.2 && y <= 8.2;
      }
      wrong += should != (bool)s.disc.bonds.broken[k];
    }
  cr_expect_eq(wrong, 0);
  cr_expect(peri_broken_count(&s.disc.bonds) > 0);
  peri_sim_free(&s);
}
