/* Homogenized moduli of a nanocomposite RVE (002_b20c318388227af9.txt §3.3.1, eqs. 3.3-3.9).
 *
 * The n x n periodic cell is surrounded by boundary layers one horizon deep whose phases
 * continue the cell periodically (the platelets cut by an edge go on from the opposite one).
 * The layer nodes are given the affine displacement u = eps_bar x of a load case; the cell's
 * nodes are solved for static equilibrium of the linearized bond-based model,
 * f_ij = c_ij beta_ij (xi xi^T / |xi|^3)(u_j - u_i), with c_ij = 9 E_ij / (pi delta^3) (plane
 * stress, unit thickness; model reference section 2.3) and E_ij from the bond's class (section 8):
 * matrix E_m, same platelet E_nf, matrix-filler kappa E_m, two platelets eq. 3.1. beta is the
 * linear partial-volume ramp (section 5, rule a). The average stress is the bond virial over
 * the cell, sigma = (1/A) sum_i sum_j 1/2 f_ij (x) xi_ij V_i V_j, which for an equilibrated body
 * equals the boundary reactions divided by the section (the seed's definition). */
#include "peri/rve.h"
#include "peri/bonds.h"
#include "peri/error.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

typedef struct stencil {
  int count;
  int *di, *dj;
  double *kxx, *kxy, *kyy; /* beta xi xi^T / |xi|^3 V (V = dx^2, unit thickness) */
  double *xx, *xy, *yy;    /* beta xi_a xi_b ... for the virial: beta xi (x) xi / |xi|^3 V */
  double *ex, *ey;         /* xi components (for the virial) */
} stencil;

static void stencil_free(stencil *s) {
  free(s->di), free(s->dj), free(s->kxx), free(s->kxy), free(s->kyy), free(s->ex), free(s->ey);
  s->xx = s->xy = s->yy = NULL;
}

static int stencil_build(stencil *s, int m, double dx) {
  const double delta = m * dx;
  const int reach = m + 1;
  const int cap = (2 * reach + 1) * (2 * reach + 1);
  memset(s, 0, sizeof *s);
  s->di = malloc((size_t)cap * sizeof(int)), s->dj = malloc((size_t)cap * sizeof(int));
  s->kxx = malloc((size_t)cap * sizeof(double)), s->kxy = malloc((size_t)cap * sizeof(double));
  s->kyy = malloc((size_t)cap * sizeof(double));
  s->ex = malloc((size_t)cap * sizeof(double)), s->ey = malloc((size_t)cap * sizeof(double));
  if (!s->di || !s->dj || !s->kxx || !s->kxy || !s->kyy || !s->ex || !s->ey) return -1;
  for (int dj = -reach; dj <= reach; ++dj)
    for (int di = -reach; di <= reach; ++di) {
      if (!di && !dj) continue;
      const double x = di * dx, y = dj * dx, r = sqrt(x * x + y * y);
      const double beta = peri_partial_volume_factor(PERI_PV_LINEAR, r, delta, dx);
      if (beta <= 0) continue;
      const double w = beta * dx * dx / (r * r * r);
      const int k = s->count++;
      s->di[k] = di, s->dj[k] = dj;
      s->kxx[k] = w * x * x, s->kxy[k] = w * x * y, s->kyy[k] = w * y * y;
      s->ex[k] = x, s->ey[k] = y;
    }
  return 0;
}

/* The whole grid: (n + 2m)^2 nodes, the cell's at [m, m + n) in both directions. */
typedef struct rve_grid {
  int n, m, side; /* side = n + 2m */
  const int32_t *platelet;
  double E_m, E_nf, E_intph, E_agglm;
} rve_grid;

static int32_t phase_of(const rve_grid *g, int I, int J) {
  int i = (I - g->m) % g->n, j = (J - g->m) % g->n;
  if (i < 0) i += g->n;
  if (j < 0) j += g->n;
  return g->platelet[i + (long)g->n * j];
}

/* The four bond classes (model reference section 8, 002_b20c318388227af9.txt eq. 3.1). */
static double bond_modulus(const rve_grid *g, int32_t a, int32_t b) {
  if (a < 0 && b < 0) return g->E_m;
  if (a < 0 || b < 0) return g->E_intph;
  return a == b ? g->E_nf : g->E_agglm;
}

typedef struct system {
  rve_grid g;
  stencil st;
  double c_scale;   /* 9 / (pi delta^3) */
  int32_t *phase;   /* phase of every grid node, side^2 */
  double *Einv;     /* 2x2 block Jacobi inverses of the cell nodes, 3 per node */
} system_t;

/* f_i = sum_j k_ij (u_j - u_i) at the cell's nodes (out: 2 n^2), u over the whole grid. */
static void forces(const system_t *s, const double *u, double *out) {
  const rve_grid *g = &s->g;
  const int N = g->side;
  for (int j = 0; j < g->n; ++j)
    for (int i = 0; i < g->n; ++i) {
      const int I = i + g->m, J = j + g->m;
      const long a = I + (long)N * J;
      const int32_t pa = s->phase[a];
      double fx = 0, fy = 0;
      for (int k = 0; k < s->st.count; ++k) {
        const long b = (I + s->st.di[k]) + (long)N * (J + s->st.dj[k]);
        const double E = bond_modulus(g, pa, s->phase[b]);
        const double dux = u[2 * b] - u[2 * a], duy = u[2 * b + 1] - u[2 * a + 1];
        fx += E * (s->st.kxx[k] * dux + s->st.kxy[k] * duy);
        fy += E * (s->st.kxy[k] * dux + s->st.kyy[k] * duy);
      }
      const long c = i + (long)g->n * j;
      out[2 * c] = s->c_scale * fx, out[2 * c + 1] = s->c_scale * fy;
    }
}

/* Average stress of the cell: the bond virial (header comment), components xx, yy. */
static void average_stress(const system_t *s, const double *u, double sigma[2]) {
  const rve_grid *g = &s->g;
  const int N = g->side;
  double sxx = 0, syy = 0;
  for (int j = 0; j < g->n; ++j)
    for (int i = 0; i < g->n; ++i) {
      const int I = i + g->m, J = j + g->m;
      const long a = I + (long)N * J;
      for (int k = 0; k < s->st.count; ++k) {
        const long b = (I + s->st.di[k]) + (long)N * (J + s->st.dj[k]);
        const double E = bond_modulus(g, s->phase[a], s->phase[b]);
        const double dux = u[2 * b] - u[2 * a], duy = u[2 * b + 1] - u[2 * a + 1];
        const double fx = E * (s->st.kxx[k] * dux + s->st.kxy[k] * duy);
        const double fy = E * (s->st.kxy[k] * dux + s->st.kyy[k] * duy);
        sxx += 0.5 * fx * s->st.ex[k], syy += 0.5 * fy * s->st.ey[k];
      }
    }
  const double cells = (double)g->n * g->n;
  sigma[0] = s->c_scale * sxx / cells, sigma[1] = s->c_scale * syy / cells;
}

static double dot(const double *a, const double *b, long n) {
  double d = 0;
  for (long i = 0; i < n; ++i) d += a[i] * b[i];
  return d;
}

/* One load case: layers at u = (ex x, ey y); preconditioned conjugate gradients for the cell's
 * displacements from the affine start. Returns iterations, or -1. */
static int solve_case(system_t *s, double ex, double ey, double *u, double sigma[2]) {
  const rve_grid *g = &s->g;
  const int N = g->side;
  const long cell = 2L * g->n * g->n;
  for (int J = 0; J < N; ++J)
    for (int I = 0; I < N; ++I) {
      const long a = I + (long)N * J;
      u[2 * a] = ex * (I - g->m + 0.5), u[2 * a + 1] = ey * (J - g->m + 0.5); /* in units of dx */
    }
  double *r = malloc((size_t)cell * sizeof(double)), *z = malloc((size_t)cell * sizeof(double));
  double *p = malloc((size_t)cell * sizeof(double)), *q = malloc((size_t)cell * sizeof(double));
  double *pf = calloc((size_t)N * N * 2, sizeof(double));
  if (!r || !z || !p || !q || !pf) {
    free(r), free(z), free(p), free(q), free(pf);
    return -1;
  }
  /* Reference force: the pull of the layers alone on the cell, |f| of the affine field with the
   * cell held at zero. */
  forces(s, u, r); /* residual of the affine start: r = f(u) = b - A u */
  double ref = 0;
  {
    double *held = calloc((size_t)N * N * 2, sizeof(double));
    if (!held) {
      free(r), free(z), free(p), free(q), free(pf);
      return -1;
    }
    memcpy(held, u, (size_t)N * N * 2 * sizeof(double));
    for (int j = 0; j < g->n; ++j)
      for (int i = 0; i < g->n; ++i) {
        const long a = (i + g->m) + (long)N * (j + g->m);
        held[2 * a] = held[2 * a + 1] = 0;
      }
    forces(s, held, q);
    ref = sqrt(dot(q, q, cell));
    free(held);
  }
  const double tol = 1e-9 * ref;
  const int max_iter = 20000;
  int it = 0;
  double rz = 0;
  for (;; ++it) {
    const double rn = sqrt(dot(r, r, cell));
    if (rn <= tol) break;
    if (it >= max_iter) {
      peri_error("rve: conjugate gradients did not converge in %d iterations (residual %.3g of %.3g)",
                 max_iter, rn, ref);
      free(r), free(z), free(p), free(q), free(pf);
      return -1;
    }
    for (long c = 0; c < cell / 2; ++c) {
      const double *e = &s->Einv[3 * c];
      z[2 * c] = e[0] * r[2 * c] + e[1] * r[2 * c + 1];
      z[2 * c + 1] = e[1] * r[2 * c] + e[2] * r[2 * c + 1];
    }
    const double rz_new = dot(r, z, cell);
    if (it == 0) memcpy(p, z, (size_t)cell * sizeof(double));
    else {
      const double b = rz_new / rz;
      for (long k = 0; k < cell; ++k) p[k] = z[k] + b * p[k];
    }
    rz = rz_new;
    /* q = A p = -f(p) with the layers at zero */
    for (int j = 0; j < g->n; ++j)
      for (int i = 0; i < g->n; ++i) {
        const long a = (i + g->m) + (long)N * (j + g->m), c = i + (long)g->n * j;
        pf[2 * a] = p[2 * c], pf[2 * a + 1] = p[2 * c + 1];
      }
    forces(s, pf, q);
    const double pq = -dot(p, q, cell);
    const double alpha = rz / pq;
    for (int j = 0; j < g->n; ++j)
      for (int i = 0; i < g->n; ++i) {
        const long a = (i + g->m) + (long)N * (j + g->m), c = i + (long)g->n * j;
        u[2 * a] += alpha * p[2 * c], u[2 * a + 1] += alpha * p[2 * c + 1];
      }
    for (long k = 0; k < cell; ++k) r[k] += alpha * q[k]; /* r = f(u): f(u + a p) = f(u) + a f(p) */
  }
  average_stress(s, u, sigma);
  free(r), free(z), free(p), free(q), free(pf);
  return it;
}

int peri_rve_homogenize(const peri_rve_params *p, const peri_rve_geometry *geo, peri_rve_moduli *out) {
  system_t s;
  memset(&s, 0, sizeof s);
  rve_grid *g = &s.g;
  g->n = geo->n, g->m = p->m, g->side = geo->n + 2 * p->m, g->platelet = geo->platelet;
  g->E_m = p->E_matrix, g->E_nf = p->E_filler, g->E_intph = p->kappa * p->E_matrix;
  g->E_agglm = g->E_intph >= g->E_m ? g->E_m : g->E_intph; /* eq. 3.1 */
  /* Lengths in units of dx: xi xi^T/|xi|^3 V scales as dx, c as dx^-3, displacements as dx,
   * so the forces below are in units of E and the stresses come out in Pa. */
  if (stencil_build(&s.st, p->m, 1.0)) {
    stencil_free(&s.st);
    return -1;
  }
  s.c_scale = 9.0 / (PI * (double)p->m * p->m * p->m);
  const int N = g->side;
  const long cells = (long)g->n * g->n;
  s.phase = malloc((size_t)N * N * sizeof(int32_t));
  s.Einv = malloc((size_t)cells * 3 * sizeof(double));
  double *u = malloc((size_t)N * N * 2 * sizeof(double));
  int rc = -1;
  if (!s.phase || !s.Einv || !u) goto done;
  for (int J = 0; J < N; ++J)
    for (int I = 0; I < N; ++I) s.phase[I + (long)N * J] = phase_of(g, I, J);
  for (int j = 0; j < g->n; ++j)
    for (int i = 0; i < g->n; ++i) {
      const int I = i + g->m, J = j + g->m;
      const int32_t pa = s.phase[I + (long)N * J];
      double dxx = 0, dxy = 0, dyy = 0;
      for (int k = 0; k < s.st.count; ++k) {
        const double E = bond_modulus(g, pa, s.phase[(I + s.st.di[k]) + (long)N * (J + s.st.dj[k])]);
        dxx += E * s.st.kxx[k], dxy += E * s.st.kxy[k], dyy += E * s.st.kyy[k];
      }
      dxx *= s.c_scale, dxy *= s.c_scale, dyy *= s.c_scale;
      const double det = dxx * dyy - dxy * dxy;
      double *e = &s.Einv[3 * (i + (long)g->n * j)];
      e[0] = dyy / det, e[1] = -dxy / det, e[2] = dxx / det;
    }
  double sx[2], sy[2];
  const int itx = solve_case(&s, p->strain, 0.0, u, sx); /* eq. 3.3 */
  if (itx < 0) goto done;
  const int ity = solve_case(&s, 0.0, p->strain, u, sy); /* eq. 3.4 */
  if (ity < 0) goto done;
  const double a11 = sx[0] / p->strain, a21 = sx[1] / p->strain; /* eq. 3.6 */
  const double a12 = sy[0] / p->strain, a22 = sy[1] / p->strain; /* eq. 3.7 */
  out->nu21 = a21 / a11, out->E11 = a11 * (1 - out->nu21 * out->nu21); /* eq. 3.8 */
  out->nu12 = a12 / a22, out->E22 = a22 * (1 - out->nu12 * out->nu12); /* eq. 3.9 */
  out->platelets = geo->platelets;
  out->filler_fraction = (double)geo->filler_nodes / (double)cells;
  out->iterations = itx + ity;
  rc = 0;
done:
  free(u), free(s.phase), free(s.Einv);
  stencil_free(&s.st);
  return rc;
}

int peri_rve_monte_carlo(const peri_rve_params *p, int count, peri_rve_moduli *each) {
  int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(| : failed)
  for (int k = 0; k < count; ++k) {
    peri_rve_geometry g;
    if (peri_rve_generate(p, (uint64_t)k, &g) || peri_rve_homogenize(p, &g, &each[k])) failed |= 1;
    peri_rve_geometry_free(&g);
  }
  return failed ? -1 : 0;
}

void peri_rve_mean_std(const double *v, int count, double *mean, double *std) {
  double s = 0;
  for (int k = 0; k < count; ++k) s += v[k];
  *mean = count ? s / count : 0;
  double q = 0;
  for (int k = 0; k < count; ++k) q += (v[k] - *mean) * (v[k] - *mean);
  *std = count > 1 ? sqrt(q / (count - 1)) : 0;
}
