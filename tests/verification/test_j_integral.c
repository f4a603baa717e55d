/* The J-integral (docs/plasticity.md section 6, src/post/j_integral.c) of an elastic plate with
 * a central crack under uniform remote tension, solved by the implicit solver (plane stress):
 *  - J over three square rings around the right tip equals the energy release rate
 *    G = K_I^2 / E (plane stress: E' = E) with the handbook K_I of the centre-cracked plate of
 *    finite width (Tada, Paris & Irwin, The Stress Analysis of Cracks Handbook, 3rd ed., 2000,
 *    p. 2.2 (Feddersen with Tada's correction, better than 0.1% for any a/b):
 *      K_I = sigma sqrt(pi a) [1 - 0.025 (a/b)^2 + 0.06 (a/b)^4] sqrt(sec(pi a / (2 b)))
 *    with 2a the crack length and 2b the width), within 5%;
 *  - the three rings agree within 5% of their mean (path independence);
 *  - the crack does not grow (no bond breaks): the crack extension column is below one spacing.
 * The plate is 120 x 180 mm (height/width 1.5: the handbook value is that of an infinitely
 * long strip, and the end effect of h/b = 1.5 on K_I is below 1% there, Isida 1971), the crack
 * 2a = 40 mm (a/b = 1/3, a = 16 spacings), PMB (nu = 1/3) and LPS (nu = 0.3). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include "peri/j_integral.h"
#include "peri/quasistatic.h"
#include "peri/setup.h"
#include "peri/solver.h"
#include "support.h"

#define WIDTH 0.12   /* 2b (m) */
#define HEIGHT 0.18  /* 2h (m) */
#define CRACK 0.04   /* 2a (m) */
#define STRESS 50e6  /* remote tension (Pa) */
#define E_PLATE 200e9

static double handbook_K(double sigma, double a, double b) {
  const double r = a / b;
  return sigma * sqrt(M_PI * a) * (1.0 - 0.025 * r * r + 0.06 * r * r * r * r) * sqrt(1.0 / cos(M_PI * a / (2.0 * b)));
}

static void cracked_plate(const char *material) {
  char deck[4096];
  const double dx = 1.25e-3; /* a = 16 spacings */
  snprintf(deck, sizeof deck,
           "dimension: 2\n"
           "plane: stress\n"
           "materials:\n"
           "  steel: {%s, density: 7800, youngs_modulus: %g}\n"
           "discretization: {spacing: %g, m: 3, thickness: 1e-3,\n"
           "                 fill: [{shape: rectangle, min: [%g, %g], max: [%g, %g]}]}\n"
           "precracks: [{from: [%g, 0], to: [%g, 0]}]\n"
           "regions:\n"
           "  top: {shape: rectangle, min: [-1, %g], max: [1, 1]}\n"
           "  bottom: {shape: rectangle, min: [-1, -1], max: [1, %g]}\n"
           "  left_pin: {shape: rectangle, min: [-1, -0.001], max: [%g, 0]}\n"
           "  right_pin: {shape: rectangle, min: [%g, -0.001], max: [1, 0]}\n"
           "boundary_conditions:\n"
           "  - {type: traction, region: top, y: %g, layer: %g}\n"
           "  - {type: traction, region: bottom, y: %g, layer: %g}\n"
           "  - {type: displacement, region: left_pin, x: 0, y: 0}\n"
           "  - {type: displacement, region: right_pin, y: 0}\n"
           "j_integral:\n"
           "  tip: [%g, 0]\n"
           "  contours: [[0.004, 0.008], [0.008, 0.013], [0.013, 0.018]]\n"
           "solver: {type: implicit, breaking: false}\n"
           "output: {picture: false}\n",
           material, E_PLATE, dx, -WIDTH / 2, -HEIGHT / 2, WIDTH / 2, HEIGHT / 2, -CRACK / 2, CRACK / 2,
           HEIGHT / 2 - dx, -HEIGHT / 2 + dx, -WIDTH / 2 + dx, WIDTH / 2 - dx, STRESS, dx, -STRESS, dx, CRACK / 2);
  peri_sim s = {0};
  cr_assert_eq(sim_from_string(&s, deck), 0, "deck:\n%s", deck);
  cr_assert_not_null(s.out.j_integral);
  peri_apply_initial_conditions(&s);
  cr_assert_eq(peri_solve_quasi_static(&s, NULL, NULL), 0, "the implicit solve failed");
  double J[3], extension = -1.0;
  cr_assert_eq(peri_j_integral_values(&s, s.out.j_integral, J, &extension), 0);
  const double K = handbook_K(STRESS, CRACK / 2, WIDTH / 2), G = K * K / E_PLATE;
  const double mean = (J[0] + J[1] + J[2]) / 3.0;
  printf("%s: G = K^2/E = %.2f J/m^2; J = %.2f %.2f %.2f (%+.2f%% %+.2f%% %+.2f%%); crack extension %g m\n", material,
         G, J[0], J[1], J[2], 100 * (J[0] / G - 1), 100 * (J[1] / G - 1), 100 * (J[2] / G - 1), extension);
  for (int c = 0; c < 3; ++c) {
    cr_expect(fabs(J[c] / G - 1.0) < 0.05, "%s: contour %d J = %g, G = %g (%+.2f%%)", material, c + 1, J[c], G,
              100 * (J[c] / G - 1));
    cr_expect(fabs(J[c] / mean - 1.0) < 0.05, "%s: contour %d J = %g, mean %g", material, c + 1, J[c], mean);
  }
  cr_expect(extension >= 0.0 && extension < 1e-3, "%s: crack extension %g m without breaking", material, extension);
  peri_sim_free(&s);
}

Test(j_integral, pmb_centre_cracked_plate) { cracked_plate("model: pmb"); }
Test(j_integral, lps_centre_cracked_plate) { cracked_plate("model: lps, poisson_ratio: 0.3"); }
