/* Sublayers fitted to a 2D or 3D family (docs/plasticity.md section 4, "3D bars and the
 * family calibration"): under uniaxial stress a bond at direction cosine c to the axis has the stretch
 * s = eps (c^2 - nu (1 - c^2)), so the bonds of a family yield one direction after the other
 * and the bar's curve is an average of the bond curve over directions, not the bond curve.
 * The fit chooses the weights of sublayers on a fixed ladder of yield stretches so that this
 * average follows the uniaxial curve: a non-negative least-squares fit (Lawson-Hanson) at
 * the breakpoints and along the piecewise-linear curve, sum W = 1. */
#include <math.h>
#include "peri/plasticity.h"

/* Gauss-Legendre points on [0, 1] for the direction average (the integrands are piecewise
 * smooth, 64 points resolve them to well below the fit's residual). */
#define DIRECTIONS 64
/* samples of the curve between 0 and the last breakpoint, besides the breakpoints */
#define CURVE_SAMPLES 96
/* weight of a curve sample against a breakpoint's in the least squares */
#define CURVE_SAMPLE_WEIGHT 0.1
/* the ladder of yield stretches: PERI_MAX_SUBLAYERS values from this fraction of the first
 * breakpoint's strain to the last breakpoint's, geometric */
#define LADDER_LOW 0.25

static void gauss_legendre_01(int n, double *x, double *w) {
  for (int i = 0; i < n; ++i) {
    double z = cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (fabs(dz) < 1e-15) break;
    }
    x[i] = 0.5 * (1.0 - z);
    w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
  }
}

/* The direction measure of a family: 3D, c = cos(angle) uniform on [0, 1]; 2D, the angle
 * uniform on [0, pi/2]. Fills the bond stretch per unit bar strain a[] and the axial
 * stress weight q[] (c^2 times the measure), normalised so that sum q a = 1: then the bar's
 * stress over E is sum q g(eps a) for a bond curve g (stretch -> stress over E). */
static void family_directions(int dim, double nu, double *a, double *q) {
  double x[DIRECTIONS], w[DIRECTIONS], norm = 0.0;
  gauss_legendre_01(DIRECTIONS, x, w);
  for (int i = 0; i < DIRECTIONS; ++i) {
    const double c = dim == 3 ? x[i] : cos(0.5 * M_PI * x[i]);
    a[i] = c * c - nu * (1.0 - c * c);
    q[i] = w[i] * c * c;
    norm += q[i] * a[i];
  }
  for (int i = 0; i < DIRECTIONS; ++i) q[i] /= norm;
}

double peri_sublayers_family_stress(int dim, double nu, const peri_sublayers *sl, double eps) {
  double a[DIRECTIONS], q[DIRECTIONS], sigma = 0.0;
  family_directions(dim, nu, a, q);
  for (int i = 0; i < DIRECTIONS; ++i) {
    const double s = eps * a[i];
    double g = 0.0;
    for (int k = 0; k < sl->n; ++k) g += sl->weight[k] * fmax(-sl->yield[k], fmin(s, sl->yield[k]));
    sigma += q[i] * g;
  }
  return sigma;
}

/* Least squares min |A x - b| over the columns in `active` (Householder QR of a copy). */
static void least_squares(int m, int n, const double *A, const double *b, const int *active, int na, double *x) {
  double R[m * na], y[m];
  for (int r = 0; r < m; ++r) {
    y[r] = b[r];
    for (int j = 0; j < na; ++j) R[r * na + j] = A[r * n + active[j]];
  }
  for (int j = 0; j < na; ++j) {
    double norm = 0.0;
    for (int r = j; r < m; ++r) norm += R[r * na + j] * R[r * na + j];
    norm = sqrt(norm);
    if (norm == 0.0) continue;
    const double alpha = R[j * na + j] > 0.0 ? -norm : norm;
    double v[m], vv = 0.0;
    for (int r = j; r < m; ++r) v[r] = R[r * na + j] - (r == j ? alpha : 0.0), vv += v[r] * v[r];
    if (vv == 0.0) continue;
    for (int k = j; k < na; ++k) {
      double d = 0.0;
      for (int r = j; r < m; ++r) d += v[r] * R[r * na + k];
      for (int r = j; r < m; ++r) R[r * na + k] -= 2.0 * d / vv * v[r];
    }
    double d = 0.0;
    for (int r = j; r < m; ++r) d += v[r] * y[r];
    for (int r = j; r < m; ++r) y[r] -= 2.0 * d / vv * v[r];
  }
  for (int j = na - 1; j >= 0; --j) {
    double t = y[j];
    for (int k = j + 1; k < na; ++k) t -= R[j * na + k] * x[k];
    x[j] = R[j * na + j] != 0.0 ? t / R[j * na + j] : 0.0;
  }
}

/* Non-negative least squares (Lawson and Hanson, Solving Least Squares Problems, 1974,
 * ch. 23): min |A x - b| with x >= 0, A m x n row-major. */
static void nnls(int m, int n, const double *A, const double *b, double *x) {
  bool in[n];
  for (int j = 0; j < n; ++j) x[j] = 0.0, in[j] = false;
  for (int outer = 0; outer < 3 * n; ++outer) {
    double grad[n], best = 1e-14;
    int enter = -1;
    for (int j = 0; j < n; ++j) {
      grad[j] = 0.0;
      for (int r = 0; r < m; ++r) {
        double res = b[r];
        for (int k = 0; k < n; ++k) res -= A[r * n + k] * x[k];
        grad[j] += A[r * n + j] * res;
      }
      if (!in[j] && grad[j] > best) best = grad[j], enter = j;
    }
    if (enter < 0) return;
    in[enter] = true;
    for (int inner = 0; inner < 3 * n; ++inner) {
      int active[n], na = 0;
      for (int j = 0; j < n; ++j)
        if (in[j]) active[na++] = j;
      double z[n];
      least_squares(m, n, A, b, active, na, z);
      double step = 1.0;
      for (int j = 0; j < na; ++j)
        if (z[j] <= 0.0) {
          const double xa = x[active[j]];
          step = fmin(step, xa / (xa - z[j]));
        }
      for (int j = 0; j < na; ++j) x[active[j]] += step * (z[j] - x[active[j]]);
      if (step >= 1.0) break;
      for (int j = 0; j < na; ++j)
        if (x[active[j]] <= 1e-15) x[active[j]] = 0.0, in[active[j]] = false;
    }
  }
}

/* The piecewise-linear curve through the origin and the breakpoints, over E, flat beyond. */
static double curve_over_E(double E, int n, const double *strain, const double *stress, double eps) {
  if (eps <= strain[0]) return eps * stress[0] / (E * strain[0]);
  for (int k = 1; k < n; ++k)
    if (eps <= strain[k])
      return (stress[k - 1] + (stress[k] - stress[k - 1]) * (eps - strain[k - 1]) / (strain[k] - strain[k - 1])) / E;
  return stress[n - 1] / E;
}

void peri_sublayers_fit_family(int dim, double nu, double E, int n, const double *strain, const double *stress,
                               peri_sublayers *out) {
  enum { COLS = PERI_MAX_SUBLAYERS, ROWS = PERI_MAX_SUBLAYERS + CURVE_SAMPLES + 1 };
  double ladder[COLS], a[DIRECTIONS], q[DIRECTIONS], samples[ROWS], row_weight[ROWS];
  const double lo = LADDER_LOW * strain[0], hi = strain[n - 1];
  for (int j = 0; j < COLS; ++j) ladder[j] = lo * pow(hi / lo, (double)j / (COLS - 1));
  family_directions(dim, nu, a, q);
  int m = 0;
  for (int k = 0; k < n; ++k) samples[m] = strain[k], row_weight[m++] = 1.0;
  for (int i = 1; i <= CURVE_SAMPLES; ++i) samples[m] = hi * i / CURVE_SAMPLES, row_weight[m++] = CURVE_SAMPLE_WEIGHT;
  /* rows: relative misfit at each sample; the last row holds sum W = 1 (weight 1e3) */
  double A[ROWS * COLS], b[ROWS], W[COLS];
  for (int r = 0; r < m; ++r) {
    const double target = curve_over_E(E, n, strain, stress, samples[r]), scale = row_weight[r] / target;
    for (int j = 0; j < COLS; ++j) {
      double f = 0.0;
      for (int i = 0; i < DIRECTIONS; ++i) f += q[i] * fmax(-ladder[j], fmin(samples[r] * a[i], ladder[j]));
      A[r * COLS + j] = f * scale;
    }
    b[r] = target * scale;
  }
  for (int j = 0; j < COLS; ++j) A[m * COLS + j] = 1e3;
  b[m] = 1e3;
  nnls(m + 1, COLS, A, b, W);
  double sum = 0.0;
  for (int j = 0; j < COLS; ++j) sum += W[j];
  out->n = 0;
  for (int j = 0; j < COLS; ++j)
    if (W[j] > 0.0) out->weight[out->n] = W[j] / sum, out->yield[out->n++] = ladder[j];
}
