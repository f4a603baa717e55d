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

/* A radial return only beyond the bound by this margin, and the screen of a node that has
 * never yielded with this one, as in the per-bond rule (deviatoric_plasticity.c). */
#define RETURN_MARGIN 1e-10
#define SCREEN_MARGIN 1e-6
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

/* d(n) of the offset x (|x| = r0) */
static inline void direction_modes(const double x[3], double r0, double d[NC]) {
  const double s = 1.0 / (r0 * r0);
  d[0] = x[0] * x[0] * s, d[1] = x[1] * x[1] * s, d[2] = x[2] * x[2] * s;
  d[3] = 2.0 * x[0] * x[1] * s, d[4] = 2.0 * x[0] * x[2] * s, d[5] = 2.0 * x[1] * x[2] * s;
}

/* The energy weight omega beta V_j |xi|^2 of bond i -> j and its offset. */
static inline double energy_weight(const peri_sim *s, int32_t i, int32_t j, double x[3], double *r0) {
  const peri_particles *p = &s->disc.p;
  for (int c = 0; c < 3; ++c) x[c] = p->x[3 * (size_t)j + c] - p->x[3 * (size_t)i + c];
  *r0 = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  const peri_bonds *b = &s->disc.bonds;
  return peri_bonds_omega(b, *r0) * peri_bonds_beta(b, *r0) * p->volume[j] * *r0 * *r0;
}

/* Node i's moments K, K^-1 and H over its intact bonds; returns how many bonds are intact. */
static int32_t build_moments(const peri_sim *s, peri_tensor_plasticity *t, int32_t i) {
  const peri_bonds *b = &s->disc.bonds;
  double K[PACKED] = {0}, Kinv[PACKED], H[NC] = {0};
  int32_t intact = 0;
  for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
    if (b->broken[k]) continue;
    ++intact;
    double x[3], r0, d[NC];
    const double w = energy_weight(s, i, b->neighbor[k], x, &r0);
    direction_modes(x, r0, d);
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
  if (!t || t->n_owned > 0 || s->disc.p.n_owned == 0) return;
  const peri_particles *p = &s->disc.p;
  t->n_owned = p->n_owned, t->n_local = p->n;
  const size_t n = (size_t)t->n_owned, L = (size_t)t->layers;
  t->state = peri_calloc(L * NC * n, sizeof(double));
  if (t->quasi_static) t->committed = peri_calloc(L * NC * n, sizeof(double));
  t->term = peri_calloc(NC * (size_t)t->n_local, sizeof(double));
  t->moments = peri_malloc(sizeof(double) * PERI_TENSOR_MOMENTS * n);
  t->moment_bonds = peri_malloc(sizeof(int32_t) * n);
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

/* Whether any component of node i's state (or of its committed state) is nonzero. */
static inline bool has_state(const peri_tensor_plasticity *t, int32_t i) {
  const size_t n = (size_t)t->n_owned;
  for (int e = 0; e < t->layers * NC; ++e)
    if (t->state[(size_t)e * n + (size_t)i] != 0.0 || (t->committed && t->committed[(size_t)e * n + (size_t)i] != 0.0))
      return true;
  return false;
}

/* y = a x for the packed symmetric a (stride n, node i) */
static inline void packed_times(const double *a, size_t n, int32_t i, const double x[NC], double y[NC]) {
  for (int r = 0; r < NC; ++r) {
    double v = 0.0;
    for (int c = 0; c < NC; ++c) v = fma(a[(size_t)packed_index(r, c) * n + (size_t)i], x[c], v);
    y[r] = v;
  }
}

/* The return of node i; returns whether its term is nonzero. */
static bool node_return(peri_sim *s, peri_tensor_plasticity *t, int32_t i, const double *N, double elastic) {
  const peri_particles *p = &s->disc.p;
  const size_t n = (size_t)t->n_owned, nl = (size_t)t->n_local;
  const peri_material *mat = &s->mat.materials[p->material[i]];
  const peri_sublayers *sl = mat->sublayers;
  double *term = t->term;
  if (!sl) return false; /* (an elastic material's term stays 0) */
  const double scale = 3.0 * mat->mu / mat->alpha_m * p->wvol[i];
  const bool before = has_state(t, i);
  /* never yielded and below the first yield: the affine part's energy is at most the whole
   * elastic deviatoric energy of pass 1 */
  if (!before && elastic <= scale * sl->yield[0] * sl->yield[0] * (1.0 - SCREEN_MARGIN)) return false;
  if (t->moments[(size_t)MOMENT_KINV * n + (size_t)i] == 0.0) /* singular K: the state kept */
    return before;
  const double theta = p->theta[i];
  double M[NC], D[NC], A[NC] = {0};
  for (int c = 0; c < NC; ++c)
    M[c] = (c < 3 ? 1.0 : 2.0) * N[(size_t)c * n + (size_t)i] - (theta / 3.0) * t->moments[(MOMENT_H + c) * n + (size_t)i];
  packed_times(t->moments + (size_t)MOMENT_KINV * n, n, i, M, D);
  const double *base = t->committed ? t->committed : t->state;
  bool plastic = false;
  for (int l = 0; l < sl->n; ++l) {
    double delta[NC], Kd[NC], S = 0.0, P[NC];
    for (int c = 0; c < NC; ++c) delta[c] = D[c] - base[(size_t)(l * NC + c) * n + (size_t)i];
    packed_times(t->moments + (size_t)MOMENT_K * n, n, i, delta, Kd);
    for (int c = 0; c < NC; ++c) S = fma(delta[c], Kd[c], S);
    const double bound = scale * sl->yield[l] * sl->yield[l];
    const double factor = S > bound * (1.0 + RETURN_MARGIN) ? sqrt(bound / S) : 1.0;
    for (int c = 0; c < NC; ++c) {
      const double old = base[(size_t)(l * NC + c) * n + (size_t)i];
      P[c] = factor < 1.0 ? D[c] - factor * delta[c] : old;
      t->state[(size_t)(l * NC + c) * n + (size_t)i] = P[c];
      A[c] = fma(sl->weight[l], P[c], A[c]);
      plastic |= P[c] != 0.0;
    }
  }
  const double alpha = p->coef[(size_t)p->n + (size_t)i];
  for (int c = 0; c < NC; ++c) term[(size_t)c * nl + (size_t)i] = alpha * A[c];
  return plastic;
}

void peri_tensor_return(peri_sim *s, const double *N, const double *elastic) {
  peri_tensor_ready(s);
  peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (s->disc.bonds.broken_edits != t->broken_edits || t->n_owned == 0) {
    refresh_moments(s, t);
    t->broken_edits = s->disc.bonds.broken_edits;
  }
  bool any = false;
#pragma omp parallel for schedule(dynamic, 64) reduction(|| : any)
  for (int32_t i = 0; i < t->n_owned; ++i) any = node_return(s, t, i, N, elastic[i]) || any;
  const size_t nl = (size_t)t->n_local;
  for (int c = 0; c < NC; ++c) peri_sim_exchange(s, t->term + (size_t)c * nl, 1); /* the ghosts' terms */
  for (size_t g = (size_t)t->n_owned; g < nl && !any; ++g)
    for (int c = 0; c < NC; ++c) any |= t->term[(size_t)c * nl + g] != 0.0;
  t->any_plastic = any;
}

double peri_tensor_bond_term(const peri_sim *s, int32_t node, int32_t i, int32_t j) {
  const peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (!t || t->n_owned == 0) return 0.0;
  const peri_particles *p = &s->disc.p;
  double x[3], d[NC];
  for (int c = 0; c < 3; ++c) x[c] = p->x[3 * (size_t)j + c] - p->x[3 * (size_t)i + c];
  direction_modes(x, sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), d);
  double v = 0.0;
  for (int c = 0; c < NC; ++c) v += d[c] * t->term[(size_t)c * (size_t)t->n_local + (size_t)node];
  return v;
}

/* sum_l W_l P_l of node i (0 for an elastic material) */
static void weighted_tensor(const peri_sim *s, const peri_tensor_plasticity *t, int32_t i, double E[NC]) {
  const peri_sublayers *sl = s->mat.materials[s->disc.p.material[i]].sublayers;
  const size_t n = (size_t)t->n_owned;
  for (int c = 0; c < NC; ++c) E[c] = 0.0;
  for (int l = 0; sl && t->n_owned > 0 && l < sl->n; ++l)
    for (int c = 0; c < NC; ++c) E[c] = fma(sl->weight[l], t->state[(size_t)(l * NC + c) * n + (size_t)i], E[c]);
}

/* W_i = K_theta theta_i^2/2 + (alpha_m/m_i)/2 sum_l W_l sum_j omega beta V |xi|^2 (s^d - d .
 * P_l)^2 (the whole deviatoric energy for an elastic material), theta_i from this
 * displacement. Not on the time-step path. */
void peri_tensor_energy(peri_sim *s, double *W) {
  peri_tensor_ready(s);
  const peri_tensor_plasticity *t = s->state.plastic_tensor;
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
#pragma omp parallel for schedule(dynamic, 64)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const peri_sublayers *sl = mat->sublayers;
    const double eth = s->state.thermal_strain ? s->state.thermal_strain[i] : 0.0, m = p->wvol[i];
    double wq = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double x[3], r0, y2 = 0.0;
      const double w = energy_weight(s, i, j, x, &r0);
      for (int c = 0; c < 3; ++c) {
        const double y = x[c] + p->u[3 * (size_t)j + c] - p->u[3 * (size_t)i + c];
        y2 += y * y;
      }
      wq += w / r0 * (sqrt(y2) - r0 - eth * r0);
    }
    const double theta = mat->n_theta * wq / m;
    double S[PERI_MAX_SUBLAYERS] = {0};
    const int L = sl ? sl->n : 1;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      if (b->broken[k]) continue;
      const int32_t j = b->neighbor[k];
      double x[3], r0, y2 = 0.0, d[NC];
      const double w = energy_weight(s, i, j, x, &r0);
      for (int c = 0; c < 3; ++c) {
        const double y = x[c] + p->u[3 * (size_t)j + c] - p->u[3 * (size_t)i + c];
        y2 += y * y;
      }
      const double sd = (sqrt(y2) - r0) / r0 - eth - theta / 3.0;
      direction_modes(x, r0, d);
      for (int l = 0; l < L; ++l) {
        double sp = 0.0;
        for (int c = 0; sl && t->n_owned > 0 && c < NC; ++c)
          sp += d[c] * t->state[(size_t)(l * NC + c) * (size_t)t->n_owned + (size_t)i];
        S[l] += w * (sd - sp) * (sd - sp);
      }
    }
    double deviatoric = 0.0;
    for (int l = 0; l < L; ++l) deviatoric += (sl ? sl->weight[l] : 1.0) * S[l];
    W[i] = 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / m) * deviatoric;
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
      double x[3], r0, d[NC], v = 0.0;
      (void)energy_weight(s, i, b->neighbor[k], x, &r0);
      direction_modes(x, r0, d);
      for (int c = 0; c < NC; ++c) v += d[c] * E[c];
      largest = fmax(largest, fabs(v));
    }
    out[i] = largest;
  }
}

double peri_tensor_bytes_per_node(const peri_sim *s) {
  const peri_tensor_plasticity *t = s->state.plastic_tensor;
  if (!t) return 0.0;
  const bool committed = s->solver.kind == PERI_SOLVER_ADR || s->solver.kind == PERI_SOLVER_DYNAMIC_RELAXATION;
  return 8.0 * ((committed ? 2 : 1) * t->layers * NC + NC + PERI_TENSOR_MOMENTS) + 4.0;
}
