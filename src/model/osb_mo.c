/* Madenci-Oterkus ordinary state-based model `osb_mo` (Ebrahimi 2020 §2.2 eqs. 2.21-2.26,
 * Table 2.1; docs/models.md 3.6), with its own influence function omega = delta/|xi| (eq. 2.22):
 *   theta_i = d_i delta sum_j (s_ij L_ij - eth_i) beta V_j + n eth_i                      (eq. 2.23)
 *   t_ij    = 2 delta [d_i (L_ij/|xi|) (a1 theta_i - a2 dT_i/2) + b_i (s_ij - eth_i)]       (eq. 2.25)
 *   W_i     = a1 theta_i^2 - a2 theta_i dT_i + a3 dT_i^2 + b_i sum_j omega (e - eth_i |xi|)^2 beta V_j
 *   f_i     = sum_j (t_ij + t_ji) M_ij beta V_j                                           (eq. 2.30)
 * with L_ij the cosine between y_j - y_i and x_j - x_i (eq. 2.26) and eth = alpha_T dT. The
 * thermal constants of Table 2.1 (the 2D ones erratum-corrected, MODELS.md 3.5) are a2 dT =
 * 2 n a1 eth and a3 dT^2 = n^2 a1 eth^2, so with the mechanical dilatation theta^m = theta - n eth
 *   a1 theta - a2 dT/2 = a1 theta^m,   W_i = a1 (theta^m_i)^2 + b_i sum_j omega (e - eth_i |xi|)^2 beta V_j.
 * Per node, d_i = n/(delta V^H_i) and b_i = (alpha m)/(2 m_i), with the horizon volume V^H_i =
 * sum_j beta V_j (p->pstate) and the weighted volume m_i = delta sum_j |xi| beta V_j (p->wvol)
 * over the reference family (discretization.weighted_volume: discrete), or the full-horizon
 * integrals (analytic: Table 2.1's d and b). The discrete sums make theta exactly n times the
 * family-average stretch and W exact for a dilatation on any symmetric family. Each end uses
 * its own material (half-bond rule). The force pass reads three numbers per neighbour:
 *   A_i = 2 delta d_i a1 theta^m_i,  B_i = 2 delta b_i,  C_i = B_i eth_i,
 *   t_ij + t_ji = (A_i + A_j) L_ij/|xi| + (B_i + B_j) s_ij - (C_i + C_j).
 * Sublayer plasticity (docs/plasticity.md) enters through the elastic stretch s^e = s - sum_k
 * W_k s^p_k in both the dilatation sum and the b-term (MODELS.md 16.2). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/model.h"
#include "peri/plasticity.h"
#include "bond_kernel.h"
#include "node_blocks.h"
#include "plastic_bonds.h"

/* The full-horizon volume and weighted volume of omega = delta/|xi| (MODELS.md 3.6):
 * 4 pi delta^3/3 and pi delta^5 (3D), pi h delta^2 and 2 pi h delta^4/3 (2D), 2 A delta and
 * A delta^3 (1D). */
static void mo_analytic_volumes(const peri_geometry *g, double *VH, double *m) {
  const double d = g->horizon;
  if (g->dim == 3) *VH = 4.0 * M_PI * d * d * d / 3.0, *m = M_PI * pow(d, 5);
  else if (g->dim == 2) *VH = M_PI * g->thickness * d * d, *m = 2.0 * M_PI * g->thickness * pow(d, 4) / 3.0;
  else *VH = 2.0 * g->cross_section * d, *m = g->cross_section * d * d * d;
}

static int mo_init(peri_sim *s) {
  if (s->disc.family.influence != PERI_INFLUENCE_CONSTANT) {
    peri_error("the osb_mo model has its own influence function delta/|xi| (Ebrahimi 2020 eq. 2.22)");
    return PERI_ERR_INPUT;
  }
  if (peri_plastic_init(s) != PERI_OK) return PERI_ERR_INPUT; /* sublayer plasticity (docs/plasticity.md) */
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double delta = s->disc.geom.horizon;
  for (int m = 0; m < s->mat.n_materials; ++m) {
    peri_material *mat = &s->mat.materials[m];
    peri_mo_constants(&s->disc.geom, mat->K, mat->mu, &mat->n_theta, &mat->K_theta, &mat->alpha_m);
    mat->c_stable = peri_stable_micromodulus(
        &s->disc.geom, peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu));
  }
  p->theta = peri_calloc(p->n, sizeof(double));
  p->pstate = peri_calloc(p->n, sizeof(double)); /* V^H_i */
  p->wvol = peri_calloc(p->n, sizeof(double));   /* m_i */
  p->coef = peri_calloc(3 * (size_t)p->n, sizeof(double));
  if (s->disc.analytic_weighted_volume) {
    double VH, m;
    mo_analytic_volumes(&s->disc.geom, &VH, &m);
    for (int32_t i = 0; i < p->n; ++i) p->pstate[i] = VH, p->wvol[i] = m;
    return PERI_OK;
  }
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double VH = 0.0, m = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double r0 = peri_bond_length(p->x, i, j), bv = peri_bonds_beta(b, r0) * p->volume[j];
      VH += bv, m += r0 * bv;
    }
    p->pstate[i] = VH, p->wvol[i] = delta * m;
  }
  for (int32_t i = 0; i < p->n_owned; ++i)
    if (!(p->pstate[i] > 0.0)) {
      peri_error("node %d at (%g, %g, %g) has no bonds: the osb_mo model needs a family "
                 "(increase the horizon or check the geometry)",
                 i, p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]);
      return PERI_ERR_INPUT;
    }
  return PERI_OK;
}

/* A node's sums: the dilatation sum or the force, whether a bond passes the breaking screen. */
typedef struct mo_sums {
  double sum[3];
  bool candidate;
} mo_sums;

/* Node i's own data, read once per family (A, B, C for pass 2, the bound for pass 1). */
typedef struct mo_centre {
  double x0, x1, x2, u0, u1, u2, eth, bound, A, B, C;
} mo_centre;

static inline mo_centre mo_centre_of(const peri_bond_view *w, int32_t i, bool force, bool thermal) {
  const size_t n = (size_t)w->n;
  const mo_centre c = {w->x0[i], w->x1[i], w->x2[i], w->u0[i], w->u1[i], w->u2[i], thermal ? w->eth[i] : 0.0,
                       force ? 0.0 : w->s0_bound[i], force ? w->coef[i] : 0.0, force ? w->coef[n + (size_t)i] : 0.0,
                       force ? w->coef[2 * n + (size_t)i] : 0.0};
  return c;
}

/* Bond i-j, the one function of both loops below (so a node's bonds give the same numbers
 * whichever loop runs them). Pass 2 (`force`): the factor g of the force density g (y_j - y_i)
 * on i, with y_j - y_i in y0 .. y2. Pass 1: the term (s L - eth_i) beta V_j of the dilatation
 * sum, with in *excess a number positive when the mechanical stretch passes the screening
 * bound (symmetric in i and j). L/|xi| = (x.y)/(|y| |xi|^2); a bond of zero length carries no
 * force. */
static inline __attribute__((always_inline)) double mo_bond(const mo_centre ci_value, const peri_family_eval *fam,
                                                            double xj0, double xj1, double xj2, double uj0,
                                                            double uj1, double uj2, double Aj, double Bj, double Cj,
                                                            double eth_j, double bound_j, double V_j, bool force,
                                                            bool thermal, double *y0, double *y1, double *y2,
                                                            double *excess) {
  const mo_centre *ci = &ci_value;
  const double x0 = xj0 - ci->x0, x1 = xj1 - ci->x1, x2 = xj2 - ci->x2;
  const double d0 = x0 + (uj0 - ci->u0), d1 = x1 + (uj1 - ci->u1), d2 = x2 + (uj2 - ci->u2);
  *y0 = d0, *y1 = d1, *y2 = d2;
  const double r0 = peri_length3(x0, x1, x2), r = peri_length3(d0, d1, d2);
  const double inv_r0 = 1.0 / r0, inv_r = r > 0.0 ? 1.0 / r : 0.0;
  const double cos_r0 = fma(x2, d2, fma(x1, d1, x0 * d0)) * inv_r * (inv_r0 * inv_r0);
  const double bv = peri_eval_beta(fam, r0) * V_j, stretch = (r - r0) * inv_r0;
  if (force) {
    *excess = 0.0;
    const double pair = fma(ci->A + Aj, cos_r0, fma(ci->B + Bj, stretch, -(ci->C + Cj)));
    return pair * bv * inv_r;
  }
  const double st = stretch - (thermal ? 0.5 * (ci->eth + eth_j) : 0.0);
  *excess = st - (peri_min(ci->bound, bound_j) - PERI_S0_SCREEN_MARGIN);
  return fma(r - r0, cos_r0, -ci->eth) * bv; /* s L = (r - |xi|) L/|xi| */
}

#ifdef PERI_BOND_V8
/* mo_bond for eight bonds (bond_kernel.h): the same quantities, the lengths and their
 * reciprocals from reciprocal square roots, no division. Both loops use it, so the node and
 * block paths agree bit for bit. */
typedef struct mo_centre_v8 {
  peri_v8d x0, x1, x2, u0, u1, u2, eth, bound, A, B, C;
} mo_centre_v8;

/* The centre i (one value in every lane) or the eight centres i .. i+7. */
static inline __attribute__((always_inline)) mo_centre_v8 mo_centre_v8_of(const peri_bond_view *w, int32_t i,
                                                                          bool force, bool thermal, bool eight) {
  const size_t n = (size_t)w->n;
  const peri_v8d zero = v8_setzero_pd();
#define MO_CENTRE(P) (eight ? v8_loadu_pd((P) + i) : v8_set1_pd((P)[i]))
  const mo_centre_v8 c = {MO_CENTRE(w->x0), MO_CENTRE(w->x1), MO_CENTRE(w->x2),
                          MO_CENTRE(w->u0), MO_CENTRE(w->u1), MO_CENTRE(w->u2),
                          thermal ? MO_CENTRE(w->eth) : zero, force ? zero : MO_CENTRE(w->s0_bound),
                          force ? MO_CENTRE(w->coef) : zero, force ? MO_CENTRE(w->coef + n) : zero,
                          force ? MO_CENTRE(w->coef + 2 * n) : zero};
#undef MO_CENTRE
  return c;
}

static inline __attribute__((always_inline)) peri_v8d mo_bond_v8(const mo_centre_v8 *ci, const peri_family_eval *fam,
                                                                peri_v8d xj0, peri_v8d xj1, peri_v8d xj2, peri_v8d uj0,
                                                                peri_v8d uj1, peri_v8d uj2, peri_v8d Aj, peri_v8d Bj,
                                                                peri_v8d Cj, peri_v8d eth_j, peri_v8d bound_j,
                                                                peri_v8d V_j, bool force, bool thermal, peri_v8d y[3],
                                                                peri_v8d *excess) {
  const peri_v8d zero = v8_setzero_pd();
  const peri_v8d x0 = v8_sub_pd(xj0, ci->x0), x1 = v8_sub_pd(xj1, ci->x1), x2 = v8_sub_pd(xj2, ci->x2);
  y[0] = v8_add_pd(x0, v8_sub_pd(uj0, ci->u0));
  y[1] = v8_add_pd(x1, v8_sub_pd(uj1, ci->u1));
  y[2] = v8_add_pd(x2, v8_sub_pd(uj2, ci->u2));
  const peri_v8d r0_sq = v8_fmadd_pd(x2, x2, v8_fmadd_pd(x1, x1, v8_mul_pd(x0, x0)));
  const peri_v8d r_sq = v8_fmadd_pd(y[2], y[2], v8_fmadd_pd(y[1], y[1], v8_mul_pd(y[0], y[0])));
  /* a bond of zero length carries no force (its lanes of 1/r and r set to 0) */
  const peri_m8 stretched = v8_cmp_pd_mask(r_sq, zero, _CMP_GT_OQ);
  peri_v8d r0, inv_r0, r, inv_r;
  peri_root_v8(r0_sq, &r0, &inv_r0);
  peri_root_v8(r_sq, &r, &inv_r);
  r = v8_maskz_mov_pd(stretched, r), inv_r = v8_maskz_mov_pd(stretched, inv_r);
  const peri_v8d dot = v8_fmadd_pd(x2, y[2], v8_fmadd_pd(x1, y[1], v8_mul_pd(x0, y[0])));
  const peri_v8d cos_r0 = v8_mul_pd(v8_mul_pd(dot, inv_r), v8_mul_pd(inv_r0, inv_r0));
  const peri_v8d bv = v8_mul_pd(peri_beta_v8(fam, r0), V_j);
  const peri_v8d extension = v8_sub_pd(r, r0), stretch = v8_mul_pd(extension, inv_r0);
  if (force) {
    *excess = zero;
    const peri_v8d pair =
        v8_fmadd_pd(v8_add_pd(ci->A, Aj), cos_r0,
                        v8_fmsub_pd(v8_add_pd(ci->B, Bj), stretch, v8_add_pd(ci->C, Cj)));
    return v8_mul_pd(v8_mul_pd(pair, bv), inv_r);
  }
  const peri_v8d st =
      thermal ? v8_sub_pd(stretch, v8_mul_pd(v8_set1_pd(0.5), v8_add_pd(ci->eth, eth_j))) : stretch;
  *excess = v8_sub_pd(st, v8_sub_pd(v8_min_pd(ci->bound, bound_j), v8_set1_pd(PERI_S0_SCREEN_MARGIN)));
  return v8_mul_pd(v8_fmsub_pd(extension, cos_r0, ci->eth), bv);
}
#endif

/* Node i alone over its intact bonds in family order: the bond values by a vector loop, their
 * sums in order (so a node's result depends on neither threads nor ranks). */
/* Adds a chunk's bond values in family order: the force g (y_j - y_i), or the sum of g. */
static inline __attribute__((always_inline)) void mo_add_chunk(const double *g, const double *v0, const double *v1,
                                                               const double *v2, int count, bool force, double *s0,
                                                               double *s1, double *s2) {
  if (force) {
    for (int a = 0; a < count; ++a) {
      *s0 = fma(g[a], v0[a], *s0);
      *s1 = fma(g[a], v1[a], *s1);
      *s2 = fma(g[a], v2[a], *s2);
    }
  } else {
    for (int a = 0; a < count; ++a) *s0 += g[a];
  }
}

static inline __attribute__((always_inline)) mo_sums mo_node(const peri_bond_view *w, int32_t i, bool force,
                                                             bool thermal) {
  const size_t n = (size_t)w->n;
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict A = w->coef,
                         *restrict B = w->coef + n, *restrict C = w->coef + 2 * n, *restrict eth = w->eth,
                         *restrict bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
  const mo_centre ci = mo_centre_of(w, i, force, thermal);
  const int64_t k0 = w->offset[i], k1 = w->offset[i + 1];
  const bool damaged = memchr(w->broken + k0, 1, (size_t)(k1 - k0)) != NULL;
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, excess = -INFINITY;
  int32_t intact[PERI_INTACT_CHUNK];
  double g[PERI_INTACT_CHUNK], v0[PERI_INTACT_CHUNK], v1[PERI_INTACT_CHUNK], v2[PERI_INTACT_CHUNK];
#ifdef PERI_BOND_V8
  const peri_v8d zero = v8_setzero_pd();
  const mo_centre_v8 cv = mo_centre_v8_of(w, i, force, thermal, false);
  peri_v8d excess_v = v8_set1_pd(-INFINITY);
  for (int64_t k = k0; k < k1;) {
    int count;
    const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &count);
    for (int a = 0; a < count; a += 8) {
      const peri_m8 m = peri_first_lanes(count - a);
      const peri_v8i j = v8_maskz_loadu_epi32(m, nbr + a);
#define MO_GATHER(P) v8_mask_i32gather_pd(m, j, (P))
      peri_v8d y[3], e;
      const peri_v8d gv = mo_bond_v8(&cv, &fam, MO_GATHER(X0), MO_GATHER(X1), MO_GATHER(X2), MO_GATHER(U0),
                                    MO_GATHER(U1), MO_GATHER(U2), force ? MO_GATHER(A) : zero,
                                    force ? MO_GATHER(B) : zero, force ? MO_GATHER(C) : zero,
                                    thermal ? MO_GATHER(eth) : zero, force ? zero : MO_GATHER(bound), MO_GATHER(V),
                                    force, thermal, y, &e);
#undef MO_GATHER
      v8_mask_storeu_pd(g + a, m, gv);
      if (force) {
        v8_mask_storeu_pd(v0 + a, m, y[0]);
        v8_mask_storeu_pd(v1 + a, m, y[1]);
        v8_mask_storeu_pd(v2 + a, m, y[2]);
      } else {
        excess_v = v8_mask_max_pd(excess_v, m, excess_v, e);
      }
    }
    mo_add_chunk(g, v0, v1, v2, count, force, &s0, &s1, &s2);
  }
  (void)ci;
  const mo_sums r8 = {{s0, s1, s2}, v8_reduce_max_pd(excess_v) > 0.0};
  return r8;
#endif
  for (int64_t k = k0; k < k1;) {
    int count;
    const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &count);
#pragma omp simd reduction(max : excess)
    for (int a = 0; a < count; ++a) {
      const int32_t j = nbr[a];
      double e;
      g[a] = mo_bond(ci, &fam, X0[j], X1[j], X2[j], U0[j], U1[j], U2[j], force ? A[j] : 0.0, force ? B[j] : 0.0,
                     force ? C[j] : 0.0, thermal ? eth[j] : 0.0, force ? 0.0 : bound[j], V[j], force, thermal, &v0[a],
                     &v1[a], &v2[a], &e);
      excess = peri_max(excess, e);
    }
    mo_add_chunk(g, v0, v1, v2, count, force, &s0, &s1, &s2);
  }
  const mo_sums r = {{s0, s1, s2}, excess > 0.0};
  return r;
}

/* The block of nodes i0 .. i0+7 (node_blocks.h): lane l is node i0 + l and takes template
 * entry a, neighbour tj[a] + l, when bit l of lanes[a] is set; every read is contiguous. The
 * same sums, in the same order, as mo_node. */
static inline __attribute__((always_inline)) void mo_block(const peri_bond_view *w, int32_t i0,
                                                           const int32_t *restrict tj, const uint8_t *restrict lanes,
                                                           int64_t count, bool force, bool thermal,
                                                           mo_sums out[PERI_BLOCK]) {
  const size_t n = (size_t)w->n;
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict A = w->coef,
                         *restrict B = w->coef + n, *restrict C = w->coef + 2 * n, *restrict eth = w->eth,
                         *restrict bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
#ifdef PERI_BOND_V8
  {
    const peri_v8d zero = v8_setzero_pd();
    const mo_centre_v8 cv = mo_centre_v8_of(w, i0, force, thermal, true);
    peri_v8d s0 = zero, s1 = zero, s2 = zero;
    peri_m8 beyond = 0;
    for (int64_t a = 0; a < count; ++a) {
      const int64_t j = tj[a];
      const peri_m8 on = lanes[a];
      peri_prefetch_next_blocks(w, j, true);
      peri_v8d y[3], e;
      const peri_v8d g = mo_bond_v8(&cv, &fam, v8_loadu_pd(X0 + j), v8_loadu_pd(X1 + j),
                                   v8_loadu_pd(X2 + j), v8_loadu_pd(U0 + j), v8_loadu_pd(U1 + j),
                                   v8_loadu_pd(U2 + j), force ? v8_loadu_pd(A + j) : zero,
                                   force ? v8_loadu_pd(B + j) : zero, force ? v8_loadu_pd(C + j) : zero,
                                   thermal ? v8_loadu_pd(eth + j) : zero,
                                   force ? zero : v8_loadu_pd(bound + j), v8_loadu_pd(V + j), force, thermal,
                                   y, &e);
      /* a lane takes the bond when its bit is set: the node path's sums, in the same order */
      if (force) {
        s0 = v8_mask3_fmadd_pd(g, y[0], s0, on);
        s1 = v8_mask3_fmadd_pd(g, y[1], s1, on);
        s2 = v8_mask3_fmadd_pd(g, y[2], s2, on);
      } else {
        s0 = v8_mask_add_pd(s0, on, s0, g);
        beyond |= v8_mask_cmp_pd_mask(on, e, zero, _CMP_GT_OQ);
      }
    }
    double a0[PERI_BLOCK], a1[PERI_BLOCK], a2[PERI_BLOCK];
    v8_storeu_pd(a0, s0), v8_storeu_pd(a1, s1), v8_storeu_pd(a2, s2);
    for (int l = 0; l < PERI_BLOCK; ++l) {
      const mo_sums r = {{a0[l], a1[l], a2[l]}, (beyond >> l) & 1u};
      out[l] = r;
    }
    return;
  }
#endif
  double c0[PERI_BLOCK], c1[PERI_BLOCK], c2[PERI_BLOCK], cu0[PERI_BLOCK], cu1[PERI_BLOCK], cu2[PERI_BLOCK],
      ceth[PERI_BLOCK], cbound[PERI_BLOCK], cA[PERI_BLOCK], cB[PERI_BLOCK], cC[PERI_BLOCK];
  double s0[PERI_BLOCK], s1[PERI_BLOCK], s2[PERI_BLOCK], beyond[PERI_BLOCK];
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const mo_centre c = mo_centre_of(w, i0 + l, force, thermal);
    c0[l] = c.x0, c1[l] = c.x1, c2[l] = c.x2, cu0[l] = c.u0, cu1[l] = c.u1, cu2[l] = c.u2;
    ceth[l] = c.eth, cbound[l] = c.bound, cA[l] = c.A, cB[l] = c.B, cC[l] = c.C;
    s0[l] = s1[l] = s2[l] = 0.0, beyond[l] = 0.0;
  }
  for (int64_t a = 0; a < count; ++a) {
    const int64_t j = tj[a];
    /* (a second exit keeps GCC from versioning this loop for outer-loop vectorization, lps.c) */
    if (j < 0) break;
    const double *restrict on_lanes = peri_lane_on[lanes[a]];
    peri_prefetch_next_blocks(w, j, true);
    const double *restrict A0 = X0 + j, *restrict A1 = X1 + j, *restrict A2 = X2 + j, *restrict E0 = U0 + j,
                           *restrict E1 = U1 + j, *restrict E2 = U2 + j, *restrict Vj = V + j;
    const double *restrict Aj = force ? A + j : A, *restrict Bj = force ? B + j : B, *restrict Cj = force ? C + j : C,
                           *restrict Ej = thermal ? eth + j : eth, *restrict Sj = force ? bound : bound + j;
#pragma omp simd
    for (int l = 0; l < PERI_BLOCK; ++l) {
      const mo_centre c = {c0[l], c1[l], c2[l], cu0[l], cu1[l], cu2[l], ceth[l], cbound[l], cA[l], cB[l], cC[l]};
      double y0, y1, y2, e;
      const double g = mo_bond(c, &fam, A0[l], A1[l], A2[l], E0[l], E1[l], E2[l], force ? Aj[l] : 0.0,
                               force ? Bj[l] : 0.0, force ? Cj[l] : 0.0, thermal ? Ej[l] : 0.0,
                               force ? 0.0 : Sj[l], Vj[l], force, thermal, &y0, &y1, &y2, &e);
      /* unconditional updates (a lane without the bond adds exactly 0), as in lps.c */
      const bool on = on_lanes[l] != 0.0;
      const double g_on = on ? g : 0.0;
      if (force) {
        s0[l] = fma(g_on, y0, s0[l]);
        s1[l] = fma(g_on, y1, s1[l]);
        s2[l] = fma(g_on, y2, s2[l]);
      } else {
        s0[l] += g_on;
        beyond[l] += on && e > 0.0 ? 1.0 : 0.0;
      }
    }
  }
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const mo_sums r = {{s0[l], s1[l], s2[l]}, beyond[l] > 0.0};
    out[l] = r;
  }
}

/* The specialisations the passes call (constants fixed inside functions of their own, so
 * that they reach the vector loops through the outlined OpenMP regions). */
typedef struct mo_loops {
  mo_sums (*node)(const peri_bond_view *, int32_t);
  void (*block)(const peri_bond_view *, int32_t, const int32_t *, const uint8_t *, int64_t, mo_sums *);
} mo_loops;
#define MO_VARIANT(NAME, FORCE, THERMAL)                                                                 \
  static mo_sums NAME##_node(const peri_bond_view *w, int32_t i) { return mo_node(w, i, FORCE, THERMAL); } \
  static void NAME##_block(const peri_bond_view *w, int32_t i0, const int32_t *tj, const uint8_t *lanes,   \
                           int64_t count, mo_sums *out) {                                                 \
    mo_block(w, i0, tj, lanes, count, FORCE, THERMAL, out);                                               \
  }                                                                                                       \
  static const mo_loops NAME = {NAME##_node, NAME##_block};
MO_VARIANT(mo_dilatation, false, false)
MO_VARIANT(mo_dilatation_thermal, false, true)
MO_VARIANT(mo_forces, true, false)

/* The sums of every node of item `item` into sums[] (a block at a time where it is one). */
static inline void mo_item_sums(const mo_loops *loops, const peri_bond_view *w, const peri_node_blocks *items,
                                int32_t item, mo_sums sums[PERI_BLOCK]) {
  const int32_t i0 = items->first[item], i1 = items->first[item + 1];
  if (peri_item_is_block(items, item)) {
    const int64_t t0 = items->tpl[item];
    loops->block(w, i0, items->tpl_node + t0, items->tpl_lanes + t0, peri_item_entries(items, item), sums);
  } else {
    for (int32_t i = i0; i < i1; ++i) sums[i - i0] = loops->node(w, i);
  }
}

/* Node i's dilatation and its three coefficients of the force pass from the pass-1 sum. */
static inline void mo_node_coefficients(peri_sim *s, int32_t i, double sum) {
  peri_particles *p = &s->disc.p;
  const size_t n = (size_t)p->n;
  const peri_material *mat = &s->mat.materials[p->material[i]];
  const double eth_i = s->state.thermal_strain ? s->state.thermal_strain[i] : 0.0;
  const double theta_m = mat->n_theta * sum / p->pstate[i]; /* d_i delta sum, d_i = n/(delta V^H_i) */
  p->theta[i] = theta_m + mat->n_theta * eth_i;
  /* A_i = 2 delta d_i a1 theta^m = n K_theta theta^m / V^H (K_theta = 2 a1); B_i = 2 delta b_i */
  p->coef[i] = mat->n_theta * mat->K_theta * theta_m / p->pstate[i];
  p->coef[n + (size_t)i] = s->disc.geom.horizon * mat->alpha_m / p->wvol[i];
  p->coef[2 * n + (size_t)i] = p->coef[n + (size_t)i] * eth_i;
}

static void mo_exchange_coefficients(peri_sim *s) {
  const size_t n = (size_t)s->disc.p.n;
  for (int part = 0; part < 3; ++part) peri_sim_exchange(s, s->disc.p.coef + part * n, 1);
}

/* The elastic force pass: pass 1 breaks the bonds beyond their critical stretch (the exact
 * test of node_blocks.c, on the nodes the screen flags) and sets the coefficients; pass 2
 * sums the forces. */
static long mo_force_pass(peri_sim *s, bool update_s0) {
  (void)update_s0; /* (no LAMMPS-form critical stretch: refused at set-up) */
  peri_update_s0_bound(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  peri_particles *p = &s->disc.p;
  const bool breaking = s->solver.breaking;
  const mo_loops *dilatation = s->state.thermal_strain ? &mo_dilatation_thermal : &mo_dilatation;
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  long n_broken = 0;
#pragma omp parallel reduction(+ : n_broken)
  PERI_FOR_EACH_ITEM(items, item) {
    const int32_t i0 = items->first[item], i1 = items->first[item + 1];
    mo_sums sums[PERI_BLOCK];
    mo_item_sums(dilatation, &w, items, item, sums);
    for (int32_t i = i0; i < i1; ++i) {
      if (breaking && sums[i - i0].candidate) {
        const long broken_here = peri_node_blocks_break_family(s, items, item, i);
        if (broken_here > 0) sums[i - i0] = dilatation->node(&w, i); /* (the same sums as the block's) */
        n_broken += broken_here;
      }
      mo_node_coefficients(s, i, sums[i - i0].sum[0]);
    }
  }
  mo_exchange_coefficients(s);
#pragma omp parallel
  PERI_FOR_EACH_ITEM(items, item) {
    const int32_t i0 = items->first[item], i1 = items->first[item + 1];
    mo_sums sums[PERI_BLOCK];
    mo_item_sums(&mo_forces, &w, items, item, sums);
    for (int32_t i = i0; i < i1; ++i)
      for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = sums[i - i0].sum[d];
  }
  return n_broken;
}

/* Sublayer plasticity: every node through the plastic path of plastic_bonds.c (breaking, the
 * return mapping of each bond, the sums at the elastic stretches). */
static long mo_plastic_force_pass(peri_sim *s, bool update_s0) {
  (void)update_s0;
  peri_particles *p = &s->disc.p;
  peri_update_s0_bound(s);
  peri_plastic_pass pass = peri_plastic_pass_begin(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  long n_broken = 0;
#pragma omp parallel reduction(+ : n_broken)
  {
    peri_plastic_chunk *scratch = peri_plastic_chunk_new();
    PERI_FOR_EACH_ITEM(items, item) {
      for (int32_t i = items->first[item]; i < items->first[item + 1]; ++i) {
        double sum;
        const long broken_here = peri_plastic_mo_node_sums(s, &w, &pass, i, scratch, &sum);
        if (broken_here > 0) peri_node_blocks_clear_broken(items, &s->disc.bonds, item, i);
        n_broken += broken_here;
        mo_node_coefficients(s, i, sum);
      }
    }
    free(scratch);
  }
  mo_exchange_coefficients(s);
#pragma omp parallel
  PERI_FOR_EACH_ITEM(items, item) {
    for (int32_t i = items->first[item]; i < items->first[item + 1]; ++i)
      peri_plastic_mo_node_force(s, &w, &pass, i, &p->f[3 * (size_t)i]);
  }
  peri_plastic_pass_end(&pass);
  return n_broken;
}

static long mo_force(peri_sim *s) {
  return peri_force_in_breaking_order(s, s->state.plastic_stretch ? mo_plastic_force_pass : mo_force_pass);
}

/* W_i = a1 (theta^m_i)^2 + b_i delta sum_j (e^e - eth_i |xi|)^2/|xi| beta V_j over the intact
 * bonds as they are (e^e the elastic extension), theta^m_i from node i's own bonds. Not on the
 * time-step path. */
static void mo_energy(peri_sim *s, double *W) {
  peri_node_blocks *items = peri_node_blocks_refresh(s); /* (the structure-of-arrays copies) */
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const double *eth = s->state.thermal_strain, delta = s->disc.geom.horizon;
  const bool plastic = s->state.plastic_stretch != NULL;
  const peri_family_eval fam = w.fam;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    const double eth_i = eth ? eth[i] : 0.0;
    const double xi0 = w.x0[i], xi1 = w.x1[i], xi2 = w.x2[i], ui0 = w.u0[i], ui1 = w.u1[i], ui2 = w.u2[i];
    double sum = 0.0, q2 = 0.0;
#pragma omp simd reduction(+ : sum, q2)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double x0 = w.x0[j] - xi0, x1 = w.x1[j] - xi1, x2 = w.x2[j] - xi2;
      const double y0 = x0 + (w.u0[j] - ui0), y1 = x1 + (w.u1[j] - ui1), y2 = x2 + (w.u2[j] - ui2);
      const double r0 = peri_length3(x0, x1, x2), r = peri_length3(y0, y1, y2);
      const double cosine = r > 0.0 ? (x0 * y0 + x1 * y1 + x2 * y2) / (r * r0) : 0.0;
      /* the elastic stretch */
      const double se = (r - r0) / r0 - (plastic ? peri_plastic_bond_stretch(s, i, k) : 0.0);
      const double bv = b->broken[k] ? 0.0 : peri_eval_beta(&fam, r0) * w.V[j];
      sum += (se * cosine - eth_i) * bv;
      q2 += (se - eth_i) * (se - eth_i) * r0 * bv; /* omega e^2 with omega = delta/|xi|, over delta */
    }
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double theta_m = mat->n_theta * sum / p->pstate[i];
    W[i] = 0.5 * mat->K_theta * theta_m * theta_m + 0.5 * (mat->alpha_m / p->wvol[i]) * delta * q2;
  }
}

/* (t_ij + t_ji) of bond k of node i at the state of the last force pass (its coefficients,
 * exchanged for ghosts by the force pass). */
static double mo_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_particles *p = &s->disc.p;
  const int32_t j = s->disc.bonds.neighbor[k];
  const size_t n = (size_t)p->n;
  double y[3], x_dot_y = 0.0;
  peri_deformed_bond(p->x, p->u, i, j, y);
  for (int c = 0; c < 3; ++c) x_dot_y += (p->x[3 * j + c] - p->x[3 * i + c]) * y[c];
  const double r0 = peri_bond_length(p->x, i, j);
  const double cos_r0 = r > 0.0 ? x_dot_y / (r * r0 * r0) : 0.0;
  const double se = (r - r0) / r0 - peri_plastic_bond_stretch(s, i, k);
  return (p->coef[i] + p->coef[j]) * cos_r0 + (p->coef[n + (size_t)i] + p->coef[n + (size_t)j]) * se -
         (p->coef[2 * n + (size_t)i] + p->coef[2 * n + (size_t)j]);
}

const peri_model_ops peri_model_osb_mo = {
    .name = "osb_mo",
    .description = "Madenci-Oterkus ordinary state-based model, omega = delta/|xi| (any Poisson ratio)",
    .fixed_poisson = 0,
    .init = mo_init,
    .force = mo_force,
    .energy = mo_energy,
    .pair_force = mo_pair_force,
    .own_force = NULL,
    .tangent = NULL, /* (the implicit solver refuses it at set-up) */
    .tangent_reach = 2,
};
