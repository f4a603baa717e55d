/* Sublayer plasticity (docs/plasticity.md, model reference 16): uniaxial bars driven through
 * homogeneous deformations, stress read at a node more than 2 delta inside by the PD stress
 * recovery.
 *  - Monotonic loading follows the piecewise-linear curve through the breakpoints of
 *    Ebrahimi Table 5.2 (sigma = sigma0 (eps/eps0)^0.1, sigma0 = 400 MPa, eps0 = 0.002 at eps
 *    = 0.002, 0.0065, 0.0124, 0.0168) within 2%, and is flat beyond the last one.
 *  - Unloading is elastic with slope E (within 1%).
 *  - Reversed loading (Masing rule of kinematic hardening): from a peak at eps_a the reverse
 *    curve is the monotonic one doubled, sigma_a - sigma = 2 f((eps_a - eps)/2), so the bar
 *    yields again after a drop of 2 sigma_y and passes 2 sigma_k at every breakpoint of the
 *    reverse branch (within 2%).
 *  - Rate dependence (Cowper-Symonds, model reference 16.3): at a constant strain rate every
 *    bond of the 1D bar has the stretch rate eps_dot, so its yield stretches scale by
 *    kappa = 1 + (eps_dot / d)^(1/p) and the curve is the static one scaled by kappa in
 *    strain and stress: sigma(kappa eps_k) = kappa sigma_k at every breakpoint (within 2%),
 *    and elastic (E_pd eps) up to kappa eps_1. d = 40.4 /s, p = 5: mild steel (Jones,
 *    Structural Impact, 1989, Table 8.1).
 * The elastic modulus the discrete sums give at this node is not E exactly (quadrature); the
 * stresses are compared with E_pd times the curve over E, E_pd the slope measured in the
 * elastic range, and E_pd itself with E within 2% (1D) and 3% (3D, m = 3). */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include "peri/plasticity.h"
#include "peri/tensor_plasticity.h"
#include "peri/plastic_fields.h"
#include "peri/setup.h"
#include "peri/stress.h"
#include "support.h"

#define E_STEEL 200e9
#define SIGMA0 400e6
#define EPS0 0.002
static const double breakpoints[4] = {0.002, 0.0065, 0.0124, 0.0168};

/* The bar: 1D PMB, or a 3D PMB or LPS block, with the Table 5.2 curve. */
static const char *const table_5_2 = "    plasticity:\n"
                                     "      strains: [0.002, 0.0065, 0.0124, 0.0168]\n"
                                     "      power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}\n";
/* the same with Cowper-Symonds rate dependence */
#define RATE_D 40.4
#define RATE_P 5.0
static const char *const table_5_2_rate = "    plasticity:\n"
                                          "      strains: [0.002, 0.0065, 0.0124, 0.0168]\n"
                                          "      power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}\n"
                                          "      cowper_symonds: {d: 40.4, p: 5}\n";

static void build_with(peri_sim *s, int dim, const char *model, const char *plasticity) {
  char deck[2048];
  if (dim == 1)
    snprintf(deck, sizeof deck,
             "dimension: 1\n"
             "materials:\n"
             "  steel:\n"
             "    model: %s\n"
             "    density: 7800\n"
             "    youngs_modulus: 200e9\n"
             "%s"
             "discretization: {spacing: 0.01, m: 3, cross_section: 1e-4, fill: [{shape: interval, min: [0], max: [0.3]}]}\n"
             "solver: {type: explicit, steps: 1, breaking: false}\n"
             "output: {picture: false}\n",
             model, plasticity);
  else
    snprintf(deck, sizeof deck,
             "dimension: 3\n"
             "materials:\n"
             "  steel:\n"
             "    model: %s\n"
             "    density: 7800\n"
             "    youngs_modulus: 200e9\n"
             "%s"
             "%s"
             "discretization: {spacing: 1e-3, m: 3, fill: [{shape: box, min: [0, 0, 0], max: [0.015, 0.015, 0.015]}]}\n"
             "solver: {type: explicit, steps: 1, breaking: false}\n"
             "output: {picture: false}\n",
             model, strcmp(model, "lps") ? "" : "    poisson_ratio: 0.25\n", plasticity);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
}

static void build(peri_sim *s, int dim, const char *model, bool plastic) {
  build_with(s, dim, model, plastic ? table_5_2 : "");
}

/* The node nearest the centre of the body. */
static int32_t centre_node(const peri_sim *s) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, best = INFINITY;
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    for (int d = 0; d < 3; ++d) lo[d] = fmin(lo[d], s->disc.p.x[3 * i + d]), hi[d] = fmax(hi[d], s->disc.p.x[3 * i + d]);
  int32_t c = 0;
  for (int32_t i = 0; i < s->disc.p.n; ++i) {
    double r2 = 0.0;
    for (int d = 0; d < 3; ++d) r2 += pow(s->disc.p.x[3 * i + d] - 0.5 * (lo[d] + hi[d]), 2);
    if (r2 < best) best = r2, c = i;
  }
  return c;
}

/* sigma_xx at node c under the uniaxial strain eps along x (lateral contraction -nu eps in
 * 3D, nu = 1/4 the Poisson ratio of the elastic bar; plastic bonds in 3D see different
 * stretches, docs/plasticity.md). */
static double stress_at(peri_sim *s, int32_t c, double eps, double *sig) {
  const int dim = s->disc.geom.dim;
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    for (int d = 0; d < 3; ++d)
      s->disc.p.u[3 * i + d] = d == 0 ? eps * s->disc.p.x[3 * i] : d < dim ? -0.25 * eps * s->disc.p.x[3 * i + d] : 0.0;
  cr_assert_eq(peri_stress(s, sig), 0);
  return sig[9 * c];
}

/* Walks eps from a to b in increments of at most h, returning sigma at b. */
static double walk(peri_sim *s, int32_t c, double a, double b, double h, double *sig) {
  const int n = (int)ceil(fabs(b - a) / h);
  double out = 0.0;
  for (int k = 1; k <= n; ++k) out = stress_at(s, c, a + (b - a) * k / n, sig);
  return out;
}

/* 1D: the bar follows the curve of Table 5.2 (every bond at the bar's strain). */
static void check_bar_1d(void) {
  peri_sim s;
  build(&s, 1, "pmb", true);
  const int32_t c = centre_node(&s);
  double *sig = malloc(sizeof(double) * 9 * (size_t)s.disc.p.n);
  const peri_sublayers *sl = s.mat.materials[0].sublayers;
  cr_assert(sl && sl->n == 4);
  const double h = 5e-5;
  /* elastic slope */
  const double e_small = 0.5 * EPS0;
  const double E_pd = walk(&s, c, 0.0, e_small, h, sig) / e_small;
  cr_log_info("1D: E_pd = %.5g (E %.5g)", E_pd, E_STEEL);
  cr_expect(fabs(E_pd / E_STEEL - 1.0) < 0.02, "1D: elastic modulus %g, expected %g within 2%%", E_pd, E_STEEL);
  /* monotonic: every breakpoint, then beyond the last */
  double eps = e_small;
  for (int k = 0; k < 4; ++k) {
    const double sigma = walk(&s, c, eps, breakpoints[k], h, sig);
    eps = breakpoints[k];
    const double expected = SIGMA0 * pow(breakpoints[k] / EPS0, 0.1) * E_pd / E_STEEL;
    cr_log_info("1D: eps %.4f sigma %.5g expected %.5g (%.3f%%)", eps, sigma, expected, 100 * (sigma / expected - 1));
    cr_expect(fabs(sigma / expected - 1.0) < 0.02, "1D: at breakpoint %.4f sigma %g, expected %g within 2%%", eps,
              sigma, expected);
  }
  const double eps_a = 0.025;
  const double sigma_a = walk(&s, c, eps, eps_a, h, sig);
  const double flat = SIGMA0 * pow(breakpoints[3] / EPS0, 0.1) * E_pd / E_STEEL;
  cr_expect(fabs(sigma_a / flat - 1.0) < 0.02, "1D: beyond the last breakpoint sigma %g, expected flat %g", sigma_a,
            flat);
  /* unloading: elastic, slope E */
  const double d_el = 1.5 * EPS0;
  const double slope = (sigma_a - walk(&s, c, eps_a, eps_a - d_el, h, sig)) / d_el;
  cr_log_info("1D: unloading slope %.5g (E_pd %.5g)", slope, E_pd);
  cr_expect(fabs(slope / E_pd - 1.0) < 0.01, "1D: unloading slope %g, expected %g within 1%%", slope, E_pd);
  /* reversed loading: Masing, sigma_a - sigma(eps_a - 2 eps_k) = 2 sigma_k */
  eps = eps_a - d_el;
  for (int k = 0; k < 4; ++k) {
    const double target = eps_a - 2.0 * breakpoints[k];
    const double drop = sigma_a - walk(&s, c, eps, target, h, sig);
    eps = target;
    const double expected = 2.0 * SIGMA0 * pow(breakpoints[k] / EPS0, 0.1) * E_pd / E_STEEL;
    cr_log_info("1D: reverse eps %.4f drop %.5g expected %.5g (%.3f%%)", eps, drop, expected,
                100 * (drop / expected - 1));
    cr_expect(fabs(drop / expected - 1.0) < 0.02, "1D: reverse branch at %.4f: drop %g, Masing %g within 2%%", eps,
              drop, expected);
  }
  free(sig);
  peri_sim_free(&s);
}

/* 3D: the bonds of a node see different stretches (s = eps (c^2 - nu (1 - c^2)) for a bond
 * at angle arccos c to the axis), so the bar's curve is not the bond curve beyond the first
 * yield (docs/plasticity.md). What holds for any mix of directions under a proportional
 * path, and is checked here: elastic up to the first breakpoint (no bond stretches more
 * than the bar), elastic unloading with the loading slope, and the Masing rule of the bar's
 * own monotonic curve (every bond follows its own Masing loop, and the stress is their
 * sum): sigma_a - sigma(eps_a - 2 e) = 2 sigma_monotonic(e). */
static void check_bar_3d(const char *model) {
  peri_sim s;
  build(&s, 3, model, true);
  const int32_t c = centre_node(&s);
  double *sig = malloc(sizeof(double) * 9 * (size_t)s.disc.p.n);
  const double h = 1e-3;
  const double E_pd = walk(&s, c, 0.0, 0.5 * EPS0, h, sig) / (0.5 * EPS0);
  const double at_yield = walk(&s, c, 0.5 * EPS0, EPS0, h, sig);
  cr_log_info("3D %s: E_pd %.5g, sigma(eps_1) / (E_pd eps_1) = %.5f", model, E_pd, at_yield / (E_pd * EPS0));
  cr_expect(fabs(at_yield / (E_pd * EPS0) - 1.0) < 0.005, "3D %s: not elastic up to the first breakpoint", model);
  const double probes[3] = {0.5 * EPS0, EPS0, 2.0 * EPS0}; /* half-amplitudes of the reverse branch */
  double mono[3];
  double eps = EPS0;
  for (int k = 0; k < 3; ++k) {
    mono[k] = walk(&s, c, eps, probes[k], h, sig);
    eps = probes[k];
  }
  const double eps_a = 0.0124;
  const double sigma_a = walk(&s, c, eps, eps_a, h, sig);
  cr_log_info("3D %s: sigma at %.4f: %.5g (1D curve %.5g)", model, eps_a, sigma_a,
              SIGMA0 * pow(eps_a / EPS0, 0.1) * E_pd / E_STEEL);
  const double d_el = 0.5 * EPS0;
  const double slope = (sigma_a - walk(&s, c, eps_a, eps_a - d_el, h, sig)) / d_el;
  /* the elastic bar's slope over the same strains: the stretch is geometrically nonlinear,
   * so the tangent at eps_a differs from E_pd by O(eps_a), and that of a bond at elastic
   * stretch s - s^p from the elastic one by O(s^p) <= eps_a */
  peri_sim elastic;
  build(&elastic, 3, model, false);
  const double slope_el = (stress_at(&elastic, c, eps_a, sig) - stress_at(&elastic, c, eps_a - d_el, sig)) / d_el;
  peri_sim_free(&elastic);
  cr_log_info("3D %s: unloading slope %.5g (elastic bar %.5g, E_pd %.5g)", model, slope, slope_el, E_pd);
  cr_expect(fabs(slope / slope_el - 1.0) < eps_a, "3D %s: unloading slope %g, elastic %g", model, slope, slope_el);
  eps = eps_a - d_el;
  for (int k = 0; k < 3; ++k) {
    const double target = eps_a - 2.0 * probes[k];
    const double drop = sigma_a - walk(&s, c, eps, target, h, sig);
    eps = target;
    cr_log_info("3D %s: reverse eps %.4f drop %.5g, 2 sigma_monotonic %.5g (%.3f%%)", model, eps, drop, 2 * mono[k],
                100 * (drop / (2 * mono[k]) - 1));
    cr_expect(fabs(drop / (2.0 * mono[k]) - 1.0) < 0.02, "3D %s: reverse branch at %.4f: drop %g, Masing %g", model,
              eps, drop, 2.0 * mono[k]);
  }
  free(sig);
  peri_sim_free(&s);
}

/* 3D with the sublayers fitted to the family (calibration: family, docs/plasticity.md section
 * 4). The fit's model is the continuum family under uniaxial stress; its least-squares best
 * misses the curve by -9.3% at the first breakpoint and +4.2% at the second (no bond curve
 * with its tangent in [0, E] comes closer than -8.6% and +3.8% there: a direction average
 * cannot knee sharply), so the discrete block (m = 3) is asserted within 12% of the Table 5.2
 * curve at every breakpoint (that residual plus the 2% the 1D bar is held to), where the 1D
 * construction gives +50 to +61%. Under a proportional path every bond's stretch is
 * monotonic, so the walk takes large increments. Unloading and the Masing rule as
 * check_bar_3d. */
static const char *const table_5_2_family = "    plasticity:\n"
                                            "      strains: [0.002, 0.0065, 0.0124, 0.0168]\n"
                                            "      power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}\n"
                                            "      calibration: family\n";
static void check_bar_3d_family(const char *model) {
  peri_sim s;
  build_with(&s, 3, model, table_5_2_family);
  const int32_t c = centre_node(&s);
  double *sig = malloc(sizeof(double) * 9 * (size_t)s.disc.p.n);
  const peri_sublayers *sl = s.mat.materials[0].sublayers;
  cr_assert(sl && sl->n >= 2);
  const double h = 2e-3, e_small = 0.2 * EPS0;
  const double E_pd = walk(&s, c, 0.0, e_small, h, sig) / e_small;
  cr_log_info("3D %s family: %d sublayers, E_pd %.5g", model, sl->n, E_pd);
  double eps = e_small, mono[4];
  for (int k = 0; k < 4; ++k) {
    const double sigma = walk(&s, c, eps, breakpoints[k], h, sig) * E_STEEL / E_pd;
    mono[k] = sigma;
    eps = breakpoints[k];
    const double curve = SIGMA0 * pow(eps / EPS0, 0.1), model_fit = E_STEEL * peri_sublayers_family_stress(3, 0.25, sl, eps);
    cr_log_info("3D %s family: eps %.4f sigma %.5g curve %.5g (%+.2f%%) continuum fit %.5g (%+.2f%%)", model, eps, sigma,
                curve, 100 * (sigma / curve - 1), model_fit, 100 * (sigma / model_fit - 1));
    cr_expect(fabs(sigma / curve - 1.0) < 0.12, "3D %s family: at %.4f sigma %g, curve %g", model, eps, sigma, curve);
  }
  /* unloading from eps_a = the last breakpoint: the elastic bar's slope (check_bar_3d) */
  const double eps_a = eps, sigma_a = mono[3], d_el = 0.2 * EPS0;
  const double slope = (sigma_a - walk(&s, c, eps_a, eps_a - d_el, h, sig) * E_STEEL / E_pd) / d_el;
  cr_log_info("3D %s family: unloading slope %.5g (E %.5g)", model, slope, E_STEEL);
  cr_expect(fabs(slope / E_STEEL - 1.0) < eps_a, "3D %s family: unloading slope %g, E %g", model, slope, E_STEEL);
  /* Masing: the reverse branch drops by twice the monotonic stress at half the strain */
  eps = eps_a - d_el;
  for (int k = 0; k < 2; ++k) {
    const double target = eps_a - 2.0 * breakpoints[k];
    const double drop = sigma_a - walk(&s, c, eps, target, h, sig) * E_STEEL / E_pd;
    eps = target;
    cr_log_info("3D %s family: reverse eps %.4f drop %.5g, 2 sigma_monotonic %.5g (%+.2f%%)", model, eps, drop,
                2 * mono[k], 100 * (drop / (2 * mono[k]) - 1));
    cr_expect(fabs(drop / (2.0 * mono[k]) - 1.0) < 0.02, "3D %s family: reverse branch at %.4f: drop %g, Masing %g",
              model, eps, drop, 2.0 * mono[k]);
  }
  free(sig);
  peri_sim_free(&s);
}

/* 1D at the constant strain rate eps_dot (velocity eps_dot x): the static curve scaled by kappa. */
static void check_bar_1d_rate(void) {
  peri_sim s;
  build_with(&s, 1, "pmb", table_5_2_rate);
  const int32_t c = centre_node(&s);
  double *sig = malloc(sizeof(double) * 9 * (size_t)s.disc.p.n);
  const double eps_dot = 100.0, kappa = 1.0 + pow(eps_dot / RATE_D, 1.0 / RATE_P);
  for (int32_t i = 0; i < s.disc.p.n; ++i) s.disc.p.v[3 * i] = eps_dot * s.disc.p.x[3 * i];
  const double h = 5e-5, e_small = 0.5 * EPS0;
  const double E_pd = walk(&s, c, 0.0, e_small, h, sig) / e_small;
  cr_log_info("1D rate: kappa %.5f, E_pd %.5g", kappa, E_pd);
  /* elastic up to kappa eps_1 (the static curve has yielded at eps_1) */
  const double below = 0.95 * kappa * EPS0, sigma_below = walk(&s, c, e_small, below, h, sig);
  cr_expect(fabs(sigma_below / (E_pd * below) - 1.0) < 0.01, "1D rate: sigma %g at %g, elastic %g", sigma_below, below,
            E_pd * below);
  double eps = below;
  for (int k = 0; k < 4; ++k) {
    const double target = kappa * breakpoints[k];
    const double sigma = walk(&s, c, eps, target, h, sig);
    eps = target;
    const double expected = kappa * SIGMA0 * pow(breakpoints[k] / EPS0, 0.1) * E_pd / E_STEEL;
    cr_log_info("1D rate: eps %.5f sigma %.5g expected %.5g (%.3f%%)", eps, sigma, expected,
                100 * (sigma / expected - 1));
    cr_expect(fabs(sigma / expected - 1.0) < 0.02, "1D rate: at %.5f sigma %g, expected %g within 2%%", eps, sigma,
              expected);
  }
  free(sig);
  peri_sim_free(&s);
}

/* The deviatoric yield rule (yield_rule: deviatoric, docs/plasticity.md section 8) on the 3D
 * LPS block (m = 3, nu = 1/4) under uniaxial stress: u = (eps x, l y, l z) with the lateral
 * strain l solved at every increment so that sigma_yy = 0 at the centre node (the secant
 * method; the plastic state of the increment maps from the accepted one, as the quasi-static
 * solvers do, and is accepted when sigma_yy vanishes). With the bulk response elastic and
 * every bond of a node yielding together the block is von Mises with kinematic hardening by
 * overlay, whose uniaxial curve is the piecewise-linear one of the sublayers built from the
 * deviatoric curve. */
static const char *const table_5_2_deviatoric = "    plasticity:\n"
                                                "      strains: [0.002, 0.0065, 0.0124, 0.0168]\n"
                                                "      power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}\n"
                                                "      yield_rule: deviatoric\n";

/* sigma_yy at node c at the axial strain eps and lateral strain l (sigma_xx in *sxx). */
static double lateral_stress(peri_sim *s, int32_t c, double eps, double l, double *sig, double *sxx) {
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    for (int d = 0; d < 3; ++d) s->disc.p.u[3 * i + d] = (d == 0 ? eps : l) * s->disc.p.x[3 * i + d];
  cr_assert_eq(peri_stress(s, sig), 0);
  *sxx = sig[9 * c];
  return sig[9 * c + 4];
}

/* sigma_xx at node c under uniaxial stress at the axial strain eps (the lateral strain in and
 * out in *lateral), the increment accepted. */
static double uniaxial_at(peri_sim *s, int32_t c, double eps, double *lateral, double *sig) {
  double sxx = 0.0, la = *lateral, fa = lateral_stress(s, c, eps, la, sig, &sxx);
  double lb = la - 1e-5, fb = lateral_stress(s, c, eps, lb, sig, &sxx);
  for (int it = 0; it < 40 && fabs(fb) > 1e-9 * fabs(sxx) + 1.0; ++it) {
    const double next = lb - fb * (lb - la) / (fb - fa);
    la = lb, fa = fb, lb = next;
    fb = lateral_stress(s, c, eps, lb, sig, &sxx);
  }
  cr_assert(fabs(fb) <= 1e-9 * fabs(sxx) + 1.0, "uniaxial stress not reached at eps %g (sigma_yy %g)", eps, fb);
  *lateral = lb;
  peri_plastic_commit(s);
  return sxx;
}

/* Walks the axial strain from a to b in increments of at most h under uniaxial stress. */
static double uniaxial_walk(peri_sim *s, int32_t c, double a, double b, double h, double *lateral, double *sig) {
  const int n = (int)ceil(fabs(b - a) / h);
  double out = 0.0;
  for (int k = 1; k <= n; ++k) out = uniaxial_at(s, c, a + (b - a) * k / n, lateral, sig);
  return out;
}

/* The LPS block of 15^3 nodes (m = 3, nu = 1/4): the centre node and its neighbours have whole
 * families. */
static void build_block(peri_sim *s, const char *plasticity) {
  char deck[2048];
  snprintf(deck, sizeof deck,
           "dimension: 3\n"
           "materials:\n"
           "  steel:\n"
           "    model: lps\n"
           "    density: 7800\n"
           "    youngs_modulus: 200e9\n"
           "    poisson_ratio: 0.25\n"
           "%s"
           "discretization: {spacing: 1e-3, m: 3, fill: [{shape: box, min: [0, 0, 0], max: [0.014, 0.014, 0.014]}]}\n"
           "solver: {type: explicit, steps: 1, breaking: false}\n"
           "output: {picture: false}\n",
           plasticity);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  if (s->state.plastic_stretch) /* increments map from the accepted state (uniaxial_at) */
    s->state.plastic_committed = calloc((size_t)s->state.plastic_layers * (size_t)s->disc.bonds.n_bonds, sizeof(double));
  if (s->state.plastic_tensor) s->state.plastic_tensor->quasi_static = true;
}

/* Under a proportional path (the deviatoric strain stays on one axis) the radial return of
 * an increment is exact whatever its size, so the walk goes from point to point. */
#define DEVIATORIC_STEP 0.01

static void check_bar_3d_deviatoric(const char *plasticity, const char *label) {
  peri_sim s;
  build_block(&s, plasticity);
  const int32_t c = centre_node(&s);
  double *sig = malloc(sizeof(double) * 9 * (size_t)s.disc.p.n);
  const double h = DEVIATORIC_STEP, e_small = 0.5 * EPS0;
  double lateral = 0.0;
  const double E_pd = uniaxial_walk(&s, c, 0.0, e_small, h, &lateral, sig) / e_small;
  cr_log_info("3D %s: E_pd %.5g (E %.5g), nu_pd %.4f", label, E_pd, E_STEEL, -lateral / e_small);
  cr_expect(fabs(E_pd / E_STEEL - 1.0) < 0.03, "3D %s: elastic modulus %g, expected %g within 3%%", label, E_pd, E_STEEL);
  /* elastic up to the first breakpoint */
  const double below = 0.95 * EPS0, sigma_below = uniaxial_walk(&s, c, e_small, below, h, &lateral, sig);
  cr_expect(fabs(sigma_below / (E_pd * below) - 1.0) < 0.005, "3D %s: not elastic up to 0.95 eps_1 (%g, %g)", label,
            sigma_below, E_pd * below);
  double eps = below, mono[4];
  for (int k = 0; k < 4; ++k) {
    const double sigma = uniaxial_walk(&s, c, eps, breakpoints[k], h, &lateral, sig);
    eps = breakpoints[k];
    mono[k] = sigma;
    const double curve = SIGMA0 * pow(eps / EPS0, 0.1), expected = curve * E_pd / E_STEEL;
    cr_log_info("3D %s: eps %.4f sigma %.5g, curve %.5g (%+.2f%%), curve x E_pd/E %.5g (%+.2f%%)", label, eps, sigma,
                curve, 100 * (sigma / curve - 1), expected, 100 * (sigma / expected - 1));
    cr_expect(fabs(sigma / expected - 1.0) < 0.02, "3D %s: at breakpoint %.4f sigma %g, expected %g within 2%%", label,
              eps, sigma, expected);
  }
  /* beyond the last breakpoint flat; unloading elastic with the slope of the elastic block
   * over the same strains (the stretch is geometrically nonlinear: at eps_a the tangent
   * differs from E_pd by O(eps_a)) */
  const double eps_a = 0.02, sigma_a = uniaxial_walk(&s, c, eps, eps_a, h, &lateral, sig), d_el = 0.5 * EPS0;
  const double lateral_a = lateral;
  const double slope = (sigma_a - uniaxial_walk(&s, c, eps_a, eps_a - d_el, h, &lateral, sig)) / d_el;
  peri_sim elastic;
  build_block(&elastic, "");
  double lat_el = -0.25 * eps_a;
  const double s_hi = uniaxial_at(&elastic, c, eps_a, &lat_el, sig), s_lo = uniaxial_at(&elastic, c, eps_a - d_el, &lat_el, sig);
  const double slope_el = (s_hi - s_lo) / d_el;
  peri_sim_free(&elastic);
  cr_log_info("3D %s: sigma at %.3f %.5g (flat %.5g, %+.2f%%), lateral strain %.5f; unloading slope %.5g (elastic block "
              "%.5g, %+.2f%%; E_pd %.5g)", label, eps_a, sigma_a, mono[3], 100 * (sigma_a / mono[3] - 1), lateral_a,
              slope, slope_el, 100 * (slope / slope_el - 1), E_pd);
  cr_expect(fabs(sigma_a / mono[3] - 1.0) < 0.02, "3D %s: beyond the last breakpoint sigma %g, flat %g", label, sigma_a,
            mono[3]);
  cr_expect(fabs(slope / slope_el - 1.0) < 0.02, "3D %s: unloading slope %g, elastic %g within 2%%", label, slope,
            slope_el);
  /* reversed loading, Masing: elastic until the drop 2 sigma_1, then a drop of 2 sigma_k at
   * eps_a - 2 eps_k (the deviatoric strain and the stress both change by twice the
   * monotonic curve's: 2 e_k + 2 sigma_k / (9K) = 2 eps_k) */
  eps = eps_a - d_el;
  const double before = eps_a - 0.95 * 2.0 * EPS0;
  const double drop_before = sigma_a - uniaxial_walk(&s, c, eps, before, h, &lateral, sig);
  cr_log_info("3D %s: reverse drop at %.4f: %.5g, elastic %.5g (%+.2f%%)", label, before, drop_before,
              slope_el * (eps_a - before), 100 * (drop_before / (slope_el * (eps_a - before)) - 1));
  cr_expect(fabs(drop_before / (slope_el * (eps_a - before)) - 1.0) < 0.02, "3D %s: not elastic up to the reverse "
            "yield", label);
  eps = before;
  for (int k = 0; k < 4; ++k) {
    const double target = eps_a - 2.0 * breakpoints[k];
    const double drop = sigma_a - uniaxial_walk(&s, c, eps, target, h, &lateral, sig);
    eps = target;
    const double expected = 2.0 * SIGMA0 * pow(breakpoints[k] / EPS0, 0.1) * E_pd / E_STEEL;
    cr_log_info("3D %s: reverse eps %.4f drop %.5g, Masing %.5g (%+.2f%%)", label, eps, drop, expected,
                100 * (drop / expected - 1));
    cr_expect(fabs(drop / expected - 1.0) < 0.02, "3D %s: reverse branch at %.4f: drop %g, Masing %g within 2%%", label,
              eps, drop, expected);
  }
  free(sig);
  peri_sim_free(&s);
}

/* The return mapping of one node's family (docs/plasticity.md section 8) under pure shear
 * u = (g y / 2, g x / 2, 0), theta = 0: one sublayer (the curve flat from (sigma_y / E,
 * sigma_y), sigma_y = 400 MPa) yields when the shear stress reaches the von Mises k =
 * sigma_y / sqrt(3) = 230.9 MPa and stays there; every bond of the centre's family yields at
 * once (yield index 1 from the first yield on, 0 before). */
static void check_shear_deviatoric(const char *rule) {
  peri_sim s;
  char plasticity[256];
  snprintf(plasticity, sizeof plasticity, "    plasticity: {strains: [0.002], stresses: [400e6], yield_rule: %s}\n", rule);
  build_block(&s, plasticity);
  const int32_t c = centre_node(&s);
  double *sig = malloc(sizeof(double) * 9 * (size_t)s.disc.p.n), *psi = malloc(sizeof(double) * (size_t)s.disc.p.n);
  const double k_vm = SIGMA0 / sqrt(3.0), mu = E_STEEL / 2.5, g_y = k_vm / mu; /* the continuum yield shear strain */
  static const double fractions[5] = {0.5, 0.97, 1.03, 1.5, 3.0};
  double G_pd = 0.0;
  for (int q = 0; q < 5; ++q) {
    const double g = fractions[q] * g_y;
    for (int32_t i = 0; i < s.disc.p.n; ++i) {
      s.disc.p.u[3 * i] = 0.5 * g * s.disc.p.x[3 * i + 1];
      s.disc.p.u[3 * i + 1] = 0.5 * g * s.disc.p.x[3 * i];
      s.disc.p.u[3 * i + 2] = 0.0;
    }
    cr_assert_eq(peri_stress(&s, sig), 0);
    peri_plastic_commit(&s);
    peri_yield_index(&s, psi);
    const double tau = sig[9 * c + 1];
    if (q == 0) G_pd = tau / g;
    const bool yielded = fractions[q] > 1.0;
    cr_log_info("shear: g / g_y %.2f tau %.5g (elastic G_pd g %.5g, k %.5g), yield index %.3f", fractions[q], tau,
                G_pd * g, k_vm, psi[c]);
    if (yielded)
      cr_expect(fabs(tau / k_vm - 1.0) < 0.02, "shear at %.2f g_y: tau %g, von Mises k %g within 2%%", fractions[q], tau,
                k_vm);
    else
      cr_expect(fabs(tau / (G_pd * g) - 1.0) < 0.005, "shear at %.2f g_y: not elastic", fractions[q]);
    cr_expect_eq(psi[c], yielded ? 1.0 : 0.0, "shear at %.2f g_y: yield index %g", fractions[q], psi[c]);
  }
  cr_log_info("shear: G_pd %.5g (mu %.5g)", G_pd, mu);
  free(sig), free(psi);
  peri_sim_free(&s);
}

Test(plasticity, bar_3d_lps_deviatoric) { check_bar_3d_deviatoric(table_5_2_deviatoric, "LPS deviatoric"); }
Test(plasticity, shear_3d_lps_deviatoric) { check_shear_deviatoric("deviatoric"); }
/* The tensor rule (docs/plasticity.md section 10): under these homogeneous deformations every
 * family's deviatoric stretches are affine, so it must meet the same curve, Masing rule and von
 * Mises shear yield as the per-bond rule. */
static const char *const table_5_2_tensor = "    plasticity:\n"
                                            "      strains: [0.002, 0.0065, 0.0124, 0.0168]\n"
                                            "      power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}\n"
                                            "      yield_rule: deviatoric_tensor\n";
Test(plasticity, bar_3d_lps_tensor) { check_bar_3d_deviatoric(table_5_2_tensor, "LPS tensor"); }

/* The thermal strain enters the tensor rule's deviatoric stretches (s^d = e/|xi| - eth -
 * theta/3): the block expanding freely by a thermal strain 5 times the first yield strain has
 * no deviatoric stretch, so no node yields and the force vanishes to round-off; the same
 * expansion without the thermal strain (a hydrostatic stretch, theta = 3 eth) yields nowhere
 * either, while a shear of the same size yields every node with a whole family. */
Test(plasticity, tensor_thermal_expansion) {
  peri_sim s;
  build_block(&s, table_5_2_tensor);
  const int32_t n = s.disc.p.n;
  const double eth = 5.0 * EPS0;
  double *psi = malloc(sizeof(double) * (size_t)n);
  s.state.thermal_strain = calloc((size_t)n, sizeof(double));
  for (int32_t i = 0; i < n; ++i) {
    s.state.thermal_strain[i] = eth;
    for (int d = 0; d < 3; ++d) s.disc.p.u[3 * i + d] = eth * s.disc.p.x[3 * i + d];
  }
  s.mat.model->force(&s);
  double largest = 0.0;
  for (int32_t i = 0; i < 3 * n; ++i) largest = fmax(largest, fabs(s.disc.p.f[i]));
  peri_yield_index(&s, psi);
  double yielded = 0.0;
  for (int32_t i = 0; i < n; ++i) yielded += psi[i];
  /* the force density of a node at the elastic strain eth: about E eth / spacing */
  const double scale = E_STEEL * eth / 1e-3;
  cr_log_info("tensor rule, free thermal expansion %g: largest force density %g (scale %g), yielded %g", eth, largest,
              scale, yielded);
  cr_expect(largest < 1e-9 * scale, "free thermal expansion: force density %g", largest);
  cr_expect_eq(yielded, 0.0, "free thermal expansion: %g nodes yielded", yielded);
  free(s.state.thermal_strain);
  s.state.thermal_strain = NULL;
  s.mat.model->force(&s); /* the same expansion as a mechanical hydrostatic stretch */
  peri_yield_index(&s, psi);
  yielded = 0.0;
  for (int32_t i = 0; i < n; ++i) yielded += psi[i];
  cr_expect_eq(yielded, 0.0, "hydrostatic stretch: %g nodes yielded", yielded);
  for (int32_t i = 0; i < n; ++i) {
    s.disc.p.u[3 * i] = eth * s.disc.p.x[3 * i + 1];
    s.disc.p.u[3 * i + 1] = s.disc.p.u[3 * i + 2] = 0.0;
  }
  s.mat.model->force(&s);
  peri_yield_index(&s, psi);
  const int32_t c = centre_node(&s);
  cr_expect_eq(psi[c], 1.0, "a shear of 5 yield strains: the centre did not yield");
  free(psi);
  peri_sim_free(&s);
}
Test(plasticity, shear_3d_lps_tensor) { check_shear_deviatoric("deviatoric_tensor"); }
Test(plasticity, bar_1d_pmb) { check_bar_1d(); }
Test(plasticity, bar_1d_rate) { check_bar_1d_rate(); }
Test(plasticity, bar_3d_pmb) { check_bar_3d("pmb"); }
Test(plasticity, bar_3d_lps) { check_bar_3d("lps"); }
Test(plasticity, bar_3d_pmb_family) { check_bar_3d_family("pmb"); }
