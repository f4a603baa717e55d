/* The tensor yield rule of LPS in 3D (docs/plasticity.md section 10): the deviatoric sublayer
 * rule of section 8 (Besseling's overlay on Mitchell's ordinary state-based plasticity, Mitchell
 * 2011, SAND2011-3166) with each node's plastic deviatoric stretches written through one
 * symmetric tensor per sublayer, s^dp_l,ij = n . P_l,i . n (n = xi/|xi|). The state is then 6
 * numbers per node and sublayer, nothing per bond, and the force pass reads the neighbours'
 * terms as it reads their coefficients D and B.
 *
 * With d(n) = (n0^2, n1^2, n2^2, 2 n0 n1, 2 n0 n2, 2 n1 n2) (n . T . n = d . T) and the
 * energy weights w_ij = omega beta V_j |xi|^2, node i's deviatoric stretches s^d = e/|xi| -
 * eth_i - theta_i/3 have the least-squares tensor D_i = K_i^-1 M_i, K_i = sum w d d^T, M_i =
 * sum w s^d d, and
 *   sum w (s^d - d . P)^2 = |D - P|_K^2 + sum w (s^d - d . D)^2
 * (the residual is orthogonal to every d . T). Sublayer l yields on the first term, the energy
 * of the affine part, against the bound of the per-bond rule, (3 mu / alpha_m) m_i e_yl^2, and
 * returns radially in the K-norm: P_l <- D - sqrt(bound / S_l) (D - P_l). Under a homogeneous
 * deformation s^d = d . D exactly, the residual is 0, and the per-bond rule's state stays d . P
 * for the same P: the two rules are one. Where the family's stretches are not affine (a crack
 * tip) the residual stays elastic here and flows there.
 *
 * M_i comes from pass 1's sums N = sum w' q x x^T / |xi|^2 (w' = omega |xi| beta V, q = e -
 * eth |xi|, as the dilatation's): M = N (with the factor 2 of the shears) - (theta/3) H, H =
 * sum w d. K and H are the intact bonds' (rebuilt for the nodes whose bonds break); K^-1 is
 * stored. The pair force is LPS's with t_ij + t_ji losing omega |xi| (n . A_i . n + n . A_j .
 * n), A_i = alpha_i sum_l W_l P_l (the term). H . D = I . M = sum w s^d = 0 for every node
 * without broken bonds (d . I = 1), and the return keeps H . P = 0, so the plastic part adds
 * nothing to LPS's P_i, as in the per-bond rule. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bonds.h"
#include "peri/error.h"
#include "peri/plasticity.h"
#include "peri/tensor_plasticity.h"
#include "vector8.h"

#define NC PERI_TENSOR_COMPONENTS
/* the entries of a symmetric 6 x 6 matrix packed as its upper triangle, row by row */
#define PACKED 21
static inline int packed_index(int r, int c) {
  if (r > c) {
    const int t = r;
    r = c, c = t;
  }
  return r * NC - r * (r - 1) / 2 + (c - r);
}
/* where the moments of PERI_TENSOR_MOMENTS start */
#define MOMENT_K 0
#define MOMENT_KINV PACKED
#define MOMENT_H (2 * PACKED)

/* A radial return only beyond the bound by this margin, as in the per-bond rule
 * (deviatoric_plasticity.c): a second evaluation at the same displacement changes nothing. */
#define RETURN_MARGIN 1e-10
/* K is taken as singular (a family whose intact bonds do not span the six strain modes) when
 * a pivot of its Cholesky factor falls below this fraction of its largest diagonal entry */
#define SINGULAR_PIVOT 1e-10

bool peri_tensor_rule(const peri_sim *s) {
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (s->mat.materials[m].sublayers && s->mat.materials[m].sublayers->tensor) return true;
  return false;
}

int peri_tensor_init(peri_sim *s) {
  if (!peri_tensor_rule(s) || s->state.plastic_tensor) return PERI_OK;
  peri_tensor_plasticity *t = peri_calloc(1, sizeof *t);
  for (int m = 0; m < s->mat.n_materials; ++m) {
    const peri_sublayers *sl = s->mat.materials[m].sublayers;
    if (sl && sl->n > t->layers) t->layers = sl->n;
  }
  s->state.plastic_tensor = t;
  return PERI_OK;
}

void peri_tensor_free(peri_tensor_plasticity *t) {
  if (!t) return;
  free(t->state), free(t->committed), free(t->term), free(t->moments), free(t->moment_bonds);
  free(t);
}

/* The inverse of the packed symmetric positive definite a by Cholesky; false (inv 0) when a
 * pivot is below SINGULAR_PIVOT of the largest diagonal entry. */
static bool invert_packed(const double *a, double *inv) {
  double L[NC][NC] = {{0}}, largest = 0.0;
  for (int r = 0; r < NC; ++r) largest = fmax(largest, a[packed_index(r, r)]);
  for (int c = 0; c < NC; ++c) {
    double d = a[packed_index(c, c)];
    for (int k = 0; k < c; ++k) d -= L[c][k] * L[c][k];
    if (!(d > SINGULAR_PIVOT * largest)) {
      memset(inv, 0, sizeof(double) * PACKED);
      return false;
    }
    L[c][c] = sqrt(d);
    for (int r = c + 1; r < NC; ++r) {
      double v = a[packed_index(r, c)];
      for (int k = 0; k < c; ++k) v -= L[r][k] * L[c][k];
      L[r][c] = v / L[c][c];
    }
  }
  /* columns of the inverse: solve L L^T x = e_c */
  for (int c = 0; c < NC; ++c) {
    double y[NC], x[NC];
    for (int r = 0; r < NC; ++r) {
      double v = r == c ? 1.0 : 0.0;
      for (int k = 0; k < r; ++k) v -= L[r][k] * y[k];
      y[r] = v / L[r][r];
    }
    for (int r = NC - 1; r >= 0; --r) {
      double v = y[r];
      for (int k = r + 1; k < NC; ++k) v -= L[k][r] * x[k];
      x[r] = v / L[r][r];
    }
    for (int r = 0; r <= c; ++r) inv[packed_index(r, c)] = x[r];
  }
  return true;
}

/* d(n) of bond i -> j's reference direction; returns |xi|. */
static inline double bond_modes(const peri_sim *s, int32_t i, int32_t j, double d[NC]) {
  const double *x = s->disc.p.x;
  const double x0 = x[3 * (size_t)j] - x[3 * (size_t)i], x1 = x[3 * (size_t)j + 1] - x[3 * (size_t)i + 1],
               x2 = x[3 * (size_t)j + 2] - x[3 * (size_t)i + 2];
  const double r0_sq = x0 * x0 + x1 * x1 + x2 * x2, inv = 1.0 / r0_sq;
  d[0] = x0 * x0 * inv, d[1] = x1 * x1 * inv, d[2] = x2 * x2 * inv;
  d[3] = 2.0 * x0 * x1 * inv, d[4] = 2.0 * x0 * x2 * inv, d[5] = 2.0 * x1 * x2 * inv;
  return sqrt(r0_sq);
}

/* Node i's moments K, K^-1 and H over its intact bonds; returns how many bonds are intact. */
static int32_t build_moments(const peri_sim *s, peri_tensor_plasticity *t, int32_t i) {
  const peri_bonds *b = &s->disc.bonds;
  double K[PACKED] = {0}, Kinv[PACKED], H[NC] = {0};
  int32_t intact = 0;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    ++intact;
    double d[NC];
    const int32_t j = b->neighbor[k];
    const double r0 = bond_modes(s, i, j, d);
    /* the energy weight omega beta V_j |xi|^2 */
    const double w = peri_bonds_omega(b, r0) * peri_bonds_beta(b, r0) * s->disc.p.volume[j] * r0 * r0;
    for (int r = 0; r < NC; ++r) {
      H[r] += w * d[r];
      for (int c = r; c < NC; ++c) K[packed_index(r, c)] += w * d[r] * d[c];
    }
  }
  invert_packed(K, Kinv);
  const size_t n = (size_t)t->n_owned;
  for (int e = 0; e < PACKED; ++e) {
    t->moments[(MOMENT_K + e) * n + (size_t)i] = K[e];
    t->moments[(MOMENT_KINV + e) * n + (size_t)i] = Kinv[e];
  }
  for (int c = 0; c < NC; ++c) t->moments[(MOMENT_H + c) * n + (size_t)i] = H[c];
  return intact;
}

void peri_tensor_ready(peri_sim *s) {
  peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (!t || t->term) return; /* (the term is allocated last: ready) */
  const peri_particles *p = &s->disc.p;
  t->n_owned = p->n_owned, t->n_local = p->n;
  /* (a rank without nodes still takes part in the ghosts' exchange: one entry at least) */
  const size_t n = (size_t)(t->n_owned > 0 ? t->n_owned : 1), L = (size_t)t->layers;
  t->state = peri_calloc(L * NC * n, sizeof(double));
  if (t->quasi_static) t->committed = peri_calloc(L * NC * n, sizeof(double));
  t->moments = peri_malloc(sizeof(double) * PERI_TENSOR_MOMENTS * n);
  t->moment_bonds = peri_malloc(sizeof(int32_t) * n);
  t->term = peri_calloc(NC * (size_t)(t->n_local > 0 ? t->n_local : 1), sizeof(double));
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < t->n_owned; ++i) t->moment_bonds[i] = build_moments(s, t, i);
  t->broken_edits = s->disc.bonds.broken_edits;
}

void peri_tensor_commit(peri_sim *s) {
  peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (t && t->committed) memcpy(t->committed, t->state, sizeof(double) * (size_t)t->layers * NC * (size_t)t->n_owned);
}

/* The moments of the nodes whose intact bonds changed (bonds broke since the last check). */
static void refresh_moments(peri_sim *s, peri_tensor_plasticity *t) {
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 64)
  for (int32_t i = 0; i < t->n_owned; ++i) {
    int32_t intact = 0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) intact += !b->broken[k];
    if (intact != t->moment_bonds[i]) t->moment_bonds[i] = build_moments(s, t, i);
  }
}

/* Nodes per chunk of the return: the lanes of its vector loops. */
#define RETURN_CHUNK 8

/* The return of the nodes i0 .. i1-1 (at most RETURN_CHUNK, all of material `mat` with its
 * sublayers sl) in vector loops across the nodes: the least-squares tensor D, then sublayer by
 * sublayer the energy S_l of D - P_l and the radial return beyond the bound, and the term. A
 * node whose K is singular (K^-1 stored as 0) keeps its state. (No screen: a node below its
 * first yield costs a few vector operations here, against its bonds' in the passes.) */
static void chunk_return(peri_sim *s, peri_tensor_plasticity *t, int32_t i0, int32_t i1, const peri_material *mat,
                         const peri_sublayers *sl, const double *restrict N) {
  const peri_particles *p = &s->disc.p;
  const size_t n = (size_t)t->n_owned, nl = (size_t)t->n_local;
  const double *restrict K = t->moments + (size_t)MOMENT_K * n, *restrict Kinv = t->moments + (size_t)MOMENT_KINV * n,
                         *restrict H = t->moments + (size_t)MOMENT_H * n, *restrict theta = p->theta,
                         *restrict wvol = p->wvol, *restrict alpha = p->coef + p->n;
  const double *restrict base = t->committed ? t->committed : t->state;
  double *restrict state = t->state, *restrict term = t->term;
  const double scale0 = 3.0 * mat->mu / mat->alpha_m;
  double D[NC][RETURN_CHUNK], A[NC][RETURN_CHUNK], keep[RETURN_CHUNK];
#pragma omp simd
  for (int32_t i = i0; i < i1; ++i) {
    const int lane = i - i0;
    double M[NC];
    for (int c = 0; c < NC; ++c)
      M[c] = fma(theta[i] * (-1.0 / 3.0), H[(size_t)c * n + (size_t)i], (c < 3 ? 1.0 : 2.0) * N[(size_t)c * n + (size_t)i]);
    for (int r = 0; r < NC; ++r) {
      double v = 0.0;
      for (int c = 0; c < NC; ++c) v = fma(Kinv[(size_t)packed_index(r, c) * n + (size_t)i], M[c], v);
      D[r][lane] = v, A[r][lane] = 0.0;
    }
    keep[lane] = Kinv[(size_t)i] == 0.0 ? 1.0 : 0.0;
  }
  for (int l = 0; l < sl->n; ++l) {
    const double W = sl->weight[l], ey2 = sl->yield[l] * sl->yield[l];
    const double *restrict from = base + (size_t)l * NC * n;
    double *restrict to = state + (size_t)l * NC * n;
#pragma omp simd
    for (int32_t i = i0; i < i1; ++i) {
      const int lane = i - i0;
      double delta[NC], S = 0.0;
      for (int c = 0; c < NC; ++c) delta[c] = D[c][lane] - from[(size_t)c * n + (size_t)i];
      for (int r = 0; r < NC; ++r) {
        double Kd = 0.0;
        for (int c = 0; c < NC; ++c) Kd = fma(K[(size_t)packed_index(r, c) * n + (size_t)i], delta[c], Kd);
        S = fma(delta[r], Kd, S);
      }
      const double bound = (scale0 * wvol[i]) * ey2;
      const bool flows = S > bound * (1.0 + RETURN_MARGIN) && keep[lane] == 0.0;
      const double factor = sqrt(bound / (flows ? S : bound));
      for (int c = 0; c < NC; ++c) {
        const double old = from[(size_t)c * n + (size_t)i];
        const double P = flows ? fma(-factor, delta[c], D[c][lane]) : old;
        to[(size_t)c * n + (size_t)i] = P;
        A[c][lane] = fma(W, P, A[c][lane]);
      }
    }
  }
#pragma omp simd
  for (int32_t i = i0; i < i1; ++i)
    for (int c = 0; c < NC; ++c) term[(size_t)c * nl + (size_t)i] = alpha[i] * A[c][i - i0];
}

#ifdef PERI_BOND_V8
/* chunk_return for eight nodes i0 .. i0+7 of one material, one node a lane: the same
 * operations, so the same numbers. */
static void chunk_return_v8(peri_sim *s, peri_tensor_plasticity *t, int32_t i0, const peri_material *mat,
                            const peri_sublayers *sl, const double *restrict N) {
  const peri_particles *p = &s->disc.p;
  const size_t n = (size_t)t->n_owned, nl = (size_t)t->n_local, i = (size_t)i0;
  const double *restrict K = t->moments + (size_t)MOMENT_K * n, *restrict Kinv = t->moments + (size_t)MOMENT_KINV * n,
                         *restrict H = t->moments + (size_t)MOMENT_H * n;
  const double *restrict base = t->committed ? t->committed : t->state;
  double *restrict state = t->state, *restrict term = t->term;
  const peri_v8d third = v8_mul_pd(v8_loadu_pd(p->theta + i), v8_set1_pd(-1.0 / 3.0));
  peri_v8d M[NC], D[NC], A[NC];
  for (int c = 0; c < NC; ++c) {
    const peri_v8d Nc = v8_loadu_pd(N + (size_t)c * n + i);
    M[c] = v8_fmadd_pd(third, v8_loadu_pd(H + (size_t)c * n + i), c < 3 ? Nc : v8_add_pd(Nc, Nc));
  }
  for (int r = 0; r < NC; ++r) {
    peri_v8d v = v8_setzero_pd();
    for (int c = 0; c < NC; ++c) v = v8_fmadd_pd(v8_loadu_pd(Kinv + (size_t)packed_index(r, c) * n + i), M[c], v);
    D[r] = v, A[r] = v8_setzero_pd();
  }
  const peri_m8 solvable = v8_cmp_pd_mask(v8_loadu_pd(Kinv + i), v8_setzero_pd(), _CMP_NEQ_OQ);
  const peri_v8d scale = v8_mul_pd(v8_set1_pd(3.0 * mat->mu / mat->alpha_m), v8_loadu_pd(p->wvol + i));
  for (int l = 0; l < sl->n; ++l) {
    const double *restrict from = base + (size_t)l * NC * n;
    double *restrict to = state + (size_t)l * NC * n;
    peri_v8d delta[NC], S = v8_setzero_pd();
    for (int c = 0; c < NC; ++c) delta[c] = v8_sub_pd(D[c], v8_loadu_pd(from + (size_t)c * n + i));
    for (int r = 0; r < NC; ++r) {
      peri_v8d Kd = v8_setzero_pd();
      for (int c = 0; c < NC; ++c) Kd = v8_fmadd_pd(v8_loadu_pd(K + (size_t)packed_index(r, c) * n + i), delta[c], Kd);
      S = v8_fmadd_pd(delta[r], Kd, S);
    }
    const peri_v8d bound = v8_mul_pd(scale, v8_set1_pd(sl->yield[l] * sl->yield[l]));
    const peri_m8 flows =
        solvable & v8_cmp_pd_mask(S, v8_mul_pd(bound, v8_set1_pd(1.0 + RETURN_MARGIN)), _CMP_GT_OQ);
    const peri_v8d factor = v8_sqrt_pd(v8_div_pd(bound, v8_mask_mov_pd(bound, flows, S)));
    const peri_v8d W = v8_set1_pd(sl->weight[l]);
    for (int c = 0; c < NC; ++c) {
      const peri_v8d P = v8_mask_mov_pd(v8_loadu_pd(from + (size_t)c * n + i), flows, v8_fnmadd_pd(factor, delta[c], D[c]));
      v8_storeu_pd(to + (size_t)c * n + i, P);
      A[c] = v8_fmadd_pd(W, P, A[c]);
    }
  }
  const peri_v8d alpha = v8_loadu_pd(p->coef + (size_t)p->n + i);
  for (int c = 0; c < NC; ++c) v8_storeu_pd(term + (size_t)c * nl + i, v8_mul_pd(alpha, A[c]));
}
#endif

void peri_tensor_return(peri_sim *s, const double *N, bool bonds_broke) {
  peri_tensor_ready(s);
  peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (bonds_broke || s->disc.bonds.broken_edits != t->broken_edits) {
    refresh_moments(s, t);
    t->broken_edits = s->disc.bonds.broken_edits;
  }
  const peri_particles *p = &s->disc.p;
  const int32_t n_chunks = (t->n_owned + RETURN_CHUNK - 1) / RETURN_CHUNK;
  const size_t nl = (size_t)t->n_local;
  bool any = false;
#pragma omp parallel for schedule(static) reduction(|| : any)
  for (int32_t chunk = 0; chunk < n_chunks; ++chunk) {
    const int32_t i0 = chunk * RETURN_CHUNK, i1 = i0 + RETURN_CHUNK < t->n_owned ? i0 + RETURN_CHUNK : t->n_owned;
    /* the chunk's nodes one material at a time (a run of one material in the common case) */
    for (int32_t a = i0; a < i1;) {
      int32_t b = a + 1;
      while (b < i1 && p->material[b] == p->material[a]) ++b;
      const peri_material *mat = &s->mat.materials[p->material[a]];
#ifdef PERI_BOND_V8
      if (mat->sublayers && b - a == RETURN_CHUNK) chunk_return_v8(s, t, a, mat, mat->sublayers, N);
      else
#endif
      if (mat->sublayers) chunk_return(s, t, a, b, mat, mat->sublayers, N); /* (an elastic one's term stays 0) */
      a = b;
    }
    for (int32_t i = i0; i < i1; ++i)
      for (int c = 0; c < NC; ++c) any = any || t->term[(size_t)c * nl + (size_t)i] != 0.0;
  }
  for (int c = 0; c < NC; ++c) peri_sim_exchange(s, t->term + (size_t)c * nl, 1); /* the ghosts' terms */
  for (size_t g = (size_t)t->n_owned; g < nl && !any; ++g)
    for (int c = 0; c < NC; ++c) any = any || t->term[(size_t)c * nl + g] != 0.0;
  t->any_plastic = any;
}

double peri_tensor_pair_term(const peri_sim *s, int32_t i, int32_t j) {
  const peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (!t || !t->term) return 0.0; /* (before the first force evaluation every term is 0) */
  double d[NC], v = 0.0;
  bond_modes(s, i, j, d);
  const size_t nl = (size_t)t->n_local;
  for (int c = 0; c < NC; ++c) v += d[c] * (t->term[(size_t)c * nl + (size_t)i] + t->term[(size_t)c * nl + (size_t)j]);
  return v;
}

/* sum_l W_l P_l of node i (0 for an elastic material) */
static void weighted_tensor(const peri_sim *s, const peri_tensor_plasticity *t, int32_t i, double E[NC]) {
  const peri_sublayers *sl = s->mat.materials[s->disc.p.material[i]].sublayers;
  const size_t n = (size_t)t->n_owned;
  for (int c = 0; c < NC; ++c) E[c] = 0.0;
  for (int l = 0; sl && t->state && l < sl->n; ++l)
    for (int c = 0; c < NC; ++c) E[c] = fma(sl->weight[l], t->state[(size_t)(l * NC + c) * n + (size_t)i], E[c]);
}

void peri_tensor_energy(peri_sim *s, const double *N, const double *theta, double *W) {
  peri_tensor_ready(s);
  peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (t->n_owned == 0) return;
  refresh_moments(s, t); /* (bonds broken in the loops since the last return) */
  const peri_particles *p = &s->disc.p;
  const size_t n = (size_t)t->n_owned;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < t->n_owned; ++i) {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const peri_sublayers *sl = mat->sublayers;
    if (!sl) continue;
    double M[NC], plastic = 0.0;
    for (int c = 0; c < NC; ++c)
      M[c] = fma(theta[i] * (-1.0 / 3.0), t->moments[(MOMENT_H + c) * n + (size_t)i], (c < 3 ? 1.0 : 2.0) * N[(size_t)c * n + (size_t)i]);
    for (int l = 0; l < sl->n; ++l) {
      double P[NC], quadratic = 0.0, linear = 0.0;
      for (int c = 0; c < NC; ++c) P[c] = t->state[(size_t)(l * NC + c) * n + (size_t)i];
      for (int r = 0; r < NC; ++r) {
        double KP = 0.0;
        for (int c = 0; c < NC; ++c) KP = fma(t->moments[(MOMENT_K + packed_index(r, c)) * n + (size_t)i], P[c], KP);
        quadratic = fma(P[r], KP, quadratic);
        linear = fma(P[r], M[r], linear);
      }
      plastic = fma(sl->weight[l], quadratic - 2.0 * linear, plastic);
    }
    W[i] += 0.5 * (mat->alpha_m / p->wvol[i]) * plastic;
  }
}

void peri_tensor_yield_index(const peri_sim *s, double *psi) {
  const peri_tensor_plasticity *t = s->state.plastic_tensor;
  const size_t n = t ? (size_t)t->n_owned : 0;
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
    bool flowed = false;
    for (int c = 0; n > 0 && c < NC; ++c) flowed |= t->state[(size_t)c * n + (size_t)i] != 0.0;
    psi[i] = flowed ? 1.0 : 0.0;
  }
}

void peri_tensor_plastic_stretch(const peri_sim *s, double *out) {
  const peri_tensor_plasticity *t = s->state.plastic_tensor;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 64)
  for (int32_t i = 0; i < s->disc.p.n_owned; ++i) {
    double E[NC], largest = 0.0;
    weighted_tensor(s, t, i, E);
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      double d[NC], v = 0.0;
      bond_modes(s, i, b->neighbor[k], d);
      for (int c = 0; c < NC; ++c) v += d[c] * E[c];
      largest = fmax(largest, fabs(v));
    }
    out[i] = largest;
  }
}

double *peri_tensor_state_rows(const peri_sim *s) {
  const peri_tensor_plasticity *t = s->state.plastic_tensor;
  const int32_t owned = s->disc.p.n_owned;
  const size_t width = (size_t)t->layers * NC, n = (size_t)t->n_owned;
  double *rows = peri_calloc(width * (size_t)(owned > 0 ? owned : 1), sizeof(double));
  for (int32_t i = 0; i < t->n_owned; ++i)
    for (size_t e = 0; e < width; ++e) rows[(size_t)i * width + e] = t->state[e * n + (size_t)i];
  return rows;
}

void peri_tensor_set_state_rows(peri_sim *s, const double *rows, const int32_t *global_id) {
  peri_tensor_ready(s);
  peri_tensor_plasticity *t = s->state.plastic_tensor;
  const size_t width = (size_t)t->layers * NC, n = (size_t)t->n_owned;
  for (int32_t i = 0; i < t->n_owned; ++i) {
    const double *row = rows + (size_t)(global_id ? global_id[i] : i) * width;
    for (size_t e = 0; e < width; ++e) {
      t->state[e * n + (size_t)i] = row[e];
      if (t->committed) t->committed[e * n + (size_t)i] = row[e]; /* (written at an accepted load step) */
    }
  }
  /* (the terms follow from the state at the next return, before any force pass reads them) */
}

double peri_tensor_bytes_per_node(const peri_sim *s) {
  const peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (!t) return 0.0;
  return 8.0 * ((t->quasi_static ? 2 : 1) * t->layers * NC + NC + PERI_TENSOR_MOMENTS) + 4.0;
}
