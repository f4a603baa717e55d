/* The LPS force states (docs/models.md 3.5). (1) While every family is intact the peer form
 * equals the variational one (their P terms agree: P = S - theta m/3 with S = theta m/n), in
 * 2D and 3D, to round-off. (2) With bonds cut, peri's peer form equals an independent
 * evaluation of t_ij = n (K_theta theta_i - alpha_i P_i/3) omega |xi|/m_i + alpha_i omega e^d,
 * P_i = theta_i m_i (1/n - 1/3) (in 3D t = (3K theta/m) omega |xi| + alpha omega e^d), written
 * here as plain loops over the families, to 1e-10 relative; and it differs from the
 * variational form. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdlib.h>
#include "peri/setup.h"
#include "support.h"

static const char *deck2d =
    "dimension: 2\nplane: stress\n"
    "materials:\n  m: {model: lps, density: 1000, youngs_modulus: 70e9, poisson_ratio: 0.3}\n"
    "discretization: {spacing: 1.0e-3, m: 3, thickness: 1.0e-3, fill: [{shape: rectangle, min: [0, 0], max: [0.012, 0.01]}]}\n"
    "solver: {type: explicit, steps: 1, breaking: false}\noutput: {picture: false}\n";
static const char *deck3d =
    "dimension: 3\n"
    "materials:\n  m: {model: lps, density: 1000, bulk_modulus: 60e9, shear_modulus: 25e9}\n"
    "discretization: {spacing: 1.0e-3, m: 3, fill: [{shape: box, min: [0, 0, 0], max: [0.008, 0.007, 0.006]}]}\n"
    "solver: {type: explicit, steps: 1, breaking: false}\noutput: {picture: false}\n";

/* a smooth displacement with shear and stretch */
static void displace(peri_sim *s) {
  for (int32_t i = 0; i < s->disc.p.n; ++i) {
    const double *x = &s->disc.p.x[3 * i];
    s->disc.p.u[3 * i] = 1e-5 * sin(200 * x[0]) + 3e-4 * x[1];
    s->disc.p.u[3 * i + 1] = 2e-5 * cos(150 * x[1] + 100 * x[0]);
    s->disc.p.u[3 * i + 2] = s->disc.geom.dim == 3 ? 1e-5 * sin(300 * x[2]) : 0.0;
  }
}

static void forces(peri_sim *s, bool peer, double *f) {
  s->mat.materials[0].peer_force_state = peer;
  s->mat.model->force(s);
  for (int64_t c = 0; c < 3 * (int64_t)s->disc.p.n_owned; ++c) f[c] = s->disc.p.f[c];
}

static double max_abs(const double *a, int64_t n) {
  double m = 0.0;
  for (int64_t k = 0; k < n; ++k) m = fmax(m, fabs(a[k]));
  return m;
}

/* The peer force density of every node, evaluated directly. */
static void peer_reference(const peri_sim *s, double *f) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const peri_material *mat = &s->mat.materials[0];
  const int32_t n = p->n_owned;
  double *theta = calloc((size_t)(n > 0 ? n : 1), sizeof(double));
  for (int32_t i = 0; i < n; ++i) {
    double S = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double xi[3], y[3];
      const double L = peri_bond_xi(p->x, i, j, xi);
      for (int c = 0; c < 3; ++c) y[c] = xi[c] + p->u[3 * j + c] - p->u[3 * i + c];
      const double r = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
      S += (r - L) * L * peri_bonds_beta(b, L) * p->volume[j]; /* omega = 1 */
    }
    theta[i] = mat->n_theta * S / p->wvol[i];
  }
  for (int32_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) f[3 * i + c] = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double xi[3], y[3];
      const double L = peri_bond_xi(p->x, i, j, xi);
      for (int c = 0; c < 3; ++c) y[c] = xi[c] + p->u[3 * j + c] - p->u[3 * i + c];
      const double r = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]), e = r - L;
      double t = 0.0;
      const int32_t ends[2] = {i, j};
      for (int a = 0; a < 2; ++a) {
        const int32_t q = ends[a];
        const double m = p->wvol[q], alpha = mat->alpha_m / m, P = theta[q] * m * (1.0 / mat->n_theta - 1.0 / 3.0);
        t += mat->n_theta * (mat->K_theta * theta[q] - alpha * P / 3.0) * L / m + alpha * (e - theta[q] * L / 3.0);
      }
      for (int c = 0; c < 3; ++c) f[3 * i + c] += t * peri_bonds_beta(b, L) * p->volume[j] * y[c] / r;
    }
  }
  free(theta);
}

static void check(const char *deck) {
  peri_sim s;
  cr_assert_eq(sim_from_string(&s, deck), 0);
  displace(&s);
  const int64_t n3 = 3 * (int64_t)s.disc.p.n_owned;
  const size_t bytes = sizeof(double) * (size_t)(n3 > 0 ? n3 : 1);
  double *fv = malloc(bytes), *fp = malloc(bytes), *fr = malloc(bytes);
  forces(&s, false, fv);
  forces(&s, true, fp);
  double d = 0.0;
  for (int64_t c = 0; c < n3; ++c) d = fmax(d, fabs(fv[c] - fp[c]));
  const double scale = max_abs(fv, n3);
  cr_expect(d <= 1e-12 * scale, "%dD intact: peer and variational differ by %g (scale %g)", s.disc.geom.dim, d, scale);
  /* cut every bond crossing x = 4.5 mm, and every fifth bond elsewhere (both directions) */
  peri_bonds *b = &s.disc.bonds;
  for (int32_t i = 0; i < s.disc.p.n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double xi = s.disc.p.x[3 * i], xj = s.disc.p.x[3 * j];
      if ((xi - 0.0045) * (xj - 0.0045) < 0 || (i + j) % 5 == 0) b->broken[k] = 1;
    }
  b->broken_edits++;
  forces(&s, false, fv);
  forces(&s, true, fp);
  peer_reference(&s, fr);
  double dp = 0.0, dv = 0.0;
  for (int64_t c = 0; c < n3; ++c) dp = fmax(dp, fabs(fp[c] - fr[c])), dv = fmax(dv, fabs(fv[c] - fr[c]));
  const double sc = max_abs(fr, n3);
  cr_log_info("%dD damaged: |peer - reference| %.3g, |variational - reference| %.3g (scale %.3g)", s.disc.geom.dim,
              dp, dv, sc);
  cr_expect(dp <= 1e-10 * sc, "%dD damaged: peer differs from the reference by %g (scale %g)", s.disc.geom.dim, dp, sc);
  cr_expect(dv > 1e-6 * sc, "%dD damaged: the variational form should differ from the peer form", s.disc.geom.dim);
  free(fv), free(fp), free(fr);
  peri_sim_free(&s);
}

Test(force_state, peer_2d) { check(deck2d); }
Test(force_state, peer_3d) { check(deck3d); }
