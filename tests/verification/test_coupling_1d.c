/* The 1D PD-FEM coupling under imposed displacement fields (002_b20c318388227af9.txt
 * §2.4.1, §2.6.1, MODELS.md 14; docs/coupling.md): a bar of L = 30 with nodes at x = 0, dx,
 * ..., 30, PD nodes in [10, 20], 2-node bars elsewhere, E = A = 1, c(|xi|) = 2E/(A delta^2 |xi|)
 * with the half rule at |xi| = delta (partial_volume: lammps). The reactions F = K u of an
 * imposed u give e_r = |sum F| / sum |F| (eq. 2.38).
 *  - Linear patch test: u = a + b x everywhere gives e_r at round-off (1e-13: the sums have
 *    ~100 terms of relative rounding 1e-16).
 *  - Quartic and cubic curves (Tables 2.2, 2.9) away from the coupling zones, cases (a)-(c):
 *    e_r at round-off (the seed prints 1e-16 .. 2e-15).
 *  - Cubic curve over the right interface x_IR = 20 + dx/2 (case (e), X1 = 17, X2 = 24): the
 *    sum of the reactions is -(tau_num + t_num) = -(1/24)(1 - 1/m^2) E delta^2 u'''(x_IR)
 *    exactly (eqs. 2.108, 2.111: the nonlocal traction is exact for cubic fields, the local
 *    one has the error dx^2 u'''/24), to the round-off 1e-12 sum |F|; and e_r and sum F match Tables 2.11
 *    and 2.12 to their printed 3 digits (half a unit of the last digit) for m = 3, 6, 12 and
 *    delta = 3, 1.5, 0.5.
 *  - The tractions of coupling.tractions at both interfaces for the same curve: the nonlocal
 *    (eq. A.15) plus the local one (eq. 2.107) is -sum F (eq. 2.108) to round-off and Table 2.12's
 *    last column to its 3 digits (m = 3, 6, 12); the local one is eq. 2.110's, exactly.
 *  - Quartic curve over the right interface: sum F / delta^2 and e_r of Table 2.4 (cases (e) to
 *    (i)) to their printed digits, which shows the delta^2 convergence of the imbalance.
 *  - The discrete nonlocal traction at x0 = 20.5 (eq. A.15, Table A.2) for the linear, quadratic
 *    and cubic fields of Table A.1 (g = 1e-4, X1 = 17) equals the analytic one, E u'(x0) plus
 *    (1/24) E delta^2 u''' (eq. A.8 with alpha = 1, exact for cubic fields), to round-off (the
 *    seed prints errors of 1e-20 on 1e-4), and the printed values to 3 digits.
 * X1 = 17 and X2 = 24 are read from Figures 2.6 and 2.16 (docs/coupling.md): with them the
 * printed sums, fixed by X1 alone, and the printed e_r, which depend on X2, agree. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include "peri/coupling.h"
#include "peri/sim.h"
#include "support.h"

static void build_bar(peri_sim *s, double delta, double m) {
  const double dx = delta / m;
  char deck[1024];
  snprintf(deck, sizeof deck,
           "dimension: 1\n"
           "materials: {bar: {model: pmb, density: 1, youngs_modulus: 1}}\n"
           "discretization: {spacing: %.17g, m: %.17g, cross_section: 1, partial_volume: lammps,\n"
           "                 fill: [{shape: interval, min: [%.17g], max: [%.17g]}]}\n"
           "regions: {pd: {shape: interval, min: [%.17g], max: [%.17g]}}\n"
           "coupling: {pd_region: pd, tractions: {left: {at: [%.17g], normal: -x}, right: {at: [%.17g], normal: +x}}}\n"
           "solver: {type: implicit, load_steps: 1}\n"
           "output: {picture: false}\n",
           dx, m, -0.5 * dx, 30.0 + 0.5 * dx, 10.0 - 0.25 * dx, 20.0 + 0.25 * dx, 10.0 - 0.5 * dx, 20.0 + 0.5 * dx);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  cr_assert_not_null(s->coupling);
  cr_assert_eq(s->disc.p.n, (int32_t)lround(30.0 / dx) + 1);
  cr_assert_eq(s->coupling->n_tractions, 2);
}

typedef enum { QUARTIC, CUBIC, LINEAR } curve;

/* Tables 2.2 (quartic, a = 1e-4) and 2.9 (cubic, g = 1e-4): linear, curve on (X1, X2), linear. */
static double field(curve c, double x, double X1, double X2) {
  const double a = 1e-4;
  if (c == LINEAR) return 0.3 + a * x;
  if (c == QUARTIC) {
    if (x < X1) return a * x;
    if (x < X2) return a / (4 * X1 * X1 * X1) * pow(x, 4) + 0.75 * a * X1;
    return a * pow(X2 / X1, 3) * (x - X2) + a / (4 * X1 * X1 * X1) * (pow(X2, 4) + 3 * pow(X1, 4));
  }
  if (x < X1) return a * x;
  if (x < X2) return a / (3 * X1 * X1) * pow(x, 3) + 2.0 * a / 3.0 * X1;
  return a * pow(X2 / X1, 2) * (x - X2) + a / (3 * X1 * X1) * (pow(X2, 3) + 2 * pow(X1, 3));
}

/* Imposes the curve, and returns sum F and e_r. */
static void imposed(double delta, double m, curve c, double X1, double X2, double *sum, double *e_r) {
  peri_sim s;
  build_bar(&s, delta, m);
  for (int32_t i = 0; i < s.disc.p.n; ++i) s.disc.p.u[3 * (size_t)i] = field(c, s.disc.p.x[3 * (size_t)i], X1, X2);
  peri_coupling_force(&s);
  double net[3], ratio[4];
  peri_coupling_balance(&s, net, ratio);
  *sum = net[0], *e_r = ratio[0];
  cr_expect(fabs(ratio[3] - ratio[0]) <= 1e-15, "1D: the vector e_r is e_rx");
  peri_sim_free(&s);
}

/* got agrees with the printed value to its 3 significant digits */
static void expect_printed(double got, double printed, const char *what) {
  const double unit = pow(10.0, floor(log10(fabs(printed))) - 2);
  cr_expect(fabs(got - printed) <= 0.5 * unit + 1e-12 * fabs(printed), "%s: %.6e, printed %.2e", what, got, printed);
}

Test(coupling_1d, linear_patch_test_balances_to_roundoff) {
  double sum, e_r;
  imposed(3.0, 3.0, LINEAR, 0, 0, &sum, &e_r);
  cr_expect(e_r <= 1e-13, "e_r %.3e", e_r);
}

Test(coupling_1d, curves_away_from_the_coupling_zones_balance) {
  /* (a) left FEM part, (b) PD part, (c) right FEM part: linear over both coupling zones */
  const double X[3][2] = {{2, 6}, {13, 17}, {24.5, 28.5}};
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 2; ++c) {
      double sum, e_r;
      imposed(3.0, 3.0, c == 0 ? QUARTIC : CUBIC, X[k][0], X[k][1], &sum, &e_r);
      cr_expect(e_r <= 1e-13, "case (%c) %s: e_r %.3e", 'a' + k, c == 0 ? "quartic" : "cubic", e_r);
    }
}

Test(coupling_1d, cubic_over_the_interface_tables_2_11_2_12) {
  static const struct {
    double delta, m, e_r, sum_over_delta2, sum;
  } table[] = {{3, 3, 5.78e-4, -2.56e-8, -2.31e-7}, {3, 6, 6.33e-4, -2.80e-8, -2.52e-7},
               {3, 12, 6.46e-4, -2.86e-8, -2.58e-7}, {1.5, 3, 1.45e-4, -2.56e-8, 0},
               {0.5, 3, 1.61e-5, -2.56e-8, 0}};
  const double X1 = 17, X2 = 24, E = 1.0;
  for (size_t k = 0; k < sizeof table / sizeof table[0]; ++k) {
    const double delta = table[k].delta, m = table[k].m, dx = delta / m;
    double sum, e_r;
    imposed(delta, m, CUBIC, X1, X2, &sum, &e_r);
    const double u3 = 2e-4 / (X1 * X1); /* u''' of the cubic curve */
    const double theory = -(1.0 / 24.0) * (1.0 - 1.0 / (m * m)) * E * delta * delta * u3;
    /* round-off: the sum cancels down to e_r of sum |F| (1.6e-5 at delta = 0.5), whose own
     * rounding is below 1e-12 sum |F| */
    cr_expect(fabs(sum - theory) <= 1e-12 * fabs(sum) / e_r, "delta %g m %g: sum F %.10e, eq. 2.111 %.10e (x_IR %g)",
              delta, m, sum, theory, 20 + dx / 2);
    char what[64];
    snprintf(what, sizeof what, "delta %g m %g e_r", delta, m);
    expect_printed(e_r, table[k].e_r, what);
    snprintf(what, sizeof what, "delta %g m %g sum F / delta^2", delta, m);
    expect_printed(sum / (delta * delta), table[k].sum_over_delta2, what);
    if (table[k].sum != 0.0) {
      snprintf(what, sizeof what, "delta %g m %g sum F", delta, m);
      expect_printed(sum, table[k].sum, what);
    }
  }
}

/* Table 2.12's last column: the sum of the discrete nonlocal traction (eq. A.15) and the local
 * one (eq. 2.107) at the right interface, read at the points of coupling.tractions. The local
 * one is -E u'(x_IR) - E dx^2 u'''(x_IR)/24 (eq. 2.110, exact for the cubic); the sum balances
 * the reactions, sum F = -(tau + t) (eq. 2.108), to round-off; at the left interface the field
 * is linear and the two cancel. */
Test(coupling_1d, interface_tractions_table_2_12) {
  static const struct {
    double m, printed;
  } table[] = {{3, 2.31e-7}, {6, 2.52e-7}, {12, 2.58e-7}};
  const double X1 = 17, X2 = 24, E = 1.0, delta = 3.0;
  for (size_t k = 0; k < sizeof table / sizeof table[0]; ++k) {
    const double m = table[k].m, dx = delta / m, x_ir = 20.0 + 0.5 * dx;
    peri_sim s;
    build_bar(&s, delta, m);
    for (int32_t i = 0; i < s.disc.p.n; ++i) s.disc.p.u[3 * (size_t)i] = field(CUBIC, s.disc.p.x[3 * (size_t)i], X1, X2);
    peri_coupling_force(&s);
    double net[3], ratio[4], tau[2][3], t[2][3];
    peri_coupling_balance(&s, net, ratio);
    for (int side = 0; side < 2; ++side) {
      const peri_interface_traction *tr = &s.coupling->traction[side];
      peri_coupling_nonlocal_traction(&s, tr->at, tr->axis, tr->sign, tau[side]);
      peri_coupling_local_traction(&s, tr, t[side]);
    }
    const double du = 1e-4 * x_ir * x_ir / (X1 * X1), d3u = 2e-4 / (X1 * X1);
    const double local = -E * (du + dx * dx * d3u / 24.0);
    cr_expect(fabs(t[1][0] - local) <= 1e-12 * fabs(local), "m %g: t_num %.12e, eq. 2.110 %.12e", m, t[1][0], local);
    const double sum = tau[1][0] + t[1][0];
    cr_expect(fabs(sum + net[0]) <= 1e-12 * fabs(net[0]) / ratio[0], "m %g: tau + t %.10e, -sum F %.10e", m, sum,
              -net[0]);
    expect_printed(sum, table[k].printed, "tau_num + t_num (Table 2.12)");
    cr_expect(fabs(tau[0][0] + t[0][0]) <= 1e-15, "m %g: left interface tau %.6e + t %.6e", m, tau[0][0], t[0][0]);
    cr_expect(fabs(t[0][0] - 1e-4 * E) <= 1e-15, "m %g: left t(x_IL, +1) = E u' = 1e-4: %.12e", m, t[0][0]);
    peri_sim_free(&s);
  }
}

Test(coupling_1d, quartic_over_the_interface_table_2_4) {
  static const struct {
    double delta, m, e_r, sum_over_delta2;
  } table[] = {{3, 3, 1.48e-3, -9.27e-8}, {3, 6, 1.60e-3, -1.00e-7}, {3, 12, 1.62e-3, -1.02e-7},
               {1.5, 3, 3.66e-4, -9.16e-8}, {0.5, 3, 4.04e-5, -9.08e-8}};
  for (size_t k = 0; k < sizeof table / sizeof table[0]; ++k) {
    double sum, e_r;
    imposed(table[k].delta, table[k].m, QUARTIC, 17, 24, &sum, &e_r);
    char what[64];
    snprintf(what, sizeof what, "delta %g m %g e_r", table[k].delta, table[k].m);
    expect_printed(e_r, table[k].e_r, what);
    snprintf(what, sizeof what, "delta %g m %g sum F / delta^2", table[k].delta, table[k].m);
    expect_printed(sum / (table[k].delta * table[k].delta), table[k].sum_over_delta2, what);
  }
}

Test(coupling_1d, nonlocal_traction_table_a_2) {
  const double g = 1e-4, X1 = 17, x0 = 20.5, delta = 3, E = 1;
  static const double printed[3] = {1.00e-4, 1.21e-4, 1.46e-4};
  for (int k = 0; k < 3; ++k) {
    peri_sim s;
    build_bar(&s, delta, 3);
    for (int32_t i = 0; i < s.disc.p.n; ++i) {
      const double x = s.disc.p.x[3 * (size_t)i];
      s.disc.p.u[3 * (size_t)i] = k == 0 ? g * x : k == 1 ? g / (2 * X1) * x * x : g / (3 * X1 * X1) * x * x * x;
    }
    const double at[3] = {x0, 0, 0};
    double tau[3];
    peri_coupling_nonlocal_traction(&s, at, 0, +1, tau);
    const double du = k == 0 ? g : k == 1 ? g * x0 / X1 : g * x0 * x0 / (X1 * X1);
    const double d3u = k == 2 ? 2 * g / (X1 * X1) : 0.0;
    const double analytic = E * du + E * delta * delta * d3u / 24.0;
    cr_expect(fabs(tau[0] - analytic) <= 1e-12 * analytic, "field %d: tau_num %.12e, eq. A.8 %.12e", k, tau[0], analytic);
    expect_printed(tau[0], printed[k], "tau_num (Table A.2)");
    peri_sim_free(&s);
  }
}
