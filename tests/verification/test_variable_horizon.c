/* Patch test with a horizon that varies (docs/variable_horizon.md, docs/model_reference.md 15;
 * Silling, Littlewood and Seleson 2013, "Patch test requirement for a coupling method").
 * Under u = a + Hx the interior force density must vanish. With the partial-stress force in
 * the coupling region (the default: nodes whose family holds a different horizon) it does to
 * round-off, in 1D for any H and in 2D and 3D for the dilatation H = h I (a general H:
 * tests/verification/test_shear_patch.c), for PMB and LPS; the
 * full peridynamic force on the same grid does not ("Full PD shows artifacts"), and the test
 * measures those ghost forces too, so that either regression is caught.
 *
 * Why round-off: under u = a + Hx every node's partial stress nu0_i = sum_j T_i<xi> (x) xi V_j
 * is the same tensor. In 1D the per-node constants are calibrated on the node's own family
 * (PMB c_i from sum beta |xi| V, LPS m_i), so nu0_i = E H exactly; in 2D and 3D under a
 * dilatation the bond stretches all equal h and nu0_i is the per-node constant times the
 * second moment sum omega beta V xi (x) xi of i's family, which on a square or cubic lattice is
 * isotropic and, with the calibration, gives nu0_i = (stress of the dilatation) I whatever
 * delta_i, which the lattice correction C_iso D_i^-1 keeps (on a full family D_i : I = C_iso : I).
 * The least-squares divergence of a constant field is zero. Round-off: a bond's
 * extension carries an absolute error of a few eps |x|max (|x| <= 0.05 m here) against
 * h |xi| >= 0.02 x 1e-3 m, a relative 1e-12; the force is a difference of nu0 over dx ~
 * delta/3 of sums of such terms, so |f| <= ~1e-11 of the force scale S |H| below: the limit
 * 1e-10 S |H| holds with margin. */
#include "peri/horizon_field.h"
#include "peri/setup.h"
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "support.h"

#define DX 1.0e-3
#define E_MOD 70.0e9
#define STRAIN 0.02 /* the seed's patch test: u = 0.02 x */

typedef struct {
  int dim;
  const char *model;
  const char *horizon;   /* expression of x (m) */
  double delta_max;
  int n[3];              /* cells per side */
  const char *coupling;  /* partial_stress: auto or none */
} vh_case;

static void build(peri_sim *s, const vh_case *c) {
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
           c->dim, c->dim == 2 ? "plane: stress\n" : "", mat, DX, c->horizon, c->coupling,
           c->dim == 2 ? "  thickness: 1.0e-3\n" : "", lo, hi);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  cr_assert_not_null(s->disc.horizon_field);
}

/* Distance of node i from the nearest face. */
static double depth(const peri_sim *s, const vh_case *c, int32_t i) {
  double d = INFINITY;
  for (int k = 0; k < c->dim; ++k) d = fmin(d, 0.5 * c->n[k] * DX - fabs(s->disc.p.x[3 * i + k]));
  return d;
}

/* Force-density scale of a full family at unit stretch (tests/verification/test_patch.c): the
 * constant-influence PMB micromodulus times the horizon's volume, 1D 4E/delta, plane stress
 * 9E/delta, 3D 24K/delta, at the largest horizon (the smallest scale: the stricter bound). */
static double force_scale(const vh_case *c) {
  const double K = E_MOD / (3.0 * (1.0 - 2.0 * 0.3));
  if (c->dim == 3) return 24.0 * K / c->delta_max;
  return (c->dim == 1 ? 4.0 : 9.0) * E_MOD / c->delta_max;
}

typedef struct {
  double worst;     /* largest interior |f| */
  int interior, coupled_interior;
} patch_result;

/* u = a + H x with H = STRAIN I (in 1D: u = 0.02 x + a), the force, and the largest |f| over the
 * nodes farther than 2 delta_max + 2 dx from every face (their families, their neighbours'
 * families and the gradient stencils' are all full). */
static patch_result run_patch(const vh_case *c) {
  peri_sim s;
  build(&s, c);
  const peri_horizon_field *h = s.disc.horizon_field;
  for (int32_t i = 0; i < s.disc.p.n; ++i)
    for (int a = 0; a < 3; ++a) s.disc.p.u[3 * i + a] = a < c->dim ? 1.0e-4 + STRAIN * s.disc.p.x[3 * i + a] : 0.0;
  s.solver.breaking = false;
  s.mat.model->force(&s);
  patch_result r = {0.0, 0, 0};
  const double limit = 2.0 * c->delta_max + 2.0 * DX;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    if (depth(&s, c, i) <= limit) continue;
    const double *f = &s.disc.p.f[3 * i];
    r.worst = fmax(r.worst, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
    r.interior++;
    r.coupled_interior += h->coupled[i];
  }
  peri_sim_free(&s);
  return r;
}

/* The partial-stress run passes the patch test to round-off; full peridynamics on the same
 * grid shows ghost forces above 1e-4 S |H| (the seed's artifacts are of the order of the
 * strain itself; round-off is 1e-11). */
static void check(vh_case c) {
  const double scale = force_scale(&c) * STRAIN;
  c.coupling = "auto";
  const patch_result ps = run_patch(&c);
  c.coupling = "none";
  const patch_result pd = run_patch(&c);
  cr_log_info("%s %dD delta %s: interior |f| / (S |H|) partial stress %.2e, full PD %.2e (%d interior nodes, %d "
              "coupled)", c.model, c.dim, c.horizon, ps.worst / scale, pd.worst / scale, ps.interior, ps.coupled_interior);
  cr_assert_gt(ps.coupled_interior, 0, "the coupling region has no interior node: the test would be vacuous");
  cr_expect(ps.worst <= 1e-10 * scale, "%s %dD partial stress: max interior |f| = %.3g S|H| > 1e-10", c.model, c.dim,
            ps.worst / scale);
  cr_expect(pd.worst >= 1e-4 * scale, "%s %dD full PD: max interior |f| = %.3g S|H|: the ghost forces are missing",
            c.model, c.dim, pd.worst / scale);
}

/* a step of the horizon at x = 0, and a smooth ramp over |x| < 10 dx (3 dx to 6 dx) */
#define STEP_1D "x < 0 ? 0.003 : 0.006"
#define RAMP_1D "0.0045 + 0.0015 * (x < -0.01 ? -1 : x > 0.01 ? 1 : sin(pi * x / 0.02))"

Test(variable_horizon, patch_pmb_1d_step) { check((vh_case){1, "pmb", STEP_1D, 0.006, {80, 1, 1}, NULL}); }
Test(variable_horizon, patch_pmb_1d_ramp) { check((vh_case){1, "pmb", RAMP_1D, 0.006, {80, 1, 1}, NULL}); }
Test(variable_horizon, patch_lps_1d_step) { check((vh_case){1, "lps", STEP_1D, 0.006, {80, 1, 1}, NULL}); }
Test(variable_horizon, patch_lps_1d_ramp) { check((vh_case){1, "lps", RAMP_1D, 0.006, {80, 1, 1}, NULL}); }
Test(variable_horizon, patch_pmb_2d_step) {
  check((vh_case){2, "pmb", "x < 0 ? 0.003 : 0.005", 0.005, {50, 30, 1}, NULL});
}
Test(variable_horizon, patch_lps_2d_ramp) {
  check((vh_case){2, "lps", "0.004 + 0.001 * (x < -0.005 ? -1 : x > 0.005 ? 1 : sin(pi * x / 0.01))", 0.005,
                  {50, 30, 1}, NULL});
}
Test(variable_horizon, patch_lps_3d_step) {
  check((vh_case){3, "lps", "x < 0 ? 0.002 : 0.003", 0.003, {24, 18, 18}, NULL});
}
Test(variable_horizon, patch_pmb_3d_step) {
  check((vh_case){3, "pmb", "x < 0 ? 0.002 : 0.003", 0.003, {24, 18, 18}, NULL});
}
