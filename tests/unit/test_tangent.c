/* Tangent stiffness of the models (src/model/pmb_tangent.c, lps_tangent.c): every block
 * K_ij = d f_i / d u_j equals the central difference of the model's own force, under a
 * large rotation (0.5 rad) plus a 2% stretch and noise, with broken bonds and thermal
 * strain; V_i K_ij is symmetric (the forces derive from an energy). Central differences
 * with step h = 1e-6 dx have a truncation error ~ (h/dx)^2 and a round-off error ~ 1e-16
 * dx/h relative to the largest entry, so the analytic blocks must agree to 1e-6. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/model.h"
#include "peri/setup.h"
#include "support.h"

static const char *deck2d =
    "dimension: 2\n"
    "plane: stress\n"
    "materials: {m: {model: %s, density: 1000, youngs_modulus: 70e9, poisson_ratio: %s}}\n"
    "discretization: {spacing: 1e-3, m: 3, fill: [{shape: rectangle, min: [0, 0], max: [0.008, 0.007]}]}\n"
    "solver: {type: explicit, steps: 1}\n"
    "output: {picture: false}\n";

static const char *deck3d =
    "dimension: 3\n"
    "materials: {m: {model: %s, density: 1000, youngs_modulus: 70e9, poisson_ratio: %s}}\n"
    "discretization: {spacing: 1e-3, m: 2, fill: [{shape: box, min: [0, 0, 0], max: [0.004, 0.004, 0.005]}]}\n"
    "solver: {type: explicit, steps: 1}\n"
    "output: {picture: false}\n";

typedef struct dense {
  size_t n3;
  double *K;
} dense;

static void add_dense(void *ctx, int32_t i, int32_t count, const int32_t *cols, const double *blocks) {
  dense *d = ctx;
  for (int32_t c = 0; c < count; ++c)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        d->K[(3 * (size_t)i + a) * d->n3 + 3 * (size_t)cols[c] + b] += blocks[9 * c + 3 * a + b];
}

/* u = (R - I) x + 0.02 diag(1, -0.5, 0.3) x + noise: a rotation by 0.5 rad about z. */
static void deform(peri_sim *s) {
  const double c = cos(0.5), sn = sin(0.5), dx = s->disc.geom.spacing;
  srand(7);
  for (int32_t i = 0; i < s->disc.p.n; ++i) {
    double *x = &s->disc.p.x[3 * i], *u = &s->disc.p.u[3 * i];
    const double y[3] = {1.02 * x[0], 0.99 * x[1], s->disc.geom.dim == 3 ? 1.006 * x[2] : 0.0};
    u[0] = c * y[0] - sn * y[1] - x[0];
    u[1] = sn * y[0] + c * y[1] - x[1];
    u[2] = y[2] - x[2];
    for (int d = 0; d < s->disc.geom.dim; ++d) u[d] += 1e-3 * dx * (rand() / (double)RAND_MAX - 0.5);
  }
}

/* Breaks, in both directions, the bonds that cross the plane x = 2 dx for y < 3 dx. */
static long cut(peri_sim *s) {
  const double dx = s->disc.geom.spacing;
  long count = 0;
  for (int32_t i = 0; i < s->disc.p.n; ++i)
    for (int64_t k = s->disc.bonds.offset[i]; k < s->disc.bonds.offset[i + 1]; ++k) {
      const int32_t j = s->disc.bonds.neighbor[k];
      const double *xi = &s->disc.p.x[3 * i], *xj = &s->disc.p.x[3 * j];
      if ((xi[0] - 2 * dx) * (xj[0] - 2 * dx) < 0 && xi[1] < 3 * dx && xj[1] < 3 * dx)
        s->disc.bonds.broken[k] = 1, ++count;
    }
  return count;
}

static void check(const char *deck_fmt, const char *model, const char *nu, bool thermal) {
  char deck[1024];
  snprintf(deck, sizeof deck, deck_fmt, model, nu);
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  cr_assert(s.mat.model->tangent != NULL, "model %s has no tangent", model);
  s.solver.breaking = false;
  deform(&s);
  cr_assert(cut(&s) > 0);
  if (thermal) {
    s.state.thermal_strain = calloc((size_t)s.disc.p.n + 1, sizeof(double));
    for (int32_t i = 0; i < s.disc.p.n; ++i) s.state.thermal_strain[i] = 2e-3 * (1 + (i % 5));
  }
  const size_t n = (size_t)s.disc.p.n, n3 = 3 * n;
  dense d = {n3, calloc(n3 * n3, sizeof(double))};
  s.mat.model->force(&s);
  s.mat.model->tangent(&s, add_dense, &d);
  double *fd = calloc(n3 * n3, sizeof(double)), *fp = malloc(sizeof(double) * n3);
  const double h = 1e-6 * s.disc.geom.spacing;
  for (size_t col = 0; col < n3; ++col) {
    if ((int)(col % 3) >= s.disc.geom.dim) continue;
    const double u0 = s.disc.p.u[col];
    s.disc.p.u[col] = u0 + h;
    s.mat.model->force(&s);
    memcpy(fp, s.disc.p.f, sizeof(double) * n3);
    s.disc.p.u[col] = u0 - h;
    s.mat.model->force(&s);
    s.disc.p.u[col] = u0;
    for (size_t row = 0; row < n3; ++row) fd[row * n3 + col] = (fp[row] - s.disc.p.f[row]) / (2 * h);
  }
  double kmax = 0.0, err = 0.0, asym = 0.0;
  for (size_t a = 0; a < n3; ++a)
    for (size_t b = 0; b < n3; ++b) {
      if ((int)(a % 3) >= s.disc.geom.dim || (int)(b % 3) >= s.disc.geom.dim) continue;
      const double k = d.K[a * n3 + b];
      kmax = fmax(kmax, fabs(k));
      err = fmax(err, fabs(k - fd[a * n3 + b]));
      /* V_i K_ij = (V_j K_ji)^T */
      asym = fmax(asym, fabs(s.disc.p.volume[a / 3] * k - s.disc.p.volume[b / 3] * d.K[b * n3 + a]));
    }
  const double vmax = s.disc.p.volume[0];
  cr_log_info("tangent %s %dD%s: max |K| %.4g, max |K - central difference| %.3g (%.2g relative), asymmetry "
              "%.2g relative", model, s.disc.geom.dim, thermal ? " thermal" : "", kmax, err, err / kmax,
              asym / (vmax * kmax));
  cr_assert(kmax > 0.0);
  cr_expect(err <= 1e-6 * kmax, "%s %dD: tangent differs from the force's derivative by %g of max |K|", model,
            s.disc.geom.dim, err / kmax);
  cr_expect(asym <= 1e-12 * vmax * kmax, "%s %dD: V K is not symmetric (%g)", model, s.disc.geom.dim,
            asym / (vmax * kmax));
  free(d.K);
  free(fd);
  free(fp);
  peri_sim_free(&s);
}

Test(tangent, pmb_2d) { check(deck2d, "pmb", "0.3333333333333333", false); }
Test(tangent, pmb_2d_thermal) { check(deck2d, "pmb", "0.3333333333333333", true); }
Test(tangent, lps_2d) { check(deck2d, "lps", "0.2", false); }
Test(tangent, lps_2d_thermal) { check(deck2d, "lps", "0.2", true); }
Test(tangent, pmb_3d) { check(deck3d, "pmb", "0.25", false); }
Test(tangent, lps_3d) { check(deck3d, "lps", "0.35", false); }
