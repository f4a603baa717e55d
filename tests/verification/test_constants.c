/* Published constants (docs/verification.md "Constants"; docs/model_reference.md 2.2, 2.3, 3.3, 4).
 * Each constant is checked twice: against its closed form (1e-12 relative: the two
 * evaluations differ only by rounding, a few ulps), and where possible against the rule it
 * comes from, evaluated here by numerical integration. The quadratures are Gauss-Legendre
 * on polynomial or entire integrands, so they are exact up to rounding and the same 1e-12
 * applies. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/material.h"

#define RTOL 1e-12

static void expect_rel(double got, double want, double tol, const char *what) {
  cr_expect(fabs(got - want) <= tol * fabs(want), "%s: got %.17g, expected %.17g (rel %.3g)", what,
            got, want, fabs(got - want) / fabs(want));
}

/* Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n; n <= 64). */
static void gauss_legendre(int n, double *t, double *w) {
  for (int i = 0; i < n; ++i) {
    double x = cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      double dx = p1 / dp;
      x -= dx;
      if (fabs(dx) < 1e-16) break;
    }
    t[i] = x;
    w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
}

#define NGL 24
static double gl_t[NGL], gl_w[NGL];

static void setup_gl(void) { gauss_legendre(NGL, gl_t, gl_w); }

/* int_a^b f(x) dx with NGL-point Gauss-Legendre (exact for degree < 2 NGL). */
static double integrate(double (*f)(double, const void *), const void *ctx, double a, double b) {
  double sum = 0.0, half = 0.5 * (b - a), mid = 0.5 * (a + b);
  for (int k = 0; k < NGL; ++k) sum += gl_w[k] * f(mid + half * gl_t[k], ctx);
  return sum * half;
}

typedef struct {
  int dim;
  double c, delta, h, A, s0;
} bond_ctx;

/* Integrand of int_H c |xi| dV in radial form: dV = 4 pi r^2 dr, 2 pi h r dr, 2 A dr. */
static double isotropic_integrand(double r, const void *p) {
  const bond_ctx *b = p;
  double measure = b->dim == 3 ? 4.0 * M_PI * r * r : b->dim == 2 ? 2.0 * M_PI * b->h * r : 2.0 * b->A;
  return b->c * r * measure;
}

/* Energy per unit crack area of the bonds of length r crossing the crack plane, counted
 * directly: a node at depth z (0 <= z <= r) below the plane reaches the points at distance
 * r above it on a spherical cap 2 pi r^2 (1 - z/r) (3D), on an arc 2 r arccos(z/r) times h
 * (2D), or one point (1D). The depth integral is done numerically too (z = r cos(phi) in
 * 2D, so the integrand is smooth). w0 = c s0^2 r / 2 (docs/model_reference.md 2.2). */
typedef struct {
  const bond_ctx *b;
  double r;
} crossing_ctx;

static double depth_integrand(double phi, const void *p) {
  const crossing_ctx *c = p;
  double r = c->r, z = r * cos(phi), dz = r * sin(phi); /* dz/dphi in magnitude */
  switch (c->b->dim) {
  case 3: return 2.0 * M_PI * r * r * (1.0 - z / r) * dz;
  case 2: return c->b->h * 2.0 * r * acos(z / r) * dz;
  default: return c->b->A * dz;
  }
}

static double crossing_integrand(double r, const void *p) {
  const bond_ctx *b = p;
  crossing_ctx c = {b, r};
  double w0 = b->c * b->s0 * b->s0 * r / 2.0;
  return w0 * integrate(depth_integrand, &c, 0.0, M_PI / 2.0);
}

static peri_geometry geom(int dim, peri_plane plane) {
  peri_geometry g = {.dim = dim, .plane = plane, .horizon = 3.0e-3, .spacing = 1.0e-3,
                     .thickness = 2.5e-3, .cross_section = 4.0e-6};
  return g;
}

/* E = 72 GPa with each case's own Poisson ratio; K = E / (3 (1 - 2 nu)). */
static const double E0 = 72.0e9, G0 = 3.8;

TestSuite(constants, .init = setup_gl);

Test(constants, pmb_micromodulus_closed_form) {
  const double d = 3.0e-3;
  peri_geometry g3 = geom(3, PERI_PLANE_NONE), gs = geom(2, PERI_PLANE_STRESS),
                ge = geom(2, PERI_PLANE_STRAIN), g1 = geom(1, PERI_PLANE_NONE);
  double K = E0 / (3.0 * (1.0 - 2.0 * 0.25));
  expect_rel(peri_pmb_micromodulus(&g3, E0, K), 18.0 * K / (M_PI * pow(d, 4)), RTOL, "3D 18K/(pi d^4)");
  /* docs/model_reference.md 2.3: the same at nu = 1/4 written with E */
  expect_rel(peri_pmb_micromodulus(&g3, E0, K), 12.0 * E0 / (M_PI * pow(d, 4)), RTOL, "3D 12E/(pi d^4)");
  expect_rel(peri_pmb_micromodulus(&gs, E0, NAN), 9.0 * E0 / (M_PI * gs.thickness * pow(d, 3)), RTOL,
             "plane stress 9E/(pi h d^3)");
  expect_rel(peri_pmb_micromodulus(&ge, E0, NAN), 48.0 * E0 / (5.0 * M_PI * ge.thickness * pow(d, 3)),
             RTOL, "plane strain 48E/(5 pi h d^3)");
  expect_rel(peri_pmb_micromodulus(&g1, E0, NAN), 2.0 * E0 / (g1.cross_section * d * d), RTOL,
             "1D 2E/(A d^2)");
}

Test(constants, critical_stretch_closed_form) {
  const double d = 3.0e-3;
  peri_geometry g3 = geom(3, PERI_PLANE_NONE), gs = geom(2, PERI_PLANE_STRESS),
                ge = geom(2, PERI_PLANE_STRAIN), g1 = geom(1, PERI_PLANE_NONE);
  double K = E0 / (3.0 * (1.0 - 2.0 * 0.25));
  expect_rel(peri_critical_stretch_pmb(&g3, G0, E0, K), sqrt(5.0 * G0 / (9.0 * K * d)), RTOL,
             "3D sqrt(5G0/(9K d))");
  expect_rel(peri_critical_stretch_pmb(&gs, G0, E0, NAN), sqrt(4.0 * M_PI * G0 / (9.0 * E0 * d)), RTOL,
             "plane stress sqrt(4 pi G0/(9E d))");
  expect_rel(peri_critical_stretch_pmb(&ge, G0, E0, NAN), sqrt(5.0 * M_PI * G0 / (12.0 * E0 * d)),
             RTOL, "plane strain sqrt(5 pi G0/(12E d))");
  expect_rel(peri_critical_stretch_pmb(&g1, G0, E0, NAN), sqrt(3.0 * G0 / (E0 * d)), RTOL,
             "1D sqrt(3G0/(E d))");
  /* State-based default (docs/model_reference.md 7.2): 3D sqrt(5G0/(6E d)), the PMB value at nu = 1/4. */
  expect_rel(peri_critical_stretch_lps(&g3, G0, E0), sqrt(5.0 * G0 / (6.0 * E0 * d)), RTOL, "LPS 3D");
  expect_rel(peri_critical_stretch_lps(&g3, G0, E0), peri_critical_stretch_pmb(&g3, G0, E0, K), RTOL,
             "LPS 3D = PMB 3D at nu = 1/4");
  expect_rel(peri_critical_stretch_lps(&gs, G0, E0), peri_critical_stretch_pmb(&gs, G0, E0, NAN), RTOL,
             "LPS plane stress");
}

/* docs/model_reference.md 2.2: 1/4 s^2 int_H c |xi| dV equals the classical energy of the isotropic
 * stretch s: 9K s^2/2 (3D), 2 K2D s^2 (2D), E s^2/2 (1D). K2D = E/(2(1-nu)) in plane
 * stress (nu = 1/3), E/(2(1+nu)(1-2nu)) in plane strain (nu = 1/4). */
Test(constants, pmb_micromodulus_matches_isotropic_energy) {
  const double s = 1e-3;
  struct {
    int dim;
    peri_plane plane;
    double nu;
  } cases[] = {{3, PERI_PLANE_NONE, 0.25}, {2, PERI_PLANE_STRESS, 1.0 / 3.0},
               {2, PERI_PLANE_STRAIN, 0.25}, {1, PERI_PLANE_NONE, 0.25}};
  for (int k = 0; k < 4; ++k) {
    peri_geometry g = geom(cases[k].dim, cases[k].plane);
    double nu = cases[k].nu, K = E0 / (3.0 * (1.0 - 2.0 * nu));
    bond_ctx b = {g.dim, peri_pmb_micromodulus(&g, E0, K), g.horizon, g.thickness, g.cross_section, 0};
    double W = 0.25 * s * s * integrate(isotropic_integrand, &b, 0.0, g.horizon);
    double classical;
    if (g.dim == 3) classical = 4.5 * K * s * s;
    else if (g.dim == 1) classical = 0.5 * E0 * s * s;
    else if (g.plane == PERI_PLANE_STRESS) classical = 2.0 * E0 / (2.0 * (1.0 - nu)) * s * s;
    else classical = 2.0 * E0 / (2.0 * (1.0 + nu) * (1.0 - 2.0 * nu)) * s * s;
    char what[64];
    snprintf(what, sizeof what, "isotropic energy, case %d (dim %d)", k, g.dim);
    expect_rel(W, classical, RTOL, what);
  }
}

/* docs/model_reference.md 2.2: with s0 from G0, breaking every bond across a unit crack area costs G0.
 * The crossing energy is counted directly (double integral over depth and bond length),
 * not through the reduced formulas pi int xi^3 w0 etc. */
Test(constants, critical_stretch_matches_fracture_energy) {
  peri_plane planes[] = {PERI_PLANE_NONE, PERI_PLANE_STRESS, PERI_PLANE_STRAIN, PERI_PLANE_NONE};
  int dims[] = {3, 2, 2, 1};
  for (int k = 0; k < 4; ++k) {
    peri_geometry g = geom(dims[k], planes[k]);
    double nu = peri_pmb_poisson(&g), K = E0 / (3.0 * (1.0 - 2.0 * nu));
    bond_ctx b = {g.dim, peri_pmb_micromodulus(&g, E0, K), g.horizon, g.thickness, g.cross_section,
                  peri_critical_stretch_pmb(&g, G0, E0, K)};
    /* Per unit crack area: in 2D (1D) both ends carry the factor h (A) and the crack area
     * per unit length is h (A), so one factor remains, as in depth_integrand. */
    double G = integrate(crossing_integrand, &b, 0.0, g.horizon);
    char what[64];
    snprintf(what, sizeof what, "fracture energy, case %d (dim %d)", k, g.dim);
    expect_rel(G, G0, RTOL, what);
  }
}

/* Angular mean of f(n . eps n) over the unit circle (trapezoid, exact for the degree-4
 * trigonometric polynomials here) or sphere (Gauss-Legendre in cos(theta) x trapezoid). */
static double angular_mean(int dim, const double eps[3][3], int power, double shift) {
  double sum = 0.0, wsum = 0.0;
  const int nphi = 32;
  int nt = dim == 3 ? NGL : 1;
  for (int a = 0; a < nt; ++a) {
    double ct = dim == 3 ? gl_t[a] : 0.0, st = sqrt(1.0 - ct * ct), wt = dim == 3 ? gl_w[a] : 1.0;
    for (int b = 0; b < nphi; ++b) {
      double phi = 2.0 * M_PI * b / nphi;
      double n[3] = {st * cos(phi), st * sin(phi), ct};
      double q = 0.0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) q += n[i] * eps[i][j] * n[j];
      sum += wt * pow(q - shift, power);
      wsum += wt;
    }
  }
  return sum / wsum;
}

/* Classical W = lambda'/2 (tr eps)^2 + mu eps:eps, lambda' = lambda (3D, plane strain) or
 * E nu/(1 - nu^2) (plane stress). */
static double classical_energy(const peri_geometry *g, double E, double nu, const double eps[3][3]) {
  double mu = E / (2.0 * (1.0 + nu)), lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  if (g->dim == 2 && g->plane == PERI_PLANE_STRESS) lambda = E * nu / (1.0 - nu * nu);
  if (g->dim == 1) return 0.5 * E * eps[0][0] * eps[0][0];
  double tr = 0.0, ee = 0.0;
  for (int i = 0; i < g->dim; ++i) {
    tr += eps[i][i];
    for (int j = 0; j < g->dim; ++j) ee += eps[i][j] * eps[i][j];
  }
  return 0.5 * lambda * tr * tr + mu * ee;
}

static void strain_of_dim(int dim, double eps[3][3]) {
  const double e[3][3] = {{1.0e-3, 0.3e-3, -0.2e-3}, {0.3e-3, -0.5e-3, 0.4e-3}, {-0.2e-3, 0.4e-3, 0.7e-3}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) eps[i][j] = (i < dim && j < dim) ? e[i][j] : 0.0;
}

/* PMB under any homogeneous strain stores the classical energy of the model's fixed
 * Poisson ratio (1/4 in 3D and plane strain, 1/3 in plane stress): W = 1/4 int c |xi|
 * (n.eps n)^2 dV = (c/4) (radial moment) |S| <(n.eps n)^2>. This checks the constants and
 * peri_pmb_poisson together. */
Test(constants, pmb_energy_any_strain_fixed_poisson) {
  peri_plane planes[] = {PERI_PLANE_NONE, PERI_PLANE_STRESS, PERI_PLANE_STRAIN};
  int dims[] = {3, 2, 2};
  for (int k = 0; k < 3; ++k) {
    peri_geometry g = geom(dims[k], planes[k]);
    double nu = peri_pmb_poisson(&g), K = E0 / (3.0 * (1.0 - 2.0 * nu));
    double c = peri_pmb_micromodulus(&g, E0, K), d = g.horizon;
    double eps[3][3];
    strain_of_dim(g.dim, eps);
    double radial = g.dim == 3 ? 4.0 * M_PI * pow(d, 4) / 4.0 : 2.0 * M_PI * g.thickness * pow(d, 3) / 3.0;
    double W = 0.25 * c * radial * angular_mean(g.dim, eps, 2, 0.0);
    char what[64];
    snprintf(what, sizeof what, "PMB energy, dim %d plane %d", g.dim, (int)g.plane);
    expect_rel(W, classical_energy(&g, E0, nu, eps), RTOL, what);
  }
}

Test(constants, pmb_poisson_fixed_values) {
  peri_geometry g3 = geom(3, PERI_PLANE_NONE), gs = geom(2, PERI_PLANE_STRESS),
                ge = geom(2, PERI_PLANE_STRAIN), g1 = geom(1, PERI_PLANE_NONE);
  cr_expect_eq(peri_pmb_poisson(&g3), 0.25);
  cr_expect_eq(peri_pmb_poisson(&ge), 0.25);
  cr_expect_eq(peri_pmb_poisson(&g1), 0.25);
  expect_rel(peri_pmb_poisson(&gs), 1.0 / 3.0, 1e-15, "plane stress nu");
}

/* docs/model_reference.md 3.3 table. */
Test(constants, lps_constants_closed_form) {
  const double nu = 0.3, E = 70.0e9, K = E / (3.0 * (1.0 - 2.0 * nu)), mu = E / (2.0 * (1.0 + nu));
  double n, Kt, am;
  peri_geometry g3 = geom(3, PERI_PLANE_NONE), gs = geom(2, PERI_PLANE_STRESS),
                ge = geom(2, PERI_PLANE_STRAIN);
  peri_lps_constants(&g3, K, mu, &n, &Kt, &am);
  expect_rel(n, 3.0, RTOL, "3D n_theta");
  expect_rel(Kt, K, RTOL, "3D K_theta");
  expect_rel(am, 15.0 * mu, RTOL, "3D alpha m");
  peri_lps_constants(&gs, K, mu, &n, &Kt, &am);
  double r = (1.0 + nu) / (1.0 - 2.0 * nu);
  expect_rel(n, 2.0 * (2.0 * nu - 1.0) / (nu - 1.0), RTOL, "plane stress n_theta");
  expect_rel(Kt, K + mu / 9.0 * r * r, RTOL, "plane stress K_theta");
  expect_rel(am, 8.0 * mu, RTOL, "plane stress alpha m");
  peri_lps_constants(&ge, K, mu, &n, &Kt, &am);
  expect_rel(n, 2.0, RTOL, "plane strain n_theta");
  expect_rel(Kt, K + mu / 9.0, RTOL, "plane strain K_theta");
  expect_rel(am, 8.0 * mu, RTOL, "plane strain alpha m");
}

/* Independent check of the LPS constants: under a homogeneous strain (e = |xi| n.eps n)
 * the continuum LPS energy W = K_theta theta^2/2 + (alpha m/(2m)) int w (e^d)^2 dV, with
 * theta = (n_theta/m) int w |xi| e dV, becomes W = K_theta theta^2/2 + (alpha m/2)
 * <(n.eps n - theta/3)^2>, theta = n_theta <n.eps n>, for any influence function. It must
 * equal the classical energy for every nu (Le 2014 ch. 2). The angular means are numerical. */
Test(constants, lps_constants_match_classical_energy) {
  peri_plane planes[] = {PERI_PLANE_NONE, PERI_PLANE_STRESS, PERI_PLANE_STRAIN};
  int dims[] = {3, 2, 2};
  const double nus[] = {0.1, 0.25, 1.0 / 3.0, 0.45, -0.2};
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 5; ++a) {
      peri_geometry g = geom(dims[k], planes[k]);
      double nu = nus[a], K = E0 / (3.0 * (1.0 - 2.0 * nu)), mu = E0 / (2.0 * (1.0 + nu));
      double n, Kt, am, eps[3][3];
      peri_lps_constants(&g, K, mu, &n, &Kt, &am);
      strain_of_dim(g.dim, eps);
      double theta = n * angular_mean(g.dim, eps, 1, 0.0);
      double W = 0.5 * Kt * theta * theta + 0.5 * am * angular_mean(g.dim, eps, 2, theta / 3.0);
      char what[80];
      snprintf(what, sizeof what, "LPS energy, dim %d plane %d nu %g", g.dim, (int)g.plane, nu);
      expect_rel(W, classical_energy(&g, E0, nu, eps), RTOL, what);
    }
  /* 1D: no dilatation, (alpha m/2) eps^2 = E eps^2/2. */
  peri_geometry g1 = geom(1, PERI_PLANE_NONE);
  double n, Kt, am, K = E0 / (3.0 * (1.0 - 0.6)), mu = E0 / (2.0 * 1.3);
  peri_lps_constants(&g1, K, mu, &n, &Kt, &am);
  expect_rel(am, E0, RTOL, "1D alpha m = E");
}

/* docs/model_reference.md 3.4: the dilatation bracket n K_theta - 2/3 (alpha m) + (n/9)(alpha m) is
 * 3K - 5 mu in 3D and vanishes at nu = 1/4 (3D, plane strain) and 1/3 (plane stress). */
Test(constants, lps_bracket_vanishes_at_pmb_poisson) {
  peri_plane planes[] = {PERI_PLANE_NONE, PERI_PLANE_STRESS, PERI_PLANE_STRAIN};
  int dims[] = {3, 2, 2};
  for (int k = 0; k < 3; ++k) {
    peri_geometry g = geom(dims[k], planes[k]);
    double nu = peri_pmb_poisson(&g), K = E0 / (3.0 * (1.0 - 2.0 * nu)), mu = E0 / (2.0 * (1.0 + nu));
    double n, Kt, am;
    peri_lps_constants(&g, K, mu, &n, &Kt, &am);
    double bracket = n * Kt - 2.0 / 3.0 * am + n / 9.0 * am;
    cr_expect(fabs(bracket) <= RTOL * am, "dim %d plane %d: bracket %g (alpha m %g)", g.dim, (int)g.plane,
              bracket, am);
    /* ... and at the PMB ratio 2 (alpha m)/m_analytic(w = 1/r) is the PMB micromodulus. */
    double m = g.dim == 3 ? M_PI * pow(g.horizon, 4) : 2.0 * M_PI * g.thickness * pow(g.horizon, 3) / 3.0;
    expect_rel(2.0 * am / m, peri_pmb_micromodulus(&g, E0, K), RTOL, "2 alpha m / m = c");
  }
  peri_geometry g3 = geom(3, PERI_PLANE_NONE);
  double K = 100e9, mu = 50e9, n, Kt, am;
  peri_lps_constants(&g3, K, mu, &n, &Kt, &am);
  expect_rel(n * Kt - 2.0 / 3.0 * am + n / 9.0 * am, 3.0 * K - 5.0 * mu, RTOL, "3D bracket = 3K - 5mu");
}

/* Gaussian influence moments: I_n = int_0^1 t^n exp(-t^2) dt, I_1 = (1 - 1/e)/2,
 * I_0 = sqrt(pi)/2 erf(1), I_n = ((n-1) I_{n-2} - 1/e)/2. */
static double gauss_moment(int n) {
  if (n == 0) return 0.5 * sqrt(M_PI) * erf(1.0);
  if (n == 1) return 0.5 * (1.0 - exp(-1.0));
  return 0.5 * ((n - 1) * gauss_moment(n - 2) - exp(-1.0));
}

/* docs/model_reference.md 4: m = int_H w |xi|^2 dV of a full horizon. */
Test(constants, weighted_volume_analytic) {
  const double tol = 1e-10;
  peri_geometry g3 = geom(3, PERI_PLANE_NONE), g2 = geom(2, PERI_PLANE_STRESS), g1 = geom(1, PERI_PLANE_NONE);
  const double d = g3.horizon, h = g2.thickness, A = g1.cross_section;
  expect_rel(peri_weighted_volume_analytic(&g3, PERI_INFLUENCE_CONSTANT), 4.0 * M_PI * pow(d, 5) / 5.0, tol,
             "3D constant 4 pi d^5/5");
  expect_rel(peri_weighted_volume_analytic(&g2, PERI_INFLUENCE_CONSTANT), M_PI * h * pow(d, 4) / 2.0, tol,
             "2D constant pi h d^4/2");
  expect_rel(peri_weighted_volume_analytic(&g3, PERI_INFLUENCE_INVERSE), M_PI * pow(d, 4), tol,
             "3D inverse pi d^4");
  expect_rel(peri_weighted_volume_analytic(&g2, PERI_INFLUENCE_INVERSE), 2.0 * M_PI * h * pow(d, 3) / 3.0, tol,
             "2D inverse 2 pi h d^3/3");
  /* Derived the same way (not tabulated): 1D 2A int w r^2 dr; Gaussian exp(-r^2/d^2). */
  expect_rel(peri_weighted_volume_analytic(&g1, PERI_INFLUENCE_CONSTANT), 2.0 * A * pow(d, 3) / 3.0, tol,
             "1D constant 2 A d^3/3");
  expect_rel(peri_weighted_volume_analytic(&g1, PERI_INFLUENCE_INVERSE), A * d * d, tol, "1D inverse A d^2");
  expect_rel(peri_weighted_volume_analytic(&g3, PERI_INFLUENCE_GAUSSIAN), 4.0 * M_PI * pow(d, 5) * gauss_moment(4),
             tol, "3D gaussian");
  expect_rel(peri_weighted_volume_analytic(&g2, PERI_INFLUENCE_GAUSSIAN),
             2.0 * M_PI * h * pow(d, 4) * gauss_moment(3), tol, "2D gaussian");
}

/* The influence calibration keeps int c w |xi| dV fixed: for w = 1/r it is
 * int r^dim / int r^(dim-1) = dim d/(dim+1). */
Test(constants, influence_calibration) {
  const double d = 3.0e-3;
  for (int dim = 1; dim <= 3; ++dim)
    expect_rel(peri_influence_calibration(PERI_INFLUENCE_CONSTANT, dim, d), 1.0, 1e-15, "constant");
  for (int dim = 2; dim <= 3; ++dim)
    expect_rel(peri_influence_calibration(PERI_INFLUENCE_INVERSE, dim, d), dim * d / (dim + 1.0), 1e-10,
               "inverse");
}

/* 1D with w = 1/r (the classical 1D micromodulus c/|xi|, docs/model_reference.md 2.1): calibration
 * int r dr / int (1/r) r dr = d/2. The integrand (1/r) r is 1 at r = 0. */
Test(constants, influence_calibration_1d_inverse) {
  const double d = 3.0e-3;
  expect_rel(peri_influence_calibration(PERI_INFLUENCE_INVERSE, 1, d), d / 2.0, 1e-10, "1D inverse");
  expect_rel(peri_influence_moment(PERI_INFLUENCE_INVERSE, 1, d), d, 1e-10, "int_0^d (1/r) r dr = d");
}

/* G0 = K_Ic^2 / E', E' = E (plane stress, 1D) or E/(1-nu^2) (plane strain, 3D). */
Test(constants, fracture_energy_from_toughness) {
  const double KIc = 0.75e6, nu = 0.22;
  peri_geometry g3 = geom(3, PERI_PLANE_NONE), gs = geom(2, PERI_PLANE_STRESS), ge = geom(2, PERI_PLANE_STRAIN);
  expect_rel(peri_fracture_energy_from_toughness(&gs, KIc, E0, nu), KIc * KIc / E0, RTOL, "plane stress");
  expect_rel(peri_fracture_energy_from_toughness(&ge, KIc, E0, nu), KIc * KIc * (1 - nu * nu) / E0, RTOL,
             "plane strain");
  expect_rel(peri_fracture_energy_from_toughness(&g3, KIc, E0, nu), KIc * KIc * (1 - nu * nu) / E0, RTOL, "3D");
}

/* Any two of E, nu, K, mu give back the other two. */
Test(constants, elastic_resolve_round_trips) {
  const double E = 200.0e9, nu = 0.3, K = E / (3.0 * (1.0 - 2.0 * nu)), mu = E / (2.0 * (1.0 + nu));
  const double in[6][4] = {{E, nu, NAN, NAN}, {E, NAN, K, NAN}, {E, NAN, NAN, mu},
                           {NAN, nu, K, NAN}, {NAN, nu, NAN, mu}, {NAN, NAN, K, mu}};
  for (int k = 0; k < 6; ++k) {
    double Eo, nuo, Ko, muo;
    char why[256];
    int rc = peri_elastic_resolve(in[k][0], in[k][1], in[k][2], in[k][3], NAN, &Eo, &nuo, &Ko, &muo, why,
                                  sizeof why);
    cr_assert_eq(rc, PERI_OK, "pair %d: %s", k, why);
    expect_rel(Eo, E, RTOL, "E");
    expect_rel(nuo, nu, RTOL, "nu");
    expect_rel(Ko, K, RTOL, "K");
    expect_rel(muo, mu, RTOL, "mu");
  }
  /* A bond-based model completes a single modulus with its own ratio: K = E/(3(1-2nu)). */
  double Eo, nuo, Ko, muo;
  char why[256];
  cr_assert_eq(peri_elastic_resolve(E, NAN, NAN, NAN, 0.25, &Eo, &nuo, &Ko, &muo, why, sizeof why), PERI_OK);
  expect_rel(Ko, E / 1.5, RTOL, "K from E at nu = 1/4");
  expect_rel(muo, E / 2.5, RTOL, "mu from E at nu = 1/4");
  cr_assert_eq(peri_elastic_resolve(NAN, NAN, K, NAN, 1.0 / 3.0, &Eo, &nuo, &Ko, &muo, why, sizeof why), PERI_OK);
  expect_rel(Eo, K, RTOL, "E = 3K(1-2nu) = K at nu = 1/3");
  /* inadmissible or over/under-determined input is rejected */
  cr_expect_eq(peri_elastic_resolve(E, nu, K, NAN, NAN, &Eo, &nuo, &Ko, &muo, why, sizeof why), PERI_ERR_INPUT);
  cr_expect_eq(peri_elastic_resolve(E, NAN, NAN, NAN, NAN, &Eo, &nuo, &Ko, &muo, why, sizeof why), PERI_ERR_INPUT);
  cr_expect_eq(peri_elastic_resolve(E, 0.5, NAN, NAN, NAN, &Eo, &nuo, &Ko, &muo, why, sizeof why), PERI_ERR_INPUT);
  cr_expect_eq(peri_elastic_resolve(E, -1.0, NAN, NAN, NAN, &Eo, &nuo, &Ko, &muo, why, sizeof why), PERI_ERR_INPUT);
  cr_expect_eq(peri_elastic_resolve(-E, 0.3, NAN, NAN, NAN, &Eo, &nuo, &Ko, &muo, why, sizeof why), PERI_ERR_INPUT);
  /* E > 9K would need mu < 0 */
  cr_expect_eq(peri_elastic_resolve(10.0 * K, NAN, K, NAN, NAN, &Eo, &nuo, &Ko, &muo, why, sizeof why),
               PERI_ERR_INPUT);
}
