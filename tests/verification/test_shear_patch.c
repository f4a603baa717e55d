/* Patch test under a general H in 2D and 3D (docs/variable_horizon.md "The lattice correction";
 * Silling, Littlewood and Seleson 2013, "Patch test requirement for a coupling method"): under
 * u = a + Hx, H not symmetric and with shear, the interior force density vanishes to round-off
 * at the full-PD, coupled and local nodes, (a) with the partial stress between two horizons and
 * (b) at a PD-local interface (horizon 0 outside), for PMB and LPS. Full PD on the same grid as
 * (a) shows the ghost forces, which the test measures.
 *
 * What must vanish: a peridynamic node's nu0 is, to first order in H, D_i : eps with D_i the
 * elasticity of its own discrete family, whose fourth moment on a square or cubic lattice is
 * not isotropic and depends on delta_i / dx; the lattice correction nu0 <- C_iso D_i^-1 nu0 makes
 * it C_iso : eps on every node, as the local nodes' sigma is, so the divergence of an affine
 * field is zero. Without it the shear leaves about 1e-3 of the force scale (the figures are in
 * the docs). The models are geometrically nonlinear (bond stretch and direction from the deformed
 * positions) while the local side is small-strain linear elasticity, so at a finite H the two
 * sides differ at order |H|^2 whatever the calibration: the patch test is that of the linear
 * theory of the source, the force's first-order part in H. It is measured by the fourth-order
 * central difference
 *     f_lin = (8 (f(u) - f(-u)) - (f(2u) - f(-2u))) / 12,   u = a + Hx,  |H| = 1e-3,
 * whose truncation is of order |H|^5 (1e-15 relative) and whose rounding (a bond's extension
 * carries eps |x| against |H| |xi|, |x| / |xi| <= 25: 5e-12 relative, averaging down over the
 * bonds) is far below the 1e-10 asserted. The force at a finite H is logged as well. */
#include "peri/horizon_field.h"
#include "peri/setup.h"
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "support.h"

#define DX 1.0e-3
#define E_MOD 70.0e9
#define PROBE 1.0e-3 /* |H| of the linear-part probe */

/* a general H (largest entry 1): not symmetric, with shear, in 2D the leading 2 x 2 block */
static const double H_2D[9] = {0.2, 1.0, 0, 0.3, -0.5, 0, 0, 0, 0};
static const double H_3D[9] = {0.2, 1.0, -0.3, 0.3, -0.5, 0.7, -0.6, 0.4, 0.1};
static const double OFFSET[3] = {1.0e-4, -2.0e-4, 0.5e-4};

typedef struct {
  int dim;
  const char *model;
  const char *horizon; /* expression of x (m); 0 where the nodes are local */
  double delta_max;
  int n[3];
} shear_case;

static void build(peri_sim *s, const shear_case *c, const char *coupling) {
  char lo[128], hi[128], mat[192], deck[4096];
  double h[3];
  for (int d = 0; d < 3; ++d) h[d] = 0.5 * c->n[d] * DX;
  if (c->dim == 2)
    snprintf(lo, sizeof lo, "[%.17g, %.17g]", -h[0], -h[1]), snprintf(hi, sizeof hi, "[%.17g, %.17g]", h[0], h[1]);
  else
    snprintf(lo, sizeof lo, "[%.17g, %.17g, %.17g]", -h[0], -h[1], -h[2]),
        snprintf(hi, sizeof hi, "[%.17g, %.17g, %.17g]", h[0], h[1], h[2]);
  if (c->model[0] == 'l')
    snprintf(mat, sizeof mat, "{model: lps, density: 2700, youngs_modulus: %.17g, poisson_ratio: 0.3}", E_MOD);
  else
    snprintf(mat, sizeof mat, "{model: pmb, density: 2700, youngs_modulus: %.17g}", E_MOD);
  snprintf(deck, sizeof deck,
           "dimension: %d\n%s"
           "materials:\n  mat: %s\n"
           "discretization:\n  spacing: %.17g\n  horizon: \"%s\"\n  partial_stress: %s\n%s"
           "  fill: [{shape: box, min: %s, max: %s}]\n"
           "solver: {type: explicit, steps: 1, breaking: false}\n"
           "output: {picture: false}\n",
           c->dim, c->dim == 2 ? "plane: stress\n" : "", mat, DX, c->horizon, coupling,
           c->dim == 2 ? "  thickness: 1.0e-3\n" : "", lo, hi);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  cr_assert_not_null(s->disc.horizon_field);
}

/* the force scale of test_variable_horizon.c: plane stress 9E/delta, 3D 24K/delta, at the largest
 * horizon (K of nu = 0.3, the smaller of the two models') */
static double force_scale(const shear_case *c) {
  const double K = E_MOD / (3.0 * (1.0 - 2.0 * 0.3));
  return c->dim == 3 ? 24.0 * K / c->delta_max : 9.0 * E_MOD / c->delta_max;
}

/* f of u = scale (a + H x) into f (3 n) */
static void force_at(peri_sim *s, const shear_case *c, double scale, double *f) {
  const double *H = c->dim == 2 ? H_2D : H_3D;
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    for (int a = 0; a < 3; ++a) {
      double u = 0.0;
      if (a < c->dim) {
        u = OFFSET[a];
        for (int b = 0; b < c->dim; ++b) u += H[3 * a + b] * s->disc.p.x[3 * i + b];
      }
      s->disc.p.u[3 * i + a] = scale * u;
    }
  s->mat.model->force(s);
  memcpy(f, s->disc.p.f, 3 * sizeof(double) * (size_t)s->disc.p.n);
}

typedef struct {
  double worst[3]; /* largest interior |f| / (S |H|) at full-PD, coupled and local nodes */
  int count[3];
} shear_result;

/* The largest interior |f| (nodes farther than 2 delta_max + 2 dx from every face) over S |H|. */
static shear_result interior(const peri_sim *s, const shear_case *c, const double *f, double amount) {
  const peri_horizon_field *h = s->disc.horizon_field;
  const double scale = force_scale(c) * amount, limit = 2.0 * c->delta_max + 2.0 * DX;
  shear_result r = {{0, 0, 0}, {0, 0, 0}};
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
    double depth = INFINITY;
    for (int k = 0; k < c->dim; ++k) depth = fmin(depth, 0.5 * c->n[k] * DX - fabs(s->disc.p.x[3 * i + k]));
    if (depth <= limit) continue;
    const int kind = h->local && h->local[i] ? 2 : h->coupled[i] ? 1 : 0;
    const double *fi = f + 3 * (size_t)i;
    r.worst[kind] = fmax(r.worst[kind], sqrt(fi[0] * fi[0] + fi[1] * fi[1] + fi[2] * fi[2]) / scale);
    r.count[kind]++;
  }
  return r;
}

/* The interior force of the deck under u = a + Hx: its first-order part (above) into *linear,
 * and the force itself at |H| = 0.02 into *finite. */
static void measure(const shear_case *c, const char *coupling, shear_result *linear, shear_result *finite) {
  peri_sim s;
  build(&s, c, coupling);
  const size_t n3 = 3 * (size_t)s.disc.p.n;
  double *f = calloc(n3, sizeof(double)), *g = malloc(n3 * sizeof(double));
  static const double factor[4] = {1.0, -1.0, 2.0, -2.0}, weight[4] = {8.0, -8.0, -1.0, 1.0};
  for (int q = 0; q < 4; ++q) {
    force_at(&s, c, factor[q] * PROBE, g);
    for (size_t k = 0; k < n3; ++k) f[k] += weight[q] * g[k] / 12.0;
  }
  *linear = interior(&s, c, f, PROBE);
  force_at(&s, c, 0.02, g);
  *finite = interior(&s, c, g, 0.02);
  free(f), free(g);
  peri_sim_free(&s);
}

static void check(shear_case c, bool local) {
  static const char *const kind_name[3] = {"full PD", "coupled", "local"};
  shear_result ps, finite;
  measure(&c, "auto", &ps, &finite);
  cr_log_info("%s %dD %s: first-order interior |f| / (S |H|): full PD %.2e (%d nodes), coupled %.2e (%d), local %.2e "
              "(%d); at |H| = 0.02: %.2e, %.2e, %.2e",
              c.model, c.dim, c.horizon, ps.worst[0], ps.count[0], ps.worst[1], ps.count[1], ps.worst[2], ps.count[2],
              finite.worst[0], finite.worst[1], finite.worst[2]);
  for (int k = 0; k < (local ? 3 : 2); ++k) {
    cr_assert_gt(ps.count[k], 0, "no interior %s node: the test would be vacuous", kind_name[k]);
    cr_expect(ps.worst[k] <= 1e-10, "%s %dD: the %s nodes' interior |f| = %.3g S|H| > 1e-10", c.model, c.dim,
              kind_name[k], ps.worst[k]);
  }
  if (!local) { /* the ghost forces of full PD on the same grid */
    shear_result pd;
    measure(&c, "none", &pd, &finite);
    cr_log_info("%s %dD %s: full PD everywhere, first-order interior |f| / (S |H|) %.2e", c.model, c.dim, c.horizon,
                pd.worst[0]);
    cr_expect(pd.worst[0] >= 1e-4, "%s %dD full PD: max interior |f| = %.3g S|H|: the ghost forces are missing",
              c.model, c.dim, pd.worst[0]);
  }
}

/* (a) two horizons: the steps and ramp of test_variable_horizon.c */
Test(shear_patch, two_horizons_pmb_2d) { check((shear_case){2, "pmb", "x < 0 ? 0.003 : 0.005", 0.005, {50, 30, 1}}, false); }
Test(shear_patch, two_horizons_lps_2d) {
  check((shear_case){2, "lps", "0.004 + 0.001 * (x < -0.005 ? -1 : x > 0.005 ? 1 : sin(pi * x / 0.01))", 0.005,
                     {50, 30, 1}}, false);
}
Test(shear_patch, two_horizons_pmb_3d) { check((shear_case){3, "pmb", "x < 0 ? 0.002 : 0.003", 0.003, {24, 18, 18}}, false); }
Test(shear_patch, two_horizons_lps_3d) { check((shear_case){3, "lps", "x < 0 ? 0.002 : 0.003", 0.003, {24, 18, 18}}, false); }
/* (b) a PD band, local outside: the cases of test_local_coupling.c */
Test(shear_patch, local_pmb_2d) { check((shear_case){2, "pmb", "abs(x) < 0.009 ? 0.003 : 0", 0.003, {50, 30, 1}}, true); }
Test(shear_patch, local_lps_2d) { check((shear_case){2, "lps", "abs(x) < 0.009 ? 0.003 : 0", 0.003, {50, 30, 1}}, true); }
Test(shear_patch, local_pmb_3d) { check((shear_case){3, "pmb", "abs(x) < 0.006 ? 0.002 : 0", 0.002, {30, 14, 14}}, true); }
Test(shear_patch, local_lps_3d) { check((shear_case){3, "lps", "abs(x) < 0.006 ? 0.002 : 0", 0.002, {30, 14, 14}}, true); }
