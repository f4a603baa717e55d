/* "LPS equals PMB" (docs/model_reference.md 3.4): substituting P = theta m/n - theta B/3 (B = sum w
 * |xi|^2 beta V over the intact family) into the LPS force state gives
 *   t_ij = [n K_theta - 2/3 (alpha m) + (n/9)(alpha m) B_i/m_i] theta_i w |xi|/m_i
 *          + (alpha m/m_i) w e.
 * With the discrete weighted volume (m_i = B_i) the bracket is 3K - 5 mu in 3D and
 * vanishes at nu = 1/4 (3D, plane strain) and 1/3 (plane stress); then the pair force is
 * 2 (alpha m)/m w e, which for w = 1/|xi| is a PMB force c s with c = 2 (alpha m)/m.
 * Checked here: (1) LPS equals a PMB run with that micromodulus on interior nodes to 1e-10;
 * (2) with the analytic m the difference is the (B/m - 1) term; (3) at nu = 0.2 the
 * dilatation term does not vanish; (4) the LPS force of every node, surface included,
 * equals the reduced form above evaluated independently in this file. */
#include "peri/setup.h"
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "support.h"

#define DX 1.0e-3
#define M_RATIO 3.0
#define DELTA (M_RATIO * DX)
#define THICK 1.0e-3

typedef struct {
  int dim;
  peri_plane plane;
  int n;          /* cells per side; interior (beyond 2 delta + dx = 7 dx) needs n > 14 */
  double E, nu;   /* the material */
  const char *moduli; /* how the deck gives them (exact nu = 1/3 through K = 8 mu/3) */
} lp_case;

static void build(peri_sim *s, const lp_case *c, const char *material, const char *disc_extra) {
  char box[320], deck[2048];
  double h = 0.5 * c->n * DX;
  if (c->dim == 2)
    snprintf(box, sizeof box, "{shape: rectangle, min: [%.17g, %.17g], max: [%.17g, %.17g]}", -h, -h, h, h);
  else
    snprintf(box, sizeof box, "{shape: box, min: [%.17g, %.17g, %.17g], max: [%.17g, %.17g, %.17g]}", -h, -h, -h, h,
             h, h);
  snprintf(deck, sizeof deck,
           "dimension: %d\n"
           "%s"
           "materials:\n"
           "  mat: %s\n"
           "discretization:\n"
           "  spacing: %.17g\n"
           "  m: %.17g\n"
           "%s"
           "%s"
           "  fill: [%s]\n"
           "solver: {type: explicit, steps: 1, breaking: false}\n"
           "output: {picture: false}\n",
           c->dim, c->dim != 2 ? "" : c->plane == PERI_PLANE_STRAIN ? "plane: strain\n" : "plane: stress\n", material,
           DX, M_RATIO, c->dim == 2 ? "  thickness: 1.0e-3\n" : "", disc_extra, box);
  cr_assert_eq(sim_from_string(s, deck), 0, "deck:\n%s", deck);
  s->solver.breaking = false;
}

static void build_lps(peri_sim *s, const lp_case *c, const char *weighted_volume) {
  char mat[256], extra[128];
  snprintf(mat, sizeof mat, "{model: lps, density: 2700, %s}", c->moduli);
  snprintf(extra, sizeof extra, "  influence: inverse\n  weighted_volume: %s\n", weighted_volume);
  build(s, c, mat, extra);
}

static void build_pmb(peri_sim *s, const lp_case *c, double micromodulus) {
  char mat[256];
  snprintf(mat, sizeof mat, "{model: pmb, density: 2700, micromodulus: %.17g}", micromodulus);
  build(s, c, mat, "");
}

/* Smooth, deterministic, non-affine displacement of size ~1e-4 |x|. */
static void set_field(peri_sim *s, int dim, double half) {
  for (int32_t i = 0; i < s->disc.p.n; ++i) {
    const double *x = &s->disc.p.x[3 * i];
    double a = x[0] / half, b = x[1] / half, c = x[2] / half, g[3];
    g[0] = 0.8 * a - 0.3 * b + 0.2 * c + 0.5 * sin(2.1 * a + 1.3 * b - 0.7 * c + 0.4) + 0.6 * a * b - 0.4 * c * c;
    g[1] = -0.2 * a + 0.5 * b + 0.3 * c + 0.4 * cos(1.7 * a - 0.9 * b + 1.1 * c) + 0.3 * a * a - 0.5 * b * c;
    g[2] = 0.1 * a - 0.4 * b + 0.7 * c + 0.3 * sin(1.2 * a + 2.3 * b + 0.8 * c - 0.5) + 0.45 * a * c;
    for (int d = 0; d < 3; ++d) s->disc.p.u[3 * i + d] = d < dim ? 1e-4 * half * g[d] : 0.0;
  }
}

/* Elastic constants and the LPS constants of docs/model_reference.md 3.3, from the theory. */
typedef struct {
  double K, mu, n_theta, K_theta, alpha_m;
} lps_theory;

static lps_theory theory(const lp_case *c) {
  lps_theory t;
  double nu = c->nu;
  t.K = c->E / (3.0 * (1.0 - 2.0 * nu));
  t.mu = c->E / (2.0 * (1.0 + nu));
  if (c->dim == 3) {
    t.n_theta = 3.0, t.K_theta = t.K, t.alpha_m = 15.0 * t.mu;
  } else if (c->plane == PERI_PLANE_STRAIN) {
    t.n_theta = 2.0, t.K_theta = t.K + t.mu / 9.0, t.alpha_m = 8.0 * t.mu;
  } else {
    double r = (1.0 + nu) / (1.0 - 2.0 * nu);
    t.n_theta = 2.0 * (1.0 - 2.0 * nu) / (1.0 - nu), t.K_theta = t.K + t.mu / 9.0 * r * r, t.alpha_m = 8.0 * t.mu;
  }
  return t;
}

/* beta of the linear partial-volume rule (docs/model_reference.md 5a). */
static double beta_linear(double r) {
  if (r <= DELTA - 0.5 * DX) return 1.0;
  return fmax(0.0, fmin(1.0, 0.5 + (DELTA - r) / DX));
}

/* Discrete weighted volume of a full family, w = 1/r: sum over lattice offsets k != 0 of
 * |k dx| beta(|k dx|) V, computed from the lattice, not from the code's bonds. */
static double lattice_weighted_volume(int dim) {
  double m = 0.0, V = dim == 3 ? DX * DX * DX : DX * DX * THICK;
  int R = (int)(M_RATIO + 1.0);
  for (int a = -R; a <= R; ++a)
    for (int b = -R; b <= R; ++b)
      for (int c = (dim == 3 ? -R : 0); c <= (dim == 3 ? R : 0); ++c) {
        if (!a && !b && !c) continue;
        double r = DX * sqrt((double)(a * a + b * b + c * c));
        m += r * beta_linear(r) * V;
      }
  return m;
}

/* Analytic m for w = 1/r (docs/model_reference.md 4): pi d^4 (3D), 2 pi h d^3/3 (2D). */
static double analytic_weighted_volume(int dim) {
  return dim == 3 ? M_PI * pow(DELTA, 4) : 2.0 * M_PI * THICK * pow(DELTA, 3) / 3.0;
}

static double depth(const peri_sim *s, const lp_case *c, int32_t i) {
  double h = 0.5 * c->n * DX, d = INFINITY;
  for (int k = 0; k < c->dim; ++k) d = fmin(d, h - fabs(s->disc.p.x[3 * i + k]));
  return d;
}

/* Nodes whose whole neighbourhood (to 2 x the cutoff delta + dx/2) is inside the body. */
static bool interior(const peri_sim *s, const lp_case *c, int32_t i) { return depth(s, c, i) > 2.0 * DELTA + DX; }

static double norm3(const double *v) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* max over interior nodes of |a_i - b_i| and of |b_i|. */
static void interior_diff(const peri_sim *a, const peri_sim *b, const lp_case *c, double *diff, double *ref) {
  *diff = *ref = 0.0;
  int count = 0;
  for (int32_t i = 0; i < a->disc.p.n_owned; ++i) {
    for (int d = 0; d < 3; ++d)
      cr_assert_eq(a->disc.p.x[3 * i + d], b->disc.p.x[3 * i + d], "the two runs order their nodes differently");
    if (!interior(a, c, i)) continue;
    double v[3];
    for (int d = 0; d < 3; ++d) v[d] = a->disc.p.f[3 * i + d] - b->disc.p.f[3 * i + d];
    *diff = fmax(*diff, norm3(v));
    *ref = fmax(*ref, norm3(&b->disc.p.f[3 * i]));
    count++;
  }
  cr_assert_gt(count, 0, "no interior nodes");
}

/* Force scale c V_H of a full family at unit stretch (as in test_patch.c): 24K/d (3D),
 * 9E/d (plane stress), 48E/(5d) (plane strain). Used to show the field is not trivial. */
static double force_scale(const lp_case *c, const lps_theory *t) {
  if (c->dim == 3) return 24.0 * t->K / DELTA;
  return (c->plane == PERI_PLANE_STRAIN ? 9.6 : 9.0) * c->E / DELTA;
}

/* (1) Discrete m at the PMB ratio: LPS == PMB with c = 2 (alpha m)/m on interior nodes. All
 * interior nodes have the same m; the bracket is zero up to rounding of the constants
 * (~1e-16 K), so the forces agree to rounding: 1e-10 relative. */
static void check_discrete(const lp_case *c) {
  lps_theory t = theory(c);
  peri_sim lps, pmb;
  build_lps(&lps, c, "discrete");
  double m = lattice_weighted_volume(c->dim);
  /* the code's discrete m of interior nodes is the lattice sum */
  for (int32_t i = 0; i < lps.disc.p.n_owned; ++i)
    if (depth(&lps, c, i) > DELTA + DX)
      cr_assert(fabs(lps.disc.p.wvol[i] / m - 1.0) < 1e-12, "m_i = %.17g, lattice sum %.17g", lps.disc.p.wvol[i], m);
  build_pmb(&pmb, c, 2.0 * t.alpha_m / m);
  double half = 0.5 * c->n * DX;
  set_field(&lps, c->dim, half);
  set_field(&pmb, c->dim, half);
  lps.mat.model->force(&lps);
  pmb.mat.model->force(&pmb);
  double diff, ref;
  interior_diff(&lps, &pmb, c, &diff, &ref);
  cr_expect(ref > 1e-7 * force_scale(c, &t), "the field gives no interior force (%.3g)", ref);
  cr_expect(diff <= 1e-10 * ref, "dim %d plane %d nu %g: |f_LPS - f_PMB| = %.3g, |f_PMB| = %.3g (rel %.3g)", c->dim,
            (int)c->plane, c->nu, diff, ref, diff / ref);
  peri_sim_free(&lps);
  peri_sim_free(&pmb);
}

/* (4) The reduced form, evaluated here over the code's bond list with theta and B computed
 * in this file; m_i is B_i (discrete) or the analytic m. Returns into f, and into F the
 * sum of the magnitudes of the pair-force terms (the rounding scale of f). */
static void reduced_lps_force(const peri_sim *s, const lps_theory *t, bool analytic, double *f, double *F) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  int32_t n = p->n_owned;
  double *theta = calloc((size_t)n, sizeof(double)), *m = calloc((size_t)n, sizeof(double)),
         *B = calloc((size_t)n, sizeof(double));
  double m_an = analytic_weighted_volume(p->dim);
  for (int32_t i = 0; i < n; ++i) {
    double sum_e = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      int32_t j = b->neighbor[k];
      double dy[3], L = peri_bond_length(p->x, i, j), w = peri_bonds_beta(b, L) * p->volume[j], om = 1.0 / L;
      for (int d = 0; d < 3; ++d) dy[d] = (p->x[3 * j + d] + p->u[3 * j + d]) - (p->x[3 * i + d] + p->u[3 * i + d]);
      sum_e += om * L * (norm3(dy) - L) * w;
      B[i] += om * L * L * w;
    }
    m[i] = analytic ? m_an : B[i];
    theta[i] = t->n_theta / m[i] * sum_e;
  }
  for (int32_t i = 0; i < n; ++i) {
    double fi[3] = {0.0, 0.0, 0.0}, Fi = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      int32_t j = b->neighbor[k];
      double dy[3], L = peri_bond_length(p->x, i, j), w = peri_bonds_beta(b, L) * p->volume[j], om = 1.0 / L;
      for (int d = 0; d < 3; ++d) dy[d] = (p->x[3 * j + d] + p->u[3 * j + d]) - (p->x[3 * i + d] + p->u[3 * i + d]);
      double r = norm3(dy), e = r - L, pair = 0.0;
      int32_t ends[2] = {i, j};
      for (int a = 0; a < 2; ++a) {
        int32_t q = ends[a];
        double bracket = t->n_theta * t->K_theta - 2.0 / 3.0 * t->alpha_m + t->n_theta / 9.0 * t->alpha_m * B[q] / m[q];
        double half_dil = bracket * theta[q] * om * L / m[q], half_dev = t->alpha_m / m[q] * om * e;
        pair += half_dil + half_dev;
        Fi += (fabs(half_dil) + fabs(half_dev)) * w;
      }
      for (int d = 0; d < 3; ++d) fi[d] += pair * w * dy[d] / r;
    }
    for (int d = 0; d < 3; ++d) f[3 * i + d] = fi[d];
    F[i] = Fi;
  }
  free(theta);
  free(m);
  free(B);
}

/* Each node's LPS force equals the reduced form: rounding only, so 1e-10 of the sum of
 * the magnitudes of its pair-force terms (each is computed to ~1e-11 relative, since
 * e = |y_j - y_i| - |xi| loses ~5 digits at |e| ~ 1e-4 |xi|, and these errors are random). */
static void check_reduced_form(const lp_case *c, const char *weighted_volume) {
  lps_theory t = theory(c);
  peri_sim s;
  build_lps(&s, c, weighted_volume);
  set_field(&s, c->dim, 0.5 * c->n * DX);
  s.mat.model->force(&s);
  double *f = calloc(3 * (size_t)s.disc.p.n_owned, sizeof(double)), *F = calloc((size_t)s.disc.p.n_owned, sizeof(double));
  reduced_lps_force(&s, &t, weighted_volume[0] == 'a', f, F);
  double worst = 0.0;
  int32_t at = -1;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i) {
    double v[3];
    for (int d = 0; d < 3; ++d) v[d] = s.disc.p.f[3 * i + d] - f[3 * i + d];
    if (norm3(v) / F[i] > worst) worst = norm3(v) / F[i], at = i;
  }
  cr_expect(worst <= 1e-10, "dim %d plane %d nu %g %s: node %d (depth %g dx) differs from the reduced form by %.3g "
            "of its bond-force sum", c->dim, (int)c->plane, c->nu, weighted_volume, at,
            at >= 0 ? depth(&s, c, at) / DX : 0.0, worst);
  free(f);
  free(F);
  peri_sim_free(&s);
}

/* (2) Analytic m: against the PMB of docs/model_reference.md 2.3 (c = 2 (alpha m)/m_analytic = 18K/(pi
 * d^4), 9E/(pi h d^3), 48E/(5 pi h d^3)). On interior nodes B = m_discrete for all, and
 * the difference is the (B/m - 1) term, (n alpha m (B/m - 1)/(9m)) sum (theta_i + theta_j)
 * w |xi| M w_ij. Expected size: |B/m - 1| relative, asserted with a safety factor 2. */
static void check_analytic(const lp_case *c) {
  lps_theory t = theory(c);
  peri_sim lps, pmb;
  build_lps(&lps, c, "analytic");
  double m = analytic_weighted_volume(c->dim), B = lattice_weighted_volume(c->dim);
  double c_pmb = c->dim == 3 ? 18.0 * t.K / (M_PI * pow(DELTA, 4))
                 : c->plane == PERI_PLANE_STRAIN ? 48.0 * c->E / (5.0 * M_PI * THICK * pow(DELTA, 3))
                                                 : 9.0 * c->E / (M_PI * THICK * pow(DELTA, 3));
  cr_expect(fabs(2.0 * t.alpha_m / m / c_pmb - 1.0) < 1e-12, "2 alpha m/m = %.17g, c = %.17g", 2.0 * t.alpha_m / m,
            c_pmb);
  build_pmb(&pmb, c, c_pmb);
  double half = 0.5 * c->n * DX;
  set_field(&lps, c->dim, half);
  set_field(&pmb, c->dim, half);
  lps.mat.model->force(&lps);
  pmb.mat.model->force(&pmb);
  double diff, ref, tol = 2.0 * fabs(B / m - 1.0);
  interior_diff(&lps, &pmb, c, &diff, &ref);
  cr_expect(diff <= tol * ref, "dim %d plane %d: |f_LPS - f_PMB| / |f_PMB| = %.4f > 2 |B/m - 1| = %.4f", c->dim,
            (int)c->plane, diff / ref, tol);
  peri_sim_free(&lps);
  peri_sim_free(&pmb);
}

/* nu = 1/4 by E and nu; nu = 1/3 exactly through K = 8 mu/3 (E = 9 K mu/(3K + mu) = 72 GPa). */
static const lp_case ps_third = {2, PERI_PLANE_STRESS, 30, 72.0e9, 1.0 / 3.0, "bulk_modulus: 72e9, shear_modulus: 27e9"};
static const lp_case pe_quarter = {2, PERI_PLANE_STRAIN, 30, 70.0e9, 0.25, "youngs_modulus: 70e9, poisson_ratio: 0.25"};
static const lp_case d3_quarter = {3, PERI_PLANE_NONE, 18, 70.0e9, 0.25, "youngs_modulus: 70e9, poisson_ratio: 0.25"};
static const lp_case d3_fifth = {3, PERI_PLANE_NONE, 18, 70.0e9, 0.2, "youngs_modulus: 70e9, poisson_ratio: 0.2"};
static const lp_case ps_03 = {2, PERI_PLANE_STRESS, 30, 70.0e9, 0.3, "youngs_modulus: 70e9, poisson_ratio: 0.3"};
static const lp_case pe_03 = {2, PERI_PLANE_STRAIN, 30, 70.0e9, 0.3, "youngs_modulus: 70e9, poisson_ratio: 0.3"};

Test(lps_pmb, discrete_plane_stress_nu_third) { check_discrete(&ps_third); }
Test(lps_pmb, discrete_plane_strain_nu_quarter) { check_discrete(&pe_quarter); }
Test(lps_pmb, discrete_3d_nu_quarter) { check_discrete(&d3_quarter); }

Test(lps_pmb, analytic_plane_stress_nu_third) { check_analytic(&ps_third); }
Test(lps_pmb, analytic_plane_strain_nu_quarter) { check_analytic(&pe_quarter); }
Test(lps_pmb, analytic_3d_nu_quarter) { check_analytic(&d3_quarter); }

/* (3) At nu = 0.2 the bracket 3K - 5 mu = -E/2.4 is not zero: the dilatation term changes
 * the interior force by more than 1% against the PMB with c = 2 (15 mu)/m. */
Test(lps_pmb, differs_3d_nu_fifth) {
  lps_theory t = theory(&d3_fifth);
  peri_sim lps, pmb;
  build_lps(&lps, &d3_fifth, "discrete");
  build_pmb(&pmb, &d3_fifth, 2.0 * t.alpha_m / lattice_weighted_volume(3));
  double half = 0.5 * d3_fifth.n * DX;
  set_field(&lps, 3, half);
  set_field(&pmb, 3, half);
  lps.mat.model->force(&lps);
  pmb.mat.model->force(&pmb);
  double diff, ref;
  interior_diff(&lps, &pmb, &d3_fifth, &diff, &ref);
  cr_expect(diff > 0.01 * ref, "nu = 0.2: |f_LPS - f_PMB| / |f_PMB| = %.4f, expected > 1%%", diff / ref);
  peri_sim_free(&lps);
  peri_sim_free(&pmb);
}

/* (4) Every node, surface included (partial families, different m_i at the two ends). In
 * 3D with the discrete m this is the LAMMPS peri/lps pair force of docs/model_reference.md 3.1. */
Test(lps_pmb, reduced_form_3d_nu_fifth_discrete) { check_reduced_form(&d3_fifth, "discrete"); }
Test(lps_pmb, reduced_form_3d_nu_quarter_analytic) { check_reduced_form(&d3_quarter, "analytic"); }
Test(lps_pmb, reduced_form_plane_stress_nu_03_discrete) { check_reduced_form(&ps_03, "discrete"); }
Test(lps_pmb, reduced_form_plane_stress_nu_third_analytic) { check_reduced_form(&ps_third, "analytic"); }
Test(lps_pmb, reduced_form_plane_strain_nu_03_analytic) { check_reduced_form(&pe_03, "analytic"); }
Test(lps_pmb, reduced_form_plane_strain_nu_quarter_discrete) { check_reduced_form(&pe_quarter, "discrete"); }
