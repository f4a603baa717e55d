/* Peridynamic heat conduction: micro-conductivity constants, the continuum flux of a
 * linear field, and the discrete conduction operator (Bobaru & Duangpanya 2012 sec. 2-3; docs/model_reference.md 11). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/error.h"
#include "peri/model.h"
#include "peri/sim.h"
#include "peri/thermal.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ---------------------------------------------------------------- constants */

/* From (1/2) int_H k(r) xi_1^2 / r^2 dV = kappa (the flux of T = a x over H+ is kappa a):
 *   1D: (1/2) 2 int_0^d k dr;  2D: (pi/2) int_0^d k r dr;  3D: (2 pi/3) int_0^d k r^2 dr. */
double peri_thermal_k_constant(peri_thermal_kernel kernel, int dim, double kappa, double delta) {
  if (kernel == PERI_TKERNEL_CONSTANT) {
    if (dim == 1) return kappa / delta;
    if (dim == 2) return 4.0 * kappa / (M_PI * delta * delta);
    return 9.0 * kappa / (2.0 * M_PI * delta * delta * delta);
  }
  if (dim == 1) return 2.0 * kappa / delta;
  if (dim == 2) return 12.0 * kappa / (M_PI * delta * delta);
  return 18.0 * kappa / (M_PI * delta * delta * delta);
}

double peri_thermal_k(peri_thermal_kernel kernel, int dim, double kappa, double delta, double r) {
  double k0 = peri_thermal_k_constant(kernel, dim, kappa, delta);
  if (kernel == PERI_TKERNEL_CONSTANT) return k0;
  double f = 1.0 - r / delta;
  return f > 0.0 ? k0 * f : 0.0;
}

double peri_thermal_bond_kappa(peri_thermal_bond_rule rule, double ka, double kb) {
  if (ka == kb) return ka;
  if (rule == PERI_TBOND_HARMONIC) return (ka > 0.0 && kb > 0.0) ? 2.0 * ka * kb / (ka + kb) : 0.0;
  return ka < kb ? ka : kb;
}

/* Gauss-Legendre nodes and weights on [a, b] (Newton on P_n). */
static void gauss_legendre(int n, double a, double b, double *x, double *w) {
  for (int i = 0; i < n; ++i) {
    double z = cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = 0.0;
      for (int j = 0; j < n; ++j) {
        double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * j + 1.0) * z * p1 - j * p2) / (j + 1.0);
      }
      dp = n * (z * p0 - p1) / (z * z - 1.0);
      double dz = p0 / dp;
      z -= dz;
      if (fabs(dz) < 1e-16) break;
    }
    x[i] = 0.5 * (a + b) - 0.5 * (b - a) * z;
    w[i] = (b - a) / ((1.0 - z * z) * dp * dp);
  }
}

/* q = int_{H+} k(r) (g.xi)/r e dV, H+ = {g.xi > 0}, in a frame (e1 = g/|g|, e2, e3). */
void peri_thermal_flux_integral(peri_thermal_kernel kernel, int dim, double kappa, double delta,
                                const double g[3], double q[3]) {
  q[0] = q[1] = q[2] = 0.0;
  double gn = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (gn == 0.0) return;
  double e1[3] = {g[0] / gn, g[1] / gn, g[2] / gn};
  enum { NR = 8, NA = 40 };
  double xr[NR], wr[NR];
  gauss_legendre(NR, 0.0, delta, xr, wr);
  /* radial moments int_0^d k(r) r^(dim-1) dr (polynomial: exact with 8 points) */
  double radial = 0.0;
  for (int a = 0; a < NR; ++a)
    radial += wr[a] * peri_thermal_k(kernel, dim, kappa, delta, xr[a]) * pow(xr[a], dim - 1);
  if (dim == 1) {
    /* H+ is the half line along g: (g.e) e = |g| e1 */
    for (int d = 0; d < 3; ++d) q[d] = gn * e1[d] * radial;
    return;
  }
  double e2[3], e3[3];
  if (dim == 2) {
    e2[0] = -e1[1], e2[1] = e1[0], e2[2] = 0.0;
    double xa[NA], wa[NA];
    gauss_legendre(NA, -0.5 * M_PI, 0.5 * M_PI, xa, wa);
    for (int a = 0; a < NA; ++a) {
      double c = cos(xa[a]), s = sin(xa[a]);
      for (int d = 0; d < 3; ++d) q[d] += wa[a] * gn * c * (c * e1[d] + s * e2[d]) * radial;
    }
    return;
  }
  /* 3D: mu = cos(angle to g) in (0, 1], azimuth psi; dV = r^2 dr dmu dpsi */
  double t[3] = {fabs(e1[0]) < 0.9 ? 1.0 : 0.0, fabs(e1[0]) < 0.9 ? 0.0 : 1.0, 0.0};
  double dot = t[0] * e1[0] + t[1] * e1[1] + t[2] * e1[2];
  for (int d = 0; d < 3; ++d) e2[d] = t[d] - dot * e1[d];
  double n2 = sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
  for (int d = 0; d < 3; ++d) e2[d] /= n2;
  e3[0] = e1[1] * e2[2] - e1[2] * e2[1];
  e3[1] = e1[2] * e2[0] - e1[0] * e2[2];
  e3[2] = e1[0] * e2[1] - e1[1] * e2[0];
  double xm[NR], wm[NR];
  gauss_legendre(NR, 0.0, 1.0, xm, wm);
  const int npsi = 16; /* trapezoid rule: exact for trigonometric polynomials of degree < 16 */
  for (int a = 0; a < NR; ++a)
    for (int b = 0; b < npsi; ++b) {
      double mu = xm[a], st = sqrt(1.0 - mu * mu), psi = 2.0 * M_PI * b / npsi;
      double w = wm[a] * (2.0 * M_PI / npsi) * gn * mu * radial;
      for (int d = 0; d < 3; ++d) q[d] += w * (mu * e1[d] + st * (cos(psi) * e2[d] + sin(psi) * e3[d]));
    }
}

/* ---------------------------------------------------------------- operator */

/* Linear partial-area factor of Bobaru & Duangpanya 2012 Algorithm 1 (= docs/model_reference.md 5(a)). */
static double algorithm1_factor(double r, double delta, double dx) {
  if (r < delta - 0.5 * dx) return 1.0;
  double f = (delta + 0.5 * dx - r) / dx;
  return f < 0.0 ? 0.0 : (f > 1.0 ? 1.0 : f);
}

/* The kernel argument of Algorithm 1 (docs/model_reference.md 5(b)). */
static double algorithm1_argument(double r, double delta, double dx) {
  if (r < delta - 0.5 * dx) return r;
  double f = algorithm1_factor(r, delta, dx);
  if (r <= delta) return r - dx * (1.0 - f) / 2.0;
  return delta - dx * f / 2.0;
}

static double node_gfac(const peri_sim *s) {
  if (s->disc.geom.dim == 2) return s->disc.geom.thickness;
  if (s->disc.geom.dim == 1) return s->disc.geom.cross_section;
  return 1.0;
}

int peri_thermal_build(peri_sim *s) {
  peri_thermal *th = s->thermal;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int dim = s->disc.geom.dim;
  const double dx = s->disc.geom.spacing, delta = s->disc.geom.horizon, gfac = node_gfac(s);
  const int32_t n = p->n_owned;
  const size_t nb = (size_t)(b->n_bonds > 0 ? b->n_bonds : 1);
  th->n = n;
  th->area = peri_malloc(sizeof(double) * (size_t)n);
  th->rhoc = peri_malloc(sizeof(double) * (size_t)n);
  th->H = peri_calloc(nb, sizeof(double));
  th->Hs = peri_calloc(nb, sizeof(double));
  th->alg_axis = peri_calloc((size_t)n, sizeof(int8_t));
  for (int32_t i = 0; i < n; ++i) {
    const peri_material *m = &s->mat.materials[p->material[i]];
    th->rhoc[i] = m->density * m->specific_heat;
    th->area[i] = p->volume[i] / gfac;
  }
  /* Boundary nodes of a vertex-centred grid: a missing axial neighbour at +-dx along an
   * axis halves the node's area (edge 1/2, corner 1/4; Bobaru & Duangpanya 2012 sec. 3) and gives the
   * outward normal of the flux rule (the highest such axis: y at corners, docs/model_reference.md 11.3). */
  const double tol = 1e-6 * dx;
  for (int32_t i = 0; i < n; ++i) {
    double factor = 1.0;
    for (int d = 0; d < dim; ++d) {
      bool plus = false, minus = false;
      for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
        const int32_t j = b->neighbor[k];
        double off = 0.0;
        for (int e = 0; e < 3; ++e)
          if (e != d) off += fabs(p->x[3 * j + e] - p->x[3 * i + e]);
        if (off > tol) continue;
        double xd = p->x[3 * j + d] - p->x[3 * i + d];
        if (fabs(xd - dx) < tol) plus = true;
        if (fabs(xd + dx) < tol) minus = true;
      }
      if (!plus || !minus) factor *= 0.5;
      if (!minus) th->alg_axis[i] = (int8_t)(-(d + 1));
      if (!plus) th->alg_axis[i] = (int8_t)(d + 1);
    }
    if (th->quadrature == PERI_TQUAD_BOBARU2012) th->area[i] *= factor;
  }
  const bool bobaru = th->quadrature == PERI_TQUAD_BOBARU2012;
  const int shell = dim == 1 ? 2 : dim == 2 ? 8 : 26;
#pragma omp parallel for schedule(dynamic, 256)
  for (int32_t i = 0; i < n; ++i) {
    const double ki = s->mat.materials[p->material[i]].conductivity;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double r = peri_bond_length(p->x, i, j);
      const double kb = peri_thermal_bond_kappa(th->bond_rule, ki, s->mat.materials[p->material[j]].conductivity);
      double f, arg;
      if (bobaru) {
        f = algorithm1_factor(r, delta, dx);
        arg = algorithm1_argument(r, delta, dx);
      } else {
        f = peri_bonds_beta(b, r);
        arg = r;
      }
      double h = peri_thermal_k(th->kernel, dim, kb, delta, arg) * f * th->area[j] / (r * r);
      double hs = 0.0;
      if (th->self_term == PERI_TSELF_CELL && fabs(r - dx) < tol) {
        /* own cell: int_cell (1/2) k e.Hess(T).e dV = k(0) lap(T) V / (2 dim), carried by
         * the 2 dim axial neighbours, sum (T_p - T_i) = dx^2 lap(T) */
        hs = peri_thermal_k(th->kernel, dim, kb, delta, 0.0) * th->area[j] / (2.0 * dim * dx * dx);
      } else if (th->self_term == PERI_TSELF_BOBARU2012) {
        bool nearest = true;
        for (int e = 0; e < 3; ++e)
          if (fabs(p->x[3 * j + e] - p->x[3 * i + e]) > dx + tol) nearest = false;
        if (nearest) {
          /* Bobaru & Duangpanya 2012 sec. 3: (1/8) sum_k k(s) (T_k - T_i) A_i / s^2, s = r/2 (docs/model_reference.md 11.3) */
          const double sh = 0.5 * r;
          hs = peri_thermal_k(th->kernel, dim, kb, delta, sh) * th->area[i] / (shell * sh * sh);
        }
      }
      th->Hs[k] = hs;
      th->H[k] = h + hs;
    }
  }
  return PERI_OK;
}

double peri_thermal_stable_dt(const peri_thermal *th) {
  if (!(th->max_row_sum > 0.0)) return INFINITY;
  /* RK4's stability interval on the negative real axis is [-2.785293563405282, 0] */
  if (th->integrator == PERI_TINT_RK4) return 0.5 * 2.785293563405282 / th->max_row_sum;
  return 1.0 / th->max_row_sum;
}

/* ---------------------------------------------------------------- the heat-only "model" */

static int heat_only_init(peri_sim *s) {
  (void)s;
  return PERI_OK;
}

static long heat_only_force(peri_sim *s) {
  memset(s->disc.p.f, 0, sizeof(double) * 3 * (size_t)s->disc.p.n_owned);
  return 0;
}

static void heat_only_energy(peri_sim *s, double *W) {
  memset(W, 0, sizeof(double) * (size_t)s->disc.p.n_owned);
}

const peri_model_ops peri_model_heat_only = {
    .name = "heat",
    .description = "heat conduction only (no mechanics)",
    .fixed_poisson = 0,
    .init = heat_only_init,
    .force = heat_only_force,
    .energy = heat_only_energy,
};

void peri_thermal_free(peri_thermal *th) {
  if (!th) return;
  free(th->T);
  free(th->T_ref);
  free(th->rhoc);
  free(th->area);
  free(th->H);
  free(th->Hs);
  if (th->own_cut) free(th->cut);
  free(th->source);
  free(th->sink);
  free(th->fixed);
  free(th->alg_axis);
  free(th->alg_bc);
  for (int k = 0; k < th->n_bcs; ++k) {
    peri_expr_free(th->bcs[k].value);
    peri_expr_free(th->bcs[k].ambient);
  }
  free(th->bcs);
  free(th->growing);
  free(th->growing_bond);
  free(th->growing_time);
  free(th->flux);
  for (int k = 0; k < 6; ++k) free(th->work[k]);
  free(th);
}
