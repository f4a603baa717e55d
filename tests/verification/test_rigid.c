/* Rigid motion (docs/verification.md Elasticity 2): a rigid translation and a small rigid
 * rotation give zero internal force on every node, surface nodes included, for PMB and
 * LPS in 2D (both planes) and 3D (translation also in 1D). The bodies have a hole so that
 * the surface is not only flat faces. */
#include "peri/setup.h"
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include "support.h"

#define DX 1.0e-3
#define E_MOD 70.0e9
#define M_RATIO 3.0

typedef struct {
  int dim;
  peri_plane plane;
  const char *model;
  double nu; /* LPS: 0.3, away from the PMB ratio, so the dilatation term is active */
} rigid_case;

/* 2D: 30 x 24 cells with a circular hole; 3D: 14 x 12 x 10 cells with a spherical hole;
 * 1D: 40 cells. All centred near the origin so |x| <= ~21 dx. */
static void build(peri_sim *s, const rigid_case *c) {
  char mat[160], shapes[512], deck[2048];
  if (c->model[0] == 'l')
    snprintf(mat, sizeof mat, "{model: lps, density: 2700, youngs_modulus: %.17g, poisson_ratio: %.17g}", E_MOD,
             c->nu);
  else
    snprintf(mat, sizeof mat, "{model: pmb, density: 2700, youngs_modulus: %.17g}", E_MOD);
  if (c->dim == 1)
    snprintf(shapes, sizeof shapes, "  fill: [{shape: interval, min: [-0.02], max: [0.02]}]\n");
  else if (c->dim == 2)
    snprintf(shapes, sizeof shapes,
             "  thickness: 1.0e-3\n"
             "  fill: [{shape: rectangle, min: [-0.015, -0.012], max: [0.015, 0.012]}]\n"
             "  remove: [{shape: circle, center: [0.003, -0.002], radius: 0.0052}]\n");
  else
    snprintf(shapes, sizeof shapes,
             "  fill: [{shape: box, min: [-0.007, -0.006, -0.005], max: [0.007, 0.006, 0.005]}]\n"
             "  remove: [{shape: sphere, center: [0.001, -0.001, 0.0005], radius: 0.0032}]\n");
  snprintf(deck, sizeof deck,
           "dimension: %d\n"
           "%s"
           "materials:\n"
           "  mat: %s\n"
           "discretization:\n"
           "  spacing: %.17g\n"
           "  m: %.17g\n"
           "%s"
           "solver: {type: explicit, steps: 1, breaking: false}\n"
           "output: {picture: false}\n",
           c->dim, c->dim != 2 ? "" : c->plane == PERI_PLANE_STRAIN ? "plane: strain\n" : "plane: stress\n", mat,
           DX, M_RATIO, shapes);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  s->solver.breaking = false;
}

/* S = c V_H: the force density of a full family with every bond at unit stretch, with
 * the constant-influence PMB micromodulus (docs/model_reference.md 2.3): 24K/d (3D), 9E/d (plane
 * stress), 48E/(5d) (plane strain), 4E/d (1D). */
static double force_scale(const rigid_case *c) {
  double d = M_RATIO * DX, K = E_MOD / (3.0 * (1.0 - 2.0 * c->nu));
  if (c->dim == 3) return 24.0 * K / d;
  if (c->dim == 1) return 4.0 * E_MOD / d;
  return (c->plane == PERI_PLANE_STRAIN ? 9.6 : 9.0) * E_MOD / d;
}

static double max_force(const peri_sim *s) {
  double worst = 0.0;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
    const double *f = &s->disc.p.f[3 * i];
    worst = fmax(worst, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
  }
  return worst;
}

/* Bound for both motions: in exact arithmetic every bond keeps its length (the rotation
 * is the exact R, not its linearisation), so e = 0, theta = 0 and f = 0 on every node.
 * In floating point y_j - y_i carries an error of a few eps |y|max, so each stretch is off
 * by at most ~4 eps |y|max / dx ~ 4 * 2.2e-16 * 24 ~ 2e-14, and |f| <= S * 2e-14 even if
 * all these errors added up. The asserted limits, 1e-9 of the force of a 1e-3 stretch
 * (translation) and 1e-6 of the force of a 1e-6 stretch (rotation), are both 1e-12 S. */
#define RIGID_TOL 1e-12

static void check_translation(const rigid_case *c) {
  peri_sim s;
  build(&s, c);
  const double t[3] = {1.0e-3, -2.0e-3, 0.5e-3}; /* of the order of dx */
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    for (int a = 0; a < c->dim; ++a) s.disc.p.u[3 * i + a] = t[a];
  s.mat.model->force(&s);
  double worst = max_force(&s), bound = RIGID_TOL * force_scale(c);
  cr_expect(worst <= bound, "%s dim %d plane %d translation: max |f| = %.3g > %.3g", c->model, c->dim,
            (int)c->plane, worst, bound);
  peri_sim_free(&s);
}

/* Rotation by 1e-6 rad about the z axis (2D) or about (1, 2, 3)/sqrt(14) (3D), through the
 * origin: u = (R - I) x = sin(a) K x + (1 - cos(a)) K^2 x (Rodrigues), with 1 - cos(a)
 * written as 2 sin^2(a/2) to avoid cancellation. */
static void check_rotation(const rigid_case *c) {
  peri_sim s;
  build(&s, c);
  const double angle = 1e-6;
  double n[3] = {0.0, 0.0, 1.0};
  if (c->dim == 3) n[0] = 1.0 / sqrt(14.0), n[1] = 2.0 / sqrt(14.0), n[2] = 3.0 / sqrt(14.0);
  const double K[3][3] = {{0.0, -n[2], n[1]}, {n[2], 0.0, -n[0]}, {-n[1], n[0], 0.0}};
  double K2[3][3], sa = sin(angle), ca1 = 2.0 * sin(0.5 * angle) * sin(0.5 * angle);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      K2[a][b] = 0.0;
      for (int k = 0; k < 3; ++k) K2[a][b] += K[a][k] * K[k][b];
    }
  for (int32_t i = 0; i < s.disc.p.n; ++i) {
    const double *x = &s.disc.p.x[3 * i];
    for (int a = 0; a < 3; ++a) {
      double kx = 0.0, k2x = 0.0;
      for (int b = 0; b < 3; ++b) kx += K[a][b] * x[b], k2x += K2[a][b] * x[b];
      s.disc.p.u[3 * i + a] = sa * kx + ca1 * k2x;
    }
  }
  s.mat.model->force(&s);
  double worst = max_force(&s), bound = RIGID_TOL * force_scale(c);
  cr_expect(worst <= bound, "%s dim %d plane %d rotation: max |f| = %.3g > %.3g", c->model, c->dim, (int)c->plane,
            worst, bound);
  peri_sim_free(&s);
}

/* The bound discriminates: an isotropic stretch of 1e-6 (the "force for a 1e-6 stretch")
 * puts on the outermost nodes a force of order S * 1e-6 / 2 (half a family pulls them in),
 * six orders of magnitude above RIGID_TOL * S. */
static void check_stretch_is_seen(const rigid_case *c) {
  peri_sim s;
  build(&s, c);
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    for (int a = 0; a < c->dim; ++a) s.disc.p.u[3 * i + a] = 1e-6 * s.disc.p.x[3 * i + a];
  s.mat.model->force(&s);
  double worst = max_force(&s), S = force_scale(c);
  cr_expect(worst > 0.01 * 1e-6 * S, "%s dim %d: a 1e-6 stretch gives only max |f| = %.3g (S = %.3g)", c->model,
            c->dim, worst, S);
  peri_sim_free(&s);
}

static const rigid_case pmb_1d = {1, PERI_PLANE_NONE, "pmb", 0.25};
static const rigid_case pmb_ps = {2, PERI_PLANE_STRESS, "pmb", 1.0 / 3.0};
static const rigid_case pmb_pe = {2, PERI_PLANE_STRAIN, "pmb", 0.25};
static const rigid_case pmb_3d = {3, PERI_PLANE_NONE, "pmb", 0.25};
static const rigid_case lps_1d = {1, PERI_PLANE_NONE, "lps", 0.3};
static const rigid_case lps_ps = {2, PERI_PLANE_STRESS, "lps", 0.3};
static const rigid_case lps_pe = {2, PERI_PLANE_STRAIN, "lps", 0.3};
static const rigid_case lps_3d = {3, PERI_PLANE_NONE, "lps", 0.3};

Test(rigid, translation_pmb_1d) { check_translation(&pmb_1d); }
Test(rigid, translation_pmb_plane_stress) { check_translation(&pmb_ps); }
Test(rigid, translation_pmb_plane_strain) { check_translation(&pmb_pe); }
Test(rigid, translation_pmb_3d) { check_translation(&pmb_3d); }
Test(rigid, translation_lps_1d) { check_translation(&lps_1d); }
Test(rigid, translation_lps_plane_stress) { check_translation(&lps_ps); }
Test(rigid, translation_lps_plane_strain) { check_translation(&lps_pe); }
Test(rigid, translation_lps_3d) { check_translation(&lps_3d); }

Test(rigid, rotation_pmb_plane_stress) { check_rotation(&pmb_ps); }
Test(rigid, rotation_pmb_plane_strain) { check_rotation(&pmb_pe); }
Test(rigid, rotation_pmb_3d) { check_rotation(&pmb_3d); }
Test(rigid, rotation_lps_plane_stress) { check_rotation(&lps_ps); }
Test(rigid, rotation_lps_plane_strain) { check_rotation(&lps_pe); }
Test(rigid, rotation_lps_3d) { check_rotation(&lps_3d); }

Test(rigid, stretch_is_seen_pmb_3d) { check_stretch_is_seen(&pmb_3d); }
Test(rigid, stretch_is_seen_lps_plane_stress) { check_stretch_is_seen(&lps_ps); }
