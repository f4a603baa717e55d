/* Ordinary state-based linear peridynamic solid (LPS): Silling 2007 in 3D, Le's plane
 * stress and plane strain model in 2D (Le 2014 ch. 2), one discrete algorithm for all
 * dimensions (docs/model_reference.md 3.3):
 *   theta_i = (n_theta/m_i) sum_j w e |xi| W_ij,       e^d = e - theta_i |xi|/3
 *   P_i     = sum_j w e^d |xi| W_ij,                   alpha_i = (alpha m)/m_i
 *   t_ij    = n_theta (K_theta theta_i - alpha_i P_i/3) w |xi|/m_i + alpha_i w e^d_ij
 *   f_i     = sum_j (t_ij + t_ji) M_ij W_ij,           W_ij = chi beta V_j
 * Each end uses its own material's constants (half-bond rule, docs/model_reference.md 8). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/model.h"
#include "peri/tensor_plasticity.h"
#include "bond_kernel.h"
#include "node_blocks.h"
#include "plastic_bonds.h"
#include "surface_correction.h"

static int lps_init(peri_sim *s) {
  if (peri_plastic_init(s) != PERI_OK) return PERI_ERR_INPUT; /* sublayer plasticity (docs/plasticity.md) */
  /* the deviatoric rules' own state (docs/plasticity.md sections 8 and 10) */
  if (peri_tensor_rule(s)) {
    if (peri_tensor_init(s) != PERI_OK) return PERI_ERR_INPUT;
  } else if (peri_deviatoric_rule(s) && peri_deviatoric_init(s) != PERI_OK) {
    return PERI_ERR_INPUT;
  }
  peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  for (int m = 0; m < s->mat.n_materials; ++m) {
    peri_material *mat = &s->mat.materials[m];
    peri_lps_constants(&s->disc.geom, mat->K, mat->mu, &mat->n_theta, &mat->K_theta, &mat->alpha_m);
    mat->c_stable = peri_stable_micromodulus(
        &s->disc.geom, peri_pwave_modulus(&s->disc.geom, mat->E, mat->nu, mat->K, mat->mu));
  }
  p->theta = peri_calloc(p->n, sizeof(double));
  p->pstate = peri_calloc(p->n, sizeof(double));
  p->wvol = peri_calloc(p->n, sizeof(double));
  p->coef = peri_calloc(2 * (size_t)p->n, sizeof(double));
  if (s->disc.analytic_weighted_volume) {
    double m = peri_weighted_volume_analytic(&s->disc.geom, s->disc.family.influence);
    for (int32_t i = 0; i < p->n; ++i) p->wvol[i] = m;
    return peri_surface_factors(s, true);
  }
  /* Discrete weighted volume over the reference family (not updated as bonds break). */
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    double m = 0.0;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k)
    {
      const int32_t j = b->neighbor[k];
      const double r0 = peri_bond_length(p->x, i, j);
      m += peri_bonds_omega(b, r0) * r0 * r0 * peri_bonds_beta(b, r0) * p->volume[j];
    }
    p->wvol[i] = m;
  }
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (!(p->wvol[i] > 0.0)) {
      peri_error("node %d at (%g, %g, %g) has no bonds: the LPS model needs a family "
                 "(increase the horizon or check the geometry)",
                 i, p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]);
      return PERI_ERR_INPUT;
    }
  }
  return peri_surface_factors(s, true); /* (none without discretization.surface_correction) */
}

/* Node i's own data, read once per family; D and B are the force pass's coefficients, the
 * bound only for the breaking screen of the dilatation pass (`screen`). */
typedef struct lps_centre {
  double x0, x1, x2, u0, u1, u2, eth, bound, V, D, B;
} lps_centre;

static inline lps_centre lps_centre_of(const peri_bond_view *w, int32_t i, bool thermal, bool force,
                                       bool screen) {
  const size_t n = (size_t)w->n;
  const lps_centre c = {w->x0[i], w->x1[i], w->x2[i], w->u0[i], w->u1[i], w->u2[i], thermal ? w->eth[i] : 0.0,
                        screen ? w->s0_bound[i] : 0.0, w->V[i], force ? w->coef[i] : 0.0,
                        force ? w->coef[n + (size_t)i] : 0.0};
  return c;
}

/* Pass 1, bond i-j: the weight w = omega |xi| beta V_j of the sums sum w (e - eth_i |xi|) and
 * sum w |xi| (returned in *q and *r0_out), the mechanical stretch when `smin` (else 0) and,
 * in *excess_out, a number positive when the stretch passes the screening bound. Both loops
 * below evaluate every bond through this one function. No division unless the stretch
 * itself is asked for (the LAMMPS-form critical stretch). */
static inline __attribute__((always_inline)) double lps_bond_sums(const lps_centre ci_value,
                                                                  const peri_family_eval *fam, double xj0,
                                                                  double xj1, double xj2, double uj0, double uj1,
                                                                  double uj2, double eth_j, double bound_j,
                                                                  double V_j, bool thermal, peri_influence influence,
                                                                  bool uniform, bool smin, bool two_sided, double *q,
                                                                  double *r0_out, double *stretch_out,
                                                                  double *excess_out) {
  const lps_centre *ci = &ci_value;
  const double x0 = xj0 - ci->x0, x1 = xj1 - ci->x1, x2 = xj2 - ci->x2;
  const double y0 = x0 + (uj0 - ci->u0), y1 = x1 + (uj1 - ci->u1), y2 = x2 + (uj2 - ci->u2);
  const double r0 = peri_length3(x0, x1, x2);
  const double e_total = peri_length3(y0, y1, y2) - r0;
  /* the mechanical extension: the stretch times r0 */
  double e_mech = e_total;
  if (thermal) e_mech -= 0.5 * (ci->eth + eth_j) * r0; /* symmetric in i, j */
  /* two-sided: |e| against the bound (the plastic screen: sublayers yield in compression too) */
  *excess_out = (two_sided ? fabs(e_mech) : e_mech) - (peri_min(ci->bound, bound_j) - PERI_S0_SCREEN_MARGIN) * r0;
  *stretch_out = smin ? e_mech / r0 : 0.0;
  *q = e_total - ci->eth * r0;
  *r0_out = r0;
  /* omega |xi| = 1 for the inverse influence */
  const double omega_r0 = influence == PERI_INFLUENCE_INVERSE ? 1.0 : peri_eval_omega(fam, influence, r0) * r0;
  return omega_r0 * peri_eval_beta(fam, r0) * (uniform ? ci->V : V_j);
}

/* The tensor yield rule (src/model/tensor_plasticity.c): n . A . n of the offset x (1/|x|^2 in
 * inv_r0_sq) for A = (xx, yy, zz, xy, xz, yz). */
static inline __attribute__((always_inline)) double lps_tensor_term(double x0, double x1, double x2,
                                                                     double inv_r0_sq, const double *A) {
  const double sum = fma(x0 * x0, A[0], fma(x1 * x1, A[1], fma(x2 * x2, A[2], 2.0 * fma(x0 * x1, A[3], fma(x0 * x2, A[4], x1 * x2 * A[5])))));
  return sum * inv_r0_sq;
}

/* Pass 2, bond i-j: the factor g of the force density g (y_j - y_i) on i, with t_ij + t_ji =
 * omega (|xi| (D_i + D_j) + e (B_i + B_j)). */
static inline __attribute__((always_inline)) double lps_bond_force(const lps_centre ci_value,
                                                                   const peri_family_eval *fam, double xj0,
                                                                   double xj1, double xj2, double uj0, double uj1,
                                                                   double uj2, double D_j, double B_j, double V_j,
                                                                   peri_influence influence, bool uniform, bool tensor,
                                                                   const double *A, double *y0, double *y1,
                                                                   double *y2) {
  const lps_centre *ci = &ci_value;
  const double x0 = xj0 - ci->x0, x1 = xj1 - ci->x1, x2 = xj2 - ci->x2;
  const double d0 = x0 + (uj0 - ci->u0), d1 = x1 + (uj1 - ci->u1), d2 = x2 + (uj2 - ci->u2);
  *y0 = d0, *y1 = d1, *y2 = d2;
  const double r0 = peri_length3(x0, x1, x2);
  const double r = peri_length3(d0, d1, d2);
  /* the tensor rule: n . (A_i + A_j) . n, A the nodes' plastic terms (A[c] = A_i + A_j) */
  const double T = tensor ? lps_tensor_term(x0, x1, x2, 1.0 / (r0 * r0), A) : 0.0;
  const double t = fma(r0, (ci->D + D_j) - T, (r - r0) * (ci->B + B_j));
  const double bv = peri_eval_beta(fam, r0) * (uniform ? ci->V : V_j);
  /* omega = 1/|xi| for the inverse influence: one division for both */
  const double scale = influence == PERI_INFLUENCE_INVERSE ? t * bv / (r0 * r)
                                                           : peri_eval_omega(fam, influence, r0) * t * bv / r;
  return r > 0.0 ? scale : 0.0;
}

#ifdef PERI_BOND_V8
/* lps_bond_sums and lps_bond_force for eight bonds (bond_kernel.h): the same quantities,
 * lengths from reciprocal square roots, no division. The node and block loops both use
 * them (Gaussian influence, which needs exp, keeps the scalar functions on both). */
typedef struct lps_centre_v8 {
  peri_v8d x0, x1, x2, u0, u1, u2, eth, bound, V, D, B;
} lps_centre_v8;

/* The centre i (one value in every lane) or the eight centres i .. i+7. */
static inline __attribute__((always_inline)) lps_centre_v8 lps_centre_v8_of(const peri_bond_view *w, int32_t i,
                                                                            bool thermal, bool force, bool screen,
                                                                            bool eight) {
  const size_t n = (size_t)w->n;
  const peri_v8d zero = v8_setzero_pd();
#define LPS_CENTRE(P) (eight ? v8_loadu_pd((P) + i) : v8_set1_pd((P)[i]))
  const lps_centre_v8 c = {LPS_CENTRE(w->x0), LPS_CENTRE(w->x1), LPS_CENTRE(w->x2),
                           LPS_CENTRE(w->u0), LPS_CENTRE(w->u1), LPS_CENTRE(w->u2),
                           thermal ? LPS_CENTRE(w->eth) : zero, screen ? LPS_CENTRE(w->s0_bound) : zero,
                           LPS_CENTRE(w->V), force ? LPS_CENTRE(w->coef) : zero,
                           force ? LPS_CENTRE(w->coef + n) : zero};
#undef LPS_CENTRE
  return c;
}

/* the lengths |xi| (r0, 1/r0 in *inv_r0) and |y| (r, 1/r in *inv_r) of eight bonds from the
 * offsets and the relative displacement components (the FMA sums of peri_bond_lengths_v8) */
static inline __attribute__((always_inline)) void lps_lengths_v8(const lps_centre_v8 *ci, const peri_offset_v8 *o,
                                                                 peri_v8d uj0, peri_v8d uj1, peri_v8d uj2,
                                                                 peri_v8d *r0, peri_v8d *inv_r0, peri_v8d *r,
                                                                 peri_v8d *inv_r, peri_v8d y[3]) {
  const peri_v8d uj[3] = {uj0, uj1, uj2}, cu[3] = {ci->u0, ci->u1, ci->u2};
  peri_deformed_lengths_v8(o, uj, cu, true, y, r, inv_r);
  *r0 = o->r0, *inv_r0 = o->inv_r0;
}

/* The offsets of eight bonds from the neighbours' positions. */
static inline __attribute__((always_inline)) peri_offset_v8 lps_offset_v8(const lps_centre_v8 *ci, peri_v8d xj0,
                                                                         peri_v8d xj1, peri_v8d xj2) {
  const peri_v8d xj[3] = {xj0, xj1, xj2}, c[3] = {ci->x0, ci->x1, ci->x2};
  return peri_offset_of_positions_v8(xj, c, true);
}

/* Pass 1 (lps_bond_sums): the weight, with q, |xi|, 1/|xi|, the stretch and the excess. */
static inline __attribute__((always_inline)) peri_v8d lps_bond_sums_v8(const lps_centre_v8 *ci,
                                                                      const peri_family_eval *fam,
                                                                      const peri_offset_v8 *o, peri_v8d uj0,
                                                                      peri_v8d uj1, peri_v8d uj2, peri_v8d eth_j,
                                                                      peri_v8d bound_j, peri_v8d V_j, bool thermal,
                                                                      peri_influence influence, bool uniform, bool smin,
                                                                      bool two_sided, bool unit_beta, bool same_bound,
                                                                      peri_v8d *q,
                                                                      peri_v8d *r0_out, peri_v8d *inv_r0_out,
                                                                      peri_v8d *stretch_out, peri_v8d *excess_out) {
  peri_v8d r0, inv_r0, r, inv_r, y[3];
  lps_lengths_v8(ci, o, uj0, uj1, uj2, &r0, &inv_r0, &r, &inv_r, y);
  const peri_v8d e_total = v8_sub_pd(r, r0);
  peri_v8d e_mech = e_total;
  if (thermal) e_mech = v8_sub_pd(e_mech, v8_mul_pd(v8_mul_pd(v8_set1_pd(0.5), v8_add_pd(ci->eth, eth_j)), r0));
  /* same_bound: every node has the centre's bound (peri_bond_view.s0_uniform), so bound_j is not read */
  const peri_v8d bound = v8_sub_pd(same_bound ? ci->bound : v8_min_pd(ci->bound, bound_j), v8_set1_pd(PERI_S0_SCREEN_MARGIN));
  *excess_out = v8_sub_pd(two_sided ? v8_abs_pd(e_mech) : e_mech, v8_mul_pd(bound, r0));
  *stretch_out = smin ? v8_mul_pd(e_mech, inv_r0) : v8_setzero_pd();
  *q = thermal ? v8_sub_pd(e_total, v8_mul_pd(ci->eth, r0)) : e_total;
  *r0_out = r0, *inv_r0_out = inv_r0;
  /* omega |xi| = 1 for the inverse influence, |xi| for the constant one */
  const peri_v8d omega_r0 = influence == PERI_INFLUENCE_INVERSE ? v8_set1_pd(1.0) : r0;
  return v8_mul_pd(v8_mul_pd(omega_r0, peri_beta_or_one_v8(fam, r0, unit_beta)), uniform ? ci->V : V_j);
}

/* lps_tensor_term for eight bonds (the same operations). */
static inline __attribute__((always_inline)) peri_v8d lps_tensor_term_v8(const peri_offset_v8 *o, const peri_v8d *A) {
  const peri_v8d x0 = o->x[0], x1 = o->x[1], x2 = o->x[2];
  const peri_v8d shear = v8_fmadd_pd(v8_mul_pd(x0, x1), A[3], v8_fmadd_pd(v8_mul_pd(x0, x2), A[4], v8_mul_pd(v8_mul_pd(x1, x2), A[5])));
  const peri_v8d sum = v8_fmadd_pd(v8_mul_pd(x0, x0), A[0],
                                   v8_fmadd_pd(v8_mul_pd(x1, x1), A[1],
                                               v8_fmadd_pd(v8_mul_pd(x2, x2), A[2], v8_mul_pd(v8_set1_pd(2.0), shear))));
  return v8_mul_pd(sum, v8_mul_pd(o->inv_r0, o->inv_r0));
}

/* Pass 2 (lps_bond_force): the factor g of the force density g (y_j - y_i), y in y[3]. */
static inline __attribute__((always_inline)) peri_v8d lps_bond_force_v8(const lps_centre_v8 *ci,
                                                                       const peri_family_eval *fam,
                                                                       const peri_offset_v8 *o, peri_v8d uj0,
                                                                       peri_v8d uj1, peri_v8d uj2, peri_v8d D_j,
                                                                       peri_v8d B_j, peri_v8d V_j,
                                                                       peri_influence influence, bool uniform,
                                                                       bool unit_beta, bool tensor, const peri_v8d *A,
                                                                       peri_v8d y[3]) {
  peri_v8d r0, inv_r0, r, inv_r;
  lps_lengths_v8(ci, o, uj0, uj1, uj2, &r0, &inv_r0, &r, &inv_r, y);
  peri_v8d DD = v8_add_pd(ci->D, D_j);
  if (tensor) DD = v8_sub_pd(DD, lps_tensor_term_v8(o, A));
  const peri_v8d t = v8_fmadd_pd(r0, DD,
                                    v8_mul_pd(v8_sub_pd(r, r0), v8_add_pd(ci->B, B_j)));
  const peri_v8d bv = v8_mul_pd(peri_beta_or_one_v8(fam, r0, unit_beta), uniform ? ci->V : V_j);
  peri_v8d scale = v8_mul_pd(v8_mul_pd(t, bv), inv_r);
  if (influence == PERI_INFLUENCE_INVERSE) scale = v8_mul_pd(scale, inv_r0); /* omega = 1/|xi| */
  return v8_maskz_mov_pd(v8_cmp_pd_mask(r, v8_setzero_pd(), _CMP_GT_OQ), scale);
}

/* Whether a specialization runs on the eight-lane functions. */
#define LPS_V8(influence) ((influence) != PERI_INFLUENCE_GAUSSIAN)
#endif

/* What a loop returns per node: pass 1 the two sums sum w q and sum w |xi| (w = omega |xi|
 * beta V_j, q = e - alpha_T dT_i |xi|), for the energy also sum omega beta V_j q^2 in sum[2],
 * the minimum mechanical stretch and whether a bond is a candidate for breaking; pass 2 the
 * force density in sum[0..2]. */
typedef struct lps_sums {
  double sum[3], smin;
  bool candidate;
  /* the tensor rule's pass 1 (src/model/tensor_plasticity.c): sum w q x_a x_b / |xi|^2 for
   * ab = xx, yy, zz, xy, xz, yz */
  double tensor[6];
} lps_sums;

/* The tensor rule's pass-1 sums of n bonds in family order, each bond's c = w q / |xi|^2 and
 * offset x: nt[ab] += c x_a x_b (the operations of a block's lane). */
static inline void lps_tensor_sums(const double *c, const double *x0, const double *x1, const double *x2, int n,
                                   double nt[6]) {
  for (int a = 0; a < n; ++a) {
    const double c0 = c[a] * x0[a], c1 = c[a] * x1[a], c2 = c[a] * x2[a];
    nt[0] = fma(c0, x0[a], nt[0]), nt[1] = fma(c1, x1[a], nt[1]), nt[2] = fma(c2, x2[a], nt[2]);
    nt[3] = fma(c0, x1[a], nt[3]), nt[4] = fma(c0, x2[a], nt[4]), nt[5] = fma(c1, x2[a], nt[5]);
  }
}

/* Node i alone, pass 1 or 2, over its intact bonds in family order (the bond values by a
 * vector loop, their sums in order). */
static inline __attribute__((always_inline)) lps_sums lps_node(const peri_bond_view *w, int32_t i, bool force,
                                                               bool thermal, peri_influence influence,
                                                               bool uniform, bool track_smin, bool energy,
                                                               bool two_sided, bool deviatoric, bool tensor) {
  const lps_centre ci = lps_centre_of(w, i, thermal, force, !force && !energy);
  const double *restrict Aterm = w->plastic_term;
  double Ai[6] = {0}, nt[6] = {0};
  if (tensor && force)
    for (int c = 0; c < 6; ++c) Ai[c] = Aterm[(size_t)c * (size_t)w->n + (size_t)i];
  const size_t n_nodes = (size_t)w->n;
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict D = w->coef,
                         *restrict B = w->coef + n_nodes, *restrict eth = w->eth, *restrict s0_bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
  const int64_t k0 = w->offset[i], k1 = w->offset[i + 1];
  const bool damaged = memchr(w->broken + k0, 1, (size_t)(k1 - k0)) != NULL;
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, smin = INFINITY, excess = -INFINITY;
  int32_t intact[PERI_INTACT_CHUNK];
  double g[PERI_INTACT_CHUNK], v0[PERI_INTACT_CHUNK], v1[PERI_INTACT_CHUNK], v2[PERI_INTACT_CHUNK];
  /* the tensor rule's pass 1: each bond's w q / |xi|^2 and offset */
  double tc[PERI_INTACT_CHUNK], tx0[PERI_INTACT_CHUNK], tx1[PERI_INTACT_CHUNK], tx2[PERI_INTACT_CHUNK];
#ifdef PERI_BOND_V8
  if (LPS_V8(influence)) {
    const peri_v8d zero = v8_setzero_pd();
    const lps_centre_v8 cv = lps_centre_v8_of(w, i, thermal, force, !force && !energy, false);
    peri_v8d Av[6];
    for (int c = 0; c < 6; ++c) Av[c] = v8_set1_pd(Ai[c]);
    peri_v8d smin_v = v8_set1_pd(INFINITY), excess_v = v8_set1_pd(-INFINITY);
    for (int64_t k = k0; k < k1;) {
      int n;
      const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &n);
      for (int a = 0; a < n; a += 8) {
        const peri_m8 m = peri_first_lanes(n - a);
        const peri_v8i j = v8_maskz_loadu_epi32(m, nbr + a);
#define LPS_GATHER(P) v8_mask_i32gather_pd(m, j, (P))
        const peri_v8d V_j = uniform ? zero : LPS_GATHER(V);
        if (force) {
          peri_v8d y[3];
          const peri_offset_v8 o = lps_offset_v8(&cv, LPS_GATHER(X0), LPS_GATHER(X1), LPS_GATHER(X2));
          peri_v8d A[6];
          for (int c = 0; tensor && c < 6; ++c) A[c] = v8_add_pd(Av[c], LPS_GATHER(Aterm + (size_t)c * n_nodes));
          const peri_v8d gv = lps_bond_force_v8(&cv, &fam, &o,
                                               LPS_GATHER(U0), LPS_GATHER(U1), LPS_GATHER(U2), LPS_GATHER(D),
                                               LPS_GATHER(B), V_j, influence, uniform, false, tensor, A, y);
          v8_mask_storeu_pd(g + a, m, gv);
          v8_mask_storeu_pd(v0 + a, m, y[0]);
          v8_mask_storeu_pd(v1 + a, m, y[1]);
          v8_mask_storeu_pd(v2 + a, m, y[2]);
        } else {
          peri_v8d q, r0, inv_r0, st, e;
          const peri_offset_v8 o = lps_offset_v8(&cv, LPS_GATHER(X0), LPS_GATHER(X1), LPS_GATHER(X2));
          const peri_v8d wt = lps_bond_sums_v8(&cv, &fam, &o,
                                              LPS_GATHER(U0), LPS_GATHER(U1), LPS_GATHER(U2),
                                              thermal ? LPS_GATHER(eth) : zero, energy ? zero : LPS_GATHER(s0_bound),
                                              V_j, thermal, influence, uniform, track_smin, two_sided, false, false, &q, &r0,
                                              &inv_r0, &st, &e);
          v8_mask_storeu_pd(g + a, m, wt);
          v8_mask_storeu_pd(v0 + a, m, q);
          v8_mask_storeu_pd(v1 + a, m, r0);
          if (energy || deviatoric) v8_mask_storeu_pd(v2 + a, m, v8_mul_pd(v8_mul_pd(q, q), inv_r0));
          if (tensor) {
            v8_mask_storeu_pd(tc + a, m, v8_mul_pd(v8_mul_pd(wt, q), v8_mul_pd(inv_r0, inv_r0)));
            v8_mask_storeu_pd(tx0 + a, m, o.x[0]);
            v8_mask_storeu_pd(tx1 + a, m, o.x[1]);
            v8_mask_storeu_pd(tx2 + a, m, o.x[2]);
          }
          if (track_smin) smin_v = v8_mask_min_pd(smin_v, m, smin_v, st);
          excess_v = v8_mask_max_pd(excess_v, m, excess_v, e);
        }
#undef LPS_GATHER
      }
      for (int a = 0; a < n; ++a) {
        s0 = fma(g[a], v0[a], s0);
        s1 = fma(g[a], v1[a], s1);
        if (force || energy || deviatoric) s2 = fma(g[a], v2[a], s2);
      }
      if (tensor && !force) lps_tensor_sums(tc, tx0, tx1, tx2, n, nt);
    }
    lps_sums r = {{s0, s1, s2}, v8_reduce_min_pd(smin_v), v8_reduce_max_pd(excess_v) > 0.0, {0}};
    if (tensor) memcpy(r.tensor, nt, sizeof nt);
    return r;
  }
#endif
  for (int64_t k = k0; k < k1;) {
    int n;
    const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &n);
    if (force) {
#pragma omp simd
      for (int a = 0; a < n; ++a) {
        const int32_t j = nbr[a];
        double A[6];
        for (int c = 0; c < 6; ++c) A[c] = tensor ? Ai[c] + Aterm[(size_t)c * n_nodes + (size_t)j] : 0.0;
        g[a] = lps_bond_force(ci, &fam, X0[j], X1[j], X2[j], U0[j], U1[j], U2[j], D[j], B[j],
                              uniform ? 0.0 : V[j], influence, uniform, tensor, A, &v0[a], &v1[a], &v2[a]);
      }
      for (int a = 0; a < n; ++a) {
        s0 = fma(g[a], v0[a], s0);
        s1 = fma(g[a], v1[a], s1);
        s2 = fma(g[a], v2[a], s2);
      }
    } else {
#pragma omp simd reduction(min : smin) reduction(max : excess)
      for (int a = 0; a < n; ++a) {
        const int32_t j = nbr[a];
        double s, e;
        g[a] = lps_bond_sums(ci, &fam, X0[j], X1[j], X2[j], U0[j], U1[j], U2[j], thermal ? eth[j] : 0.0,
                             energy ? 0.0 : s0_bound[j], uniform ? 0.0 : V[j], thermal, influence, uniform,
                             track_smin, two_sided, &v0[a], &v1[a], &s, &e);
        if (energy || deviatoric) v2[a] = v0[a] * v0[a] / v1[a];
        if (tensor) {
          tx0[a] = X0[j] - ci.x0, tx1[a] = X1[j] - ci.x1, tx2[a] = X2[j] - ci.x2;
          tc[a] = g[a] * v0[a] / (v1[a] * v1[a]);
        }
        if (track_smin) smin = peri_min(smin, s);
        excess = peri_max(excess, e);
      }
      for (int a = 0; a < n; ++a) {
        s0 = fma(g[a], v0[a], s0);
        s1 = fma(g[a], v1[a], s1);
        if (energy || deviatoric) s2 = fma(g[a], v2[a], s2);
      }
      if (tensor) lps_tensor_sums(tc, tx0, tx1, tx2, n, nt);
    }
  }
  lps_sums r = {{s0, s1, s2}, smin, excess > 0.0, {0}};
  if (tensor) memcpy(r.tensor, nt, sizeof nt);
  return r;
}

#ifdef PERI_BOND_V8
/* lps_block's eight-lane loop; unit_beta: the family has no partial volumes (bond_kernel.h). */
static inline __attribute__((always_inline)) void lps_block_v8(const peri_bond_view *w, int32_t i0,
                                                               const int32_t *restrict tj,
                                                               const uint8_t *restrict lanes, int64_t count,
                                                               bool force, bool thermal, peri_influence influence,
                                                               bool uniform, bool track_smin, bool energy,
                                                               bool two_sided, bool deviatoric, bool tensor,
                                                               lps_sums out[PERI_BLOCK], peri_break_marks *marks,
                                                               bool unit_beta, bool same_bound,
                                                               const uint16_t *restrict table, bool from_table) {
  const size_t n_nodes = (size_t)w->n;
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict D = w->coef,
                         *restrict B = w->coef + n_nodes, *restrict eth = w->eth, *restrict s0_bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
  const peri_v8d zero = v8_setzero_pd();
  const lps_centre_v8 cv = lps_centre_v8_of(w, i0, thermal, force, !force && !energy, true);
  peri_v8d s0 = zero, s1 = zero, s2 = zero, smin = v8_set1_pd(INFINITY);
  peri_m8 beyond = 0;
  /* the tensor rule: pass 1's sums w q x_a x_b / |xi|^2; the force pass's centre terms A_i */
  const double *restrict Aterm = w->plastic_term;
  peri_v8d nt[6], Ai[6];
  for (int c = 0; c < 6; ++c) {
    nt[c] = zero;
    Ai[c] = tensor && force ? v8_loadu_pd(Aterm + (size_t)c * n_nodes + (size_t)i0) : zero;
  }
  /* every entry one offset for all lanes (a lattice, node_blocks.h): the offsets and their
   * lengths from the table, the positions not read (from_table: table is not NULL, a constant
   * of each copy of the loop) */
  for (int64_t a = 0; a < count; ++a) {
    const int64_t j = tj[a];
    const peri_m8 on = lanes[a];
    peri_prefetch_next_blocks(w, j, !from_table);
    const peri_v8d V_j = uniform ? zero : v8_loadu_pd(V + j);
    const peri_offset_v8 o = from_table ? peri_offset_of_table_v8(w->geom + (size_t)table[a] * PERI_GEOM_STRIDE, true)
                                   : lps_offset_v8(&cv, v8_loadu_pd(X0 + j), v8_loadu_pd(X1 + j), v8_loadu_pd(X2 + j));
    if (force) {
      peri_v8d y[3], A[6];
      for (int c = 0; tensor && c < 6; ++c) A[c] = v8_add_pd(Ai[c], v8_loadu_pd(Aterm + (size_t)c * n_nodes + j));
      const peri_v8d g = lps_bond_force_v8(&cv, &fam, &o, v8_loadu_pd(U0 + j), v8_loadu_pd(U1 + j),
                                          v8_loadu_pd(U2 + j), v8_loadu_pd(D + j), v8_loadu_pd(B + j),
                                          V_j, influence, uniform, unit_beta, tensor, A, y);
      /* a lane takes the bond when its bit is set: the node path's sums, in the same order */
      s0 = v8_mask3_fmadd_pd(g, y[0], s0, on);
      s1 = v8_mask3_fmadd_pd(g, y[1], s1, on);
      s2 = v8_mask3_fmadd_pd(g, y[2], s2, on);
    } else {
      peri_v8d q, r0, inv_r0, st, e;
      const peri_v8d wt = lps_bond_sums_v8(
          &cv, &fam, &o, v8_loadu_pd(U0 + j), v8_loadu_pd(U1 + j), v8_loadu_pd(U2 + j),
          thermal ? v8_loadu_pd(eth + j) : zero, energy || same_bound ? zero : v8_loadu_pd(s0_bound + j), V_j,
          thermal, influence, uniform, track_smin, two_sided, unit_beta, same_bound, &q, &r0, &inv_r0, &st, &e);
      s0 = v8_mask3_fmadd_pd(wt, q, s0, on);
      s1 = v8_mask3_fmadd_pd(wt, r0, s1, on);
      if (energy || deviatoric) s2 = v8_mask3_fmadd_pd(wt, v8_mul_pd(v8_mul_pd(q, q), inv_r0), s2, on);
      if (tensor) { /* (lps_tensor_sums's operations lane by lane) */
        const peri_v8d c = v8_mul_pd(v8_mul_pd(wt, q), v8_mul_pd(inv_r0, inv_r0));
        const peri_v8d c0 = v8_mul_pd(c, o.x[0]), c1 = v8_mul_pd(c, o.x[1]), c2 = v8_mul_pd(c, o.x[2]);
        nt[0] = v8_mask3_fmadd_pd(c0, o.x[0], nt[0], on), nt[1] = v8_mask3_fmadd_pd(c1, o.x[1], nt[1], on);
        nt[2] = v8_mask3_fmadd_pd(c2, o.x[2], nt[2], on), nt[3] = v8_mask3_fmadd_pd(c0, o.x[1], nt[3], on);
        nt[4] = v8_mask3_fmadd_pd(c0, o.x[2], nt[4], on), nt[5] = v8_mask3_fmadd_pd(c1, o.x[2], nt[5], on);
      }
      if (track_smin) smin = v8_mask_min_pd(smin, on, smin, st);
      const peri_m8 over = v8_mask_cmp_pd_mask(on, e, zero, _CMP_GT_OQ); /* beyond the screening bound */
      beyond |= over;
      if (marks) peri_mark_entry(marks, a, over);
    }
  }
  double a0[PERI_BLOCK], a1[PERI_BLOCK], a2[PERI_BLOCK], am[PERI_BLOCK], at[6][PERI_BLOCK];
  v8_storeu_pd(a0, s0), v8_storeu_pd(a1, s1), v8_storeu_pd(a2, s2), v8_storeu_pd(am, smin);
  for (int c = 0; tensor && c < 6; ++c) v8_storeu_pd(at[c], nt[c]);
  for (int l = 0; l < PERI_BLOCK; ++l) {
    lps_sums r = {{a0[l], a1[l], a2[l]}, am[l], (beyond >> l) & 1u, {0}};
    for (int c = 0; tensor && c < 6; ++c) r.tensor[c] = at[c][l];
    out[l] = r;
  }
}
#endif

/* The block of nodes i0 .. i0+7 (node_blocks.h), intact, pass 1 or 2: lane l is node i0 + l
 * and takes template entry a, neighbour tj[a] + l, when bit l of lanes[a] is set; every read
 * is contiguous. Same sums as lps_node. */
static inline __attribute__((always_inline)) void lps_block(const peri_bond_view *w, int32_t i0,
                                                            const int32_t *restrict tj,
                                                            const uint8_t *restrict lanes, int64_t count,
                                                            bool force, bool thermal, peri_influence influence,
                                                            bool uniform, bool track_smin, bool energy,
                                                            bool two_sided, bool deviatoric, bool tensor,
                                                            lps_sums out[PERI_BLOCK], peri_break_marks *marks) {
  const size_t n_nodes = (size_t)w->n;
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict D = w->coef,
                         *restrict B = w->coef + n_nodes, *restrict eth = w->eth, *restrict s0_bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
#ifdef PERI_BOND_V8
  if (LPS_V8(influence)) {
    /* (copies of the loop for families without partial volumes, for pass 1 of bodies with one
     * critical stretch: its bound is the centre's, not read per neighbour, and for each source
     * of the offsets, a lattice's table or the positions: chosen per entry, the source stayed a
     * branch inside the loop, 1.2 times its time on an AMD EPYC) */
    const bool unit_beta = peri_family_unit_beta(&fam), same_bound = !force && !energy && w->s0_uniform;
    const uint16_t *table = peri_block_offsets(w, tj, count);
#define LPS_BLOCK_V8(UNIT_BETA, SAME_BOUND, FROM_TABLE)                                                          \
  lps_block_v8(w, i0, tj, lanes, count, force, thermal, influence, uniform, track_smin, energy, two_sided,        \
               deviatoric, tensor, out, marks, UNIT_BETA, SAME_BOUND, table, FROM_TABLE)
#define LPS_BLOCK_V8_SOURCES(UNIT_BETA, SAME_BOUND)                                                              \
  (table ? LPS_BLOCK_V8(UNIT_BETA, SAME_BOUND, true) : LPS_BLOCK_V8(UNIT_BETA, SAME_BOUND, false))
    if (unit_beta && same_bound) LPS_BLOCK_V8_SOURCES(true, true);
    else if (unit_beta) LPS_BLOCK_V8_SOURCES(true, false);
    else if (same_bound) LPS_BLOCK_V8_SOURCES(false, true);
    else LPS_BLOCK_V8_SOURCES(false, false);
#undef LPS_BLOCK_V8_SOURCES
#undef LPS_BLOCK_V8
    return;
  }
#endif
  if (tensor) { /* (the tensor rule without the eight-lane functions: node by node, the same sums) */
    for (int l = 0; l < PERI_BLOCK; ++l)
      out[l] = lps_node(w, i0 + l, force, thermal, influence, uniform, track_smin, energy, two_sided, deviatoric, true);
    return;
  }
  /* the eight centres as arrays (one vector each), s0 .. beyond the lanes' running sums */
  double c0[PERI_BLOCK], c1[PERI_BLOCK], c2[PERI_BLOCK], cu0[PERI_BLOCK], cu1[PERI_BLOCK], cu2[PERI_BLOCK],
      ceth[PERI_BLOCK], cbound[PERI_BLOCK], cV[PERI_BLOCK], cD[PERI_BLOCK], cB[PERI_BLOCK];
  double s0[PERI_BLOCK], s1[PERI_BLOCK], s2[PERI_BLOCK], smin[PERI_BLOCK], beyond[PERI_BLOCK],
      stretch_on[PERI_BLOCK];
  if (marks) marks->n = PERI_BREAK_MARKS + 1; /* (not kept here: the candidates' families are tested) */
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const lps_centre c = lps_centre_of(w, i0 + l, thermal, force, !force && !energy);
    c0[l] = c.x0, c1[l] = c.x1, c2[l] = c.x2, cu0[l] = c.u0, cu1[l] = c.u1, cu2[l] = c.u2;
    ceth[l] = c.eth, cbound[l] = c.bound, cV[l] = c.V, cD[l] = c.D, cB[l] = c.B;
    s0[l] = s1[l] = s2[l] = 0.0, smin[l] = INFINITY, beyond[l] = 0.0;
  }
  for (int64_t a = 0; a < count; ++a) {
    const int64_t j = tj[a];
    /* (a second exit keeps GCC from versioning this loop for outer-loop vectorization, which
     * would leave the lane loop below without if-conversion) */
    if (j < 0) break;
    const double *restrict on_lanes = peri_lane_on[lanes[a]];
    peri_prefetch_next_blocks(w, j, true);
    const double *restrict A0 = X0 + j, *restrict A1 = X1 + j, *restrict A2 = X2 + j, *restrict E0 = U0 + j,
                           *restrict E1 = U1 + j, *restrict E2 = U2 + j, *restrict Vj = V + j;
    if (force) {
      const double *restrict Dj = D + j, *restrict Bj = B + j;
#pragma omp simd
      for (int l = 0; l < PERI_BLOCK; ++l) {
        const lps_centre c = {c0[l], c1[l], c2[l], cu0[l], cu1[l], cu2[l], 0.0, 0.0, cV[l], cD[l], cB[l]};
        double y0, y1, y2;
        const double g = lps_bond_force(c, &fam, A0[l], A1[l], A2[l], E0[l], E1[l], E2[l], Dj[l], Bj[l],
                                        uniform ? 0.0 : Vj[l], influence, uniform, false, NULL, &y0, &y1, &y2);
        /* (a lane without the bond adds exactly 0, the sums starting at +0: an unconditional
         * update keeps the sums in registers, where a conditional one would store them to
         * memory at every entry and stall on the reload at the next) */
        const double g_on = on_lanes[l] != 0.0 ? g : 0.0;
        s0[l] = fma(g_on, y0, s0[l]);
        s1[l] = fma(g_on, y1, s1[l]);
        s2[l] = fma(g_on, y2, s2[l]);
      }
    } else {
      const double *restrict Ej = thermal ? eth + j : eth, *restrict Sj = energy ? s0_bound : s0_bound + j;
#pragma omp simd
      for (int l = 0; l < PERI_BLOCK; ++l) {
        const lps_centre c = {c0[l], c1[l], c2[l], cu0[l], cu1[l], cu2[l], ceth[l], cbound[l], cV[l], 0.0, 0.0};
        double q, r0, s, e;
        const double wt = lps_bond_sums(c, &fam, A0[l], A1[l], A2[l], E0[l], E1[l], E2[l], thermal ? Ej[l] : 0.0,
                                        energy ? 0.0 : Sj[l], uniform ? 0.0 : Vj[l], thermal, influence, uniform,
                                        track_smin, two_sided, &q, &r0, &s, &e);
        /* unconditional updates, as in the force pass */
        const bool on = on_lanes[l] != 0.0;
        const double wt_on = on ? wt : 0.0;
        s0[l] = fma(wt_on, q, s0[l]);
        s1[l] = fma(wt_on, r0, s1[l]);
        if (energy || deviatoric) s2[l] = fma(wt_on, q * q / r0, s2[l]);
        stretch_on[l] = on ? s : INFINITY;
        beyond[l] += on && e > 0.0 ? 1.0 : 0.0; /* the bonds beyond the screening bound */
      }
      if (track_smin) { /* (in a loop of its own, the minimum too stays in a register) */
#pragma omp simd
        for (int l = 0; l < PERI_BLOCK; ++l) smin[l] = peri_min(smin[l], stretch_on[l]);
      }
    }
  }
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const lps_sums r = {{s0[l], s1[l], s2[l]}, smin[l], beyond[l] > 0.0, {0}};
    out[l] = r;
  }
}

/* One pair of functions per pass and specialization: the OpenMP regions below are outlined
 * before inlining, so the constants must be fixed inside functions of their own to reach the
 * vector loops. */
typedef struct lps_loops {
  lps_sums (*node)(const peri_bond_view *, int32_t);
  void (*block)(const peri_bond_view *, int32_t, const int32_t *, const uint8_t *, int64_t, lps_sums *,
                peri_break_marks *);
} lps_loops;
#define LPS_VARIANT(NAME, FORCE, THERMAL, INFLUENCE, UNIFORM, SMIN, ENERGY, TWO, DEV, TENSOR)              \
  static lps_sums NAME##_node(const peri_bond_view *w, int32_t i) {                                       \
    return lps_node(w, i, FORCE, THERMAL, INFLUENCE, UNIFORM, SMIN, ENERGY, TWO, DEV, TENSOR);             \
  }                                                                                                        \
  static void NAME##_block(const peri_bond_view *w, int32_t i0, const int32_t *tj, const uint8_t *lanes,   \
                           int64_t count, lps_sums *out, peri_break_marks *marks) {                        \
    lps_block(w, i0, tj, lanes, count, FORCE, THERMAL, INFLUENCE, UNIFORM, SMIN, ENERGY, TWO, DEV, TENSOR, \
              out, marks);                                                                                 \
  }                                                                                                        \
  static const lps_loops NAME = {NAME##_node, NAME##_block};
/* Pass 1 by influence function (constant on a grid, constant, inverse, Gaussian), without
 * and with thermal strain; without and with the minimum stretch (the LAMMPS-form critical
 * stretch), and for the energy; "uniform": every node has the same volume, so the loop does
 * not gather it; "two-sided": the plastic screen (lps_plastic_force_pass), |e| against it */
#define LPS_SUMS_VARIANTS(SUFFIX, SMIN, ENERGY, TWO, DEV, TEN)                                                        \
  LPS_VARIANT(lps_sums_uniform##SUFFIX, false, false, PERI_INFLUENCE_CONSTANT, true, SMIN, ENERGY, TWO, DEV, TEN)    \
  LPS_VARIANT(lps_sums_constant##SUFFIX, false, false, PERI_INFLUENCE_CONSTANT, false, SMIN, ENERGY, TWO, DEV, TEN)  \
  LPS_VARIANT(lps_sums_inverse##SUFFIX, false, false, PERI_INFLUENCE_INVERSE, false, SMIN, ENERGY, TWO, DEV, TEN)    \
  LPS_VARIANT(lps_sums_gaussian##SUFFIX, false, false, PERI_INFLUENCE_GAUSSIAN, false, SMIN, ENERGY, TWO, DEV, TEN)  \
  LPS_VARIANT(lps_sums_thermal##SUFFIX, false, true, PERI_INFLUENCE_CONSTANT, false, SMIN, ENERGY, TWO, DEV, TEN)    \
  LPS_VARIANT(lps_sums_inverse_thermal##SUFFIX, false, true, PERI_INFLUENCE_INVERSE, false, SMIN, ENERGY,  \
              TWO, DEV, TEN)                                                                                         \
  LPS_VARIANT(lps_sums_gaussian_thermal##SUFFIX, false, true, PERI_INFLUENCE_GAUSSIAN, false, SMIN, ENERGY, \
              TWO, DEV, TEN)                                                                                         \
  static const lps_loops *const lps_sums_table##SUFFIX[2][4] = {                                         \
      {&lps_sums_uniform##SUFFIX, &lps_sums_constant##SUFFIX, &lps_sums_inverse##SUFFIX,                   \
       &lps_sums_gaussian##SUFFIX},                                                                        \
      {&lps_sums_thermal##SUFFIX, &lps_sums_thermal##SUFFIX, &lps_sums_inverse_thermal##SUFFIX,            \
       &lps_sums_gaussian_thermal##SUFFIX}};
LPS_SUMS_VARIANTS(, false, false, false, false, false)
LPS_SUMS_VARIANTS(_smin, true, false, false, false, false)
LPS_SUMS_VARIANTS(_energy, false, true, false, false, false)
LPS_SUMS_VARIANTS(_plastic, false, false, true, false, false)
LPS_SUMS_VARIANTS(_plastic_smin, true, false, true, false, false)
/* the deviatoric yield rule: pass 1 with the sum of omega beta V q^2 (the elastic deviatoric
 * energy of a node that has never yielded, its screen) */
LPS_SUMS_VARIANTS(_deviatoric, false, false, false, true, false)
LPS_SUMS_VARIANTS(_deviatoric_smin, true, false, false, true, false)
/* the tensor yield rule: pass 1 with the sums of the nodes' tensors (src/model/tensor_plasticity.c) */
LPS_SUMS_VARIANTS(_tensor, false, false, false, false, true)
LPS_SUMS_VARIANTS(_tensor_smin, true, false, false, false, true)
LPS_SUMS_VARIANTS(_tensor_energy, false, true, false, false, true)
LPS_VARIANT(lps_force_uniform, true, false, PERI_INFLUENCE_CONSTANT, true, false, false, false, false, false)
LPS_VARIANT(lps_force_constant, true, false, PERI_INFLUENCE_CONSTANT, false, false, false, false, false, false)
LPS_VARIANT(lps_force_inverse, true, false, PERI_INFLUENCE_INVERSE, false, false, false, false, false, false)
LPS_VARIANT(lps_force_gaussian, true, false, PERI_INFLUENCE_GAUSSIAN, false, false, false, false, false, false)

LPS_VARIANT(lps_force_tensor_uniform, true, false, PERI_INFLUENCE_CONSTANT, true, false, false, false, false, true)
LPS_VARIANT(lps_force_tensor_constant, true, false, PERI_INFLUENCE_CONSTANT, false, false, false, false, false, true)
LPS_VARIANT(lps_force_tensor_inverse, true, false, PERI_INFLUENCE_INVERSE, false, false, false, false, false, true)
LPS_VARIANT(lps_force_tensor_gaussian, true, false, PERI_INFLUENCE_GAUSSIAN, false, false, false, false, false, true)

/* Pass 1's table for the deck's influence function, volumes and thermal strain. */
static const lps_loops *lps_pass1_loops(const peri_sim *s, const peri_node_blocks *items,
                                        const lps_loops *const table[2][4]) {
  const int kind = s->disc.family.influence == PERI_INFLUENCE_INVERSE    ? 2
                   : s->disc.family.influence == PERI_INFLUENCE_GAUSSIAN ? 3
                   : items->uniform_volume                          ? 0
                                                                    : 1;
  return table[s->state.thermal_strain != NULL][kind];
}

/* Runs `loops` over every owned node (a block at a time where the node blocks allow, node
 * by node otherwise), with the breaking test when `breaking` (PERI_BREAK_AND_RECOMPUTE), then
 * the body (the last argument) for each node i with its sums in *r. The items are shared as
 * PERI_FOR_EACH_ITEM shares them: both passes give a thread the same run of nodes, whose rows
 * stay in its core's cache (small chunks dealt out in turn made each core reload the rows the
 * other had just read). */
#define LPS_FOR_EACH_NODE(items, loops, w, breaking, ...)                                                \
  _Pragma("omp parallel reduction(+ : n_broken)")                                                         \
  PERI_FOR_EACH_ITEM(items, item) {                                                                       \
    const int32_t i0 = (items)->first[item], i1 = (items)->first[item + 1];                               \
    lps_sums sums[PERI_BLOCK];                                                                             \
    const bool block = peri_item_is_block(items, item);                                                    \
    const int64_t t0 = (items)->tpl[item], entries = peri_item_entries(items, item);                         \
    peri_break_marks marks;                                                                                \
    marks.n = 0;                                                                                           \
    if (block) {                                                                                           \
      (loops)->block(&(w), i0, (items)->tpl_node + t0, (items)->tpl_lanes + t0, entries, sums,             \
                     (breaking) ? &marks : NULL);                                                          \
    } else {                                                                                               \
      for (int32_t i = i0; i < i1; ++i) sums[i - i0] = (loops)->node(&(w), i);                            \
    }                                                                                                      \
    if (breaking)                                                                                          \
      PERI_BREAK_AND_RECOMPUTE(s, items, item, i0, i1, sums, block, &marks, n_broken,                      \
                               (loops)->block(&(w), i0, (items)->tpl_node + t0, (items)->tpl_lanes + t0,   \
                                              entries, sums, NULL),                                        \
                               sums[i - i0] = (loops)->node(&(w), i));                                     \
    for (int32_t i = i0; i < i1; ++i) {                                                                   \
      lps_sums *r = &sums[i - i0];                                                                         \
      __VA_ARGS__                                                                                          \
    }                                                                                                      \
  }

/* Node i's dilatation theta, P and the two per-node coefficients of the force pass from its
 * pass-1 sums sum w q and sum w |xi|. With
 *   A_i = n_theta (K_theta theta_i - alpha_i P_i/3)/m_i,  B_i = alpha_i = (alpha m)/m_i,
 *   D_i = A_i - B_i (alpha_T dT_i + theta_i/3),
 * the pair force of the header is t_ij + t_ji = omega (|xi| (D_i + D_j) + e (B_i + B_j)), so the
 * force pass reads two numbers per neighbour (D in coef[0 .. n-1], B in coef[n .. 2n-1]). */
typedef struct lps_coefficients {
  double theta, P, D, B;
} lps_coefficients;
/* (the node's material constants, its weighted volume m and thermal strain; w_xx is sum w |xi|,
 * or m for the peer form (docs/models.md 3.5), which takes P as if the family were intact) */
static inline lps_coefficients lps_coefficients_of(double n_theta, double K_theta, double alpha_m, double m,
                                                   double eth_i, double we_x, double w_xx) {
  const double theta = n_theta * we_x / m;
  const double P = we_x - theta * w_xx / 3.0;
  const double alpha = alpha_m / m;
  const lps_coefficients c = {theta, P, n_theta * (K_theta * theta - alpha * P / 3.0) / m - alpha * (eth_i + theta / 3.0),
                              alpha};
  return c;
}
static inline void lps_node_coefficients(peri_sim *s, int32_t i, double we_x, double w_xx) {
  peri_particles *p = &s->disc.p;
  const size_t n = (size_t)p->n;
  const peri_material *mat = &s->mat.materials[p->material[i]];
  const lps_coefficients c =
      lps_coefficients_of(mat->n_theta, mat->K_theta, mat->alpha_m, p->wvol[i],
                          s->state.thermal_strain ? s->state.thermal_strain[i] : 0.0, we_x,
                          mat->peer_force_state ? p->wvol[i] : w_xx);
  p->theta[i] = c.theta;
  p->pstate[i] = c.P;
  p->coef[i] = c.D;
  p->coef[n + (size_t)i] = c.B;
}
/* lps_node_coefficients for the nodes i0 .. i1-1 of a work item, a block's eight in one vector
 * loop: the same operations lane by lane, so the same numbers (node by node, the six dependent
 * scalar divisions took most of the dilatation pass's time outside its bond loops) */
static void lps_item_coefficients(peri_sim *s, int32_t i0, int32_t i1, const lps_sums *sums) {
  if (i1 - i0 != PERI_BLOCK) {
    for (int32_t i = i0; i < i1; ++i) lps_node_coefficients(s, i, sums[i - i0].sum[0], sums[i - i0].sum[1]);
    return;
  }
  peri_particles *p = &s->disc.p;
  const size_t n = (size_t)p->n;
  double n_theta[PERI_BLOCK], K_theta[PERI_BLOCK], alpha_m[PERI_BLOCK], m[PERI_BLOCK], eth[PERI_BLOCK],
      we_x[PERI_BLOCK], w_xx[PERI_BLOCK];
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const int32_t i = i0 + l;
    const peri_material *mat = &s->mat.materials[p->material[i]];
    n_theta[l] = mat->n_theta, K_theta[l] = mat->K_theta, alpha_m[l] = mat->alpha_m;
    m[l] = p->wvol[i], eth[l] = s->state.thermal_strain ? s->state.thermal_strain[i] : 0.0;
    /* (the peer form's choice made here: a loop that mixes bytes and doubles is not vectorized) */
    we_x[l] = sums[l].sum[0], w_xx[l] = mat->peer_force_state ? m[l] : sums[l].sum[1];
  }
  double *restrict theta = p->theta + i0, *restrict P = p->pstate + i0, *restrict D = p->coef + i0,
                   *restrict B = p->coef + n + i0;
#pragma omp simd
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const lps_coefficients c =
        lps_coefficients_of(n_theta[l], K_theta[l], alpha_m[l], m[l], eth[l], we_x[l], w_xx[l]);
    theta[l] = c.theta, P[l] = c.P, D[l] = c.D, B[l] = c.B;
  }
}

/* Pass 1 for every owned node: break bonds beyond their critical stretch, then
 * lps_node_coefficients. */
static long lps_dilatation(peri_sim *s) {
  peri_update_s0_bound(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const bool track_smin = s->mat.s0_node != NULL, breaking = s->solver.breaking;
  const lps_loops *loops = lps_pass1_loops(s, items, track_smin ? lps_sums_table_smin : lps_sums_table);
  peri_particles *p = &s->disc.p;
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  long n_broken = 0;
  LPS_FOR_EACH_NODE(items, loops, w, breaking, {
    if (i == i0) lps_item_coefficients(s, i0, i1, sums); /* (the item's nodes at once) */
    if (track_smin) p->smin[i] = r->smin;
  })
  return n_broken;
}

/* The sums of loops over the nodes i0 .. i1-1 of a work item: its block, or node by node. */
static inline void lps_item_sums(const peri_node_blocks *items, int32_t item, int32_t i0, int32_t i1,
                                 const peri_bond_view *w, const lps_loops *loops, lps_sums sums[PERI_BLOCK]) {
  if (peri_item_is_block(items, item)) {
    const int64_t t0 = items->tpl[item];
    loops->block(w, i0, items->tpl_node + t0, items->tpl_lanes + t0, peri_item_entries(items, item), sums, NULL);
  } else {
    for (int32_t i = i0; i < i1; ++i) sums[i - i0] = loops->node(w, i);
  }
}

/* Pass 2's loops for the deck's influence function and volumes (with the tensor rule's plastic
 * terms when `tensor`). */
static const lps_loops *lps_force_loops(const peri_sim *s, const peri_node_blocks *items, bool tensor) {
  if (tensor)
    return s->disc.family.influence == PERI_INFLUENCE_INVERSE    ? &lps_force_tensor_inverse
           : s->disc.family.influence == PERI_INFLUENCE_GAUSSIAN ? &lps_force_tensor_gaussian
           : items->uniform_volume                                ? &lps_force_tensor_uniform
                                                                  : &lps_force_tensor_constant;
  return s->disc.family.influence == PERI_INFLUENCE_INVERSE    ? &lps_force_inverse
         : s->disc.family.influence == PERI_INFLUENCE_GAUSSIAN ? &lps_force_gaussian
         : items->uniform_volume                                ? &lps_force_uniform
                                                                : &lps_force_constant;
}

/* Pass 2 for every owned node, after pass 1 (the coefficients D and B of every node), with
 * the tensor rule's plastic terms when some node has one (with every term 0 the two loops give
 * the same numbers). */
static void lps_pair_forces(peri_sim *s) {
  peri_particles *p = &s->disc.p;
  const size_t n = (size_t)p->n;
  /* the force pass reads D_j and B_j of ghosts (docs/parallel.md) */
  peri_sim_exchange(s, s->disc.p.coef, 1);
  peri_sim_exchange(s, s->disc.p.coef + n, 1);
  peri_node_blocks *items = s->disc.node_blocks; /* refreshed by the dilatation pass */
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  const lps_loops *loops = lps_force_loops(s, items, s->state.plastic_tensor && s->state.plastic_tensor->any_plastic);
  long n_broken = 0; /* (the force pass breaks nothing) */
  LPS_FOR_EACH_NODE(items, loops, w, false, {
    for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = r->sum[d];
  })
  (void)n_broken;
}

static long lps_force_pass(peri_sim *s, bool update_s0) {
  const long broken = lps_dilatation(s);
  if (s->mat.s0_node && update_s0) peri_update_lammps_s0(s);
  lps_pair_forces(s);
  return broken;
}

/* Sublayer plasticity (docs/plasticity.md section 5). Pass 1 runs the elastic loops with the
 * two-sided plastic screen (the first yield stretch, the critical stretch's bound, the elastic
 * stretch of a critical bond work): a node none of whose bonds passes it and that has never
 * yielded keeps the elastic sums (its plastic stretches are 0 and the return mapping leaves
 * them 0); every other node takes the plastic path (breaking, return mapping, the sums at the
 * elastic extensions). In pass 2 a node that kept the elastic sums has only elastic bonds, so
 * its force is the elastic one whatever its neighbours did (D_j and B_j are read as they are);
 * the nodes of the plastic path sum at their elastic extensions (the bonds they broke are
 * cleared from the block loops' lane masks at once). The choice depends on
 * the node's state only, not on threads or ranks. */
static long lps_plastic_force_pass(peri_sim *s, bool update_s0) {
  peri_particles *p = &s->disc.p;
  const size_t n = (size_t)p->n;
  peri_update_s0_bound(s);
  peri_plastic_pass pass = peri_plastic_pass_begin(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const bool track_smin = s->mat.s0_node != NULL;
  const lps_loops *sums_loops = lps_pass1_loops(s, items, track_smin ? lps_sums_table_plastic_smin : lps_sums_table_plastic);
  const lps_loops *force_loops = lps_force_loops(s, items, false);
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  peri_bond_view screened = w;
  screened.s0_bound = pass.screen, screened.s0_uniform = false;
  const uint8_t *yielded = s->state.plastic_nodes;
  uint8_t *plastic_path = peri_malloc((size_t)(p->n_owned > 0 ? p->n_owned : 1));
  long n_broken = 0;
#pragma omp parallel reduction(+ : n_broken)
  {
    peri_plastic_chunk *scratch = peri_plastic_chunk_new();
    PERI_FOR_EACH_ITEM(items, item) {
      const int32_t i0 = items->first[item], i1 = items->first[item + 1];
      lps_sums sums[PERI_BLOCK];
      const bool all_yielded = peri_plastic_item_yielded(yielded, i0, i1); /* (no screen then) */
      if (!all_yielded) lps_item_sums(items, item, i0, i1, &screened, sums_loops, sums);
      for (int32_t i = i0; i < i1; ++i) {
        lps_sums *r = &sums[i - i0];
        plastic_path[i] = all_yielded || r->candidate || yielded[i];
        if (plastic_path[i]) {
          const long broken_here = peri_plastic_lps_node_sums(s, &w, &pass, i, scratch, r->sum, &r->smin);
          if (broken_here > 0) peri_node_blocks_clear_broken(items, &s->disc.bonds, item, i);
          n_broken += broken_here;
        }
        if (track_smin) p->smin[i] = r->smin;
      }
      lps_item_coefficients(s, i0, i1, sums); /* (the item's nodes at once, from their final sums) */
    }
    free(scratch);
  }
  if (track_smin && update_s0) peri_update_lammps_s0(s);
  peri_sim_exchange(s, p->coef, 1);
  peri_sim_exchange(s, p->coef + n, 1);
#pragma omp parallel
  PERI_FOR_EACH_ITEM(items, item) {
    const int32_t i0 = items->first[item], i1 = items->first[item + 1];
    lps_sums sums[PERI_BLOCK];
    bool all_plastic = true;
    for (int32_t i = i0; i < i1; ++i) all_plastic &= plastic_path[i] != 0;
    if (!all_plastic) lps_item_sums(items, item, i0, i1, &w, force_loops, sums);
    for (int32_t i = i0; i < i1; ++i) {
      double f[3];
      if (plastic_path[i]) peri_plastic_lps_node_force(s, &w, &pass, i, f);
      else f[0] = sums[i - i0].sum[0], f[1] = sums[i - i0].sum[1], f[2] = sums[i - i0].sum[2];
      for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = f[d];
    }
  }
  free(plastic_path);
  peri_plastic_pass_end(&pass);
  return n_broken;
}

/* The deviatoric yield rule (src/model/deviatoric_plasticity.c, docs/plasticity.md section
 * 8): the dilatation stays elastic, so pass 1 runs unchanged (it also sums omega beta V q^2,
 * from which a node that has never yielded knows its elastic deviatoric energy and skips the
 * return unless it passes the first yield); the sublayers then return radially at the nodes'
 * theta, and pass 2 runs the elastic loops for the nodes without a plastic state on either
 * end of a bond and the pair forces with their plastic part for the others (an item whose
 * nodes all have one skips the elastic loops). */
static long lps_deviatoric_force_pass(peri_sim *s, bool update_s0) {
  peri_update_s0_bound(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const bool track_smin = s->mat.s0_node != NULL, breaking = s->solver.breaking;
  const lps_loops *loops =
      lps_pass1_loops(s, items, track_smin ? lps_sums_table_deviatoric_smin : lps_sums_table_deviatoric);
  peri_particles *p = &s->disc.p;
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  /* sum omega beta V (e^d)^2 of the total deviatoric extensions: the screen of the return */
  double *elastic = peri_malloc(sizeof(double) * (size_t)(p->n_owned > 0 ? p->n_owned : 1));
  long n_broken = 0;
  LPS_FOR_EACH_NODE(items, loops, w, breaking, {
    if (i == i0) lps_item_coefficients(s, i0, i1, sums); /* (the item's nodes at once) */
    if (track_smin) p->smin[i] = r->smin;
    const double theta = p->theta[i];
    elastic[i] = r->sum[2] - (2.0 * theta / 3.0) * r->sum[0] + (theta * theta / 9.0) * r->sum[1];
  })
  if (track_smin && update_s0) peri_update_lammps_s0(s);
  uint8_t *near = peri_malloc((size_t)(p->n_owned > 0 ? p->n_owned : 1));
  peri_deviatoric_return(s, elastic, near);
  free(elastic);
  peri_sim_exchange(s, p->coef, 1); /* pass 2 reads D_j and B_j of ghosts */
  peri_sim_exchange(s, p->coef + (size_t)p->n, 1);
  const lps_loops *force_loops = lps_force_loops(s, items, false);
#pragma omp parallel
  PERI_FOR_EACH_ITEM(items, item) {
    const int32_t i0 = items->first[item], i1 = items->first[item + 1];
    lps_sums sums[PERI_BLOCK];
    bool all_near = true;
    for (int32_t i = i0; i < i1; ++i) all_near &= near[i] != 0;
    double block_f[PERI_BLOCK][3];
    /* a block whose nodes all take the plastic force runs it on its template */
    if (all_near && peri_item_is_block(items, item) && peri_deviatoric_block_force(s, &w, items, item, block_f)) {
      for (int32_t i = i0; i < i1; ++i)
        for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = block_f[i - i0][d];
      continue;
    }
    if (!all_near) lps_item_sums(items, item, i0, i1, &w, force_loops, sums);
    for (int32_t i = i0; i < i1; ++i) {
      double f[3];
      if (near[i]) peri_deviatoric_node_force(s, &w, i, f);
      else f[0] = sums[i - i0].sum[0], f[1] = sums[i - i0].sum[1], f[2] = sums[i - i0].sum[2];
      for (int d = 0; d < 3; ++d) p->f[3 * (size_t)i + d] = f[d];
    }
  }
  free(near);
  return n_broken;
}

/* The tensor yield rule (src/model/tensor_plasticity.c, docs/plasticity.md section 10): pass 1
 * with the sums of the nodes' least-squares tensors, the nodes' returns, then pass 2 with the
 * plastic terms of both ends of every bond. */
static long lps_tensor_force_pass(peri_sim *s, bool update_s0) {
  peri_update_s0_bound(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const bool track_smin = s->mat.s0_node != NULL, breaking = s->solver.breaking;
  const lps_loops *loops = lps_pass1_loops(s, items, track_smin ? lps_sums_table_tensor_smin : lps_sums_table_tensor);
  peri_particles *p = &s->disc.p;
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  const size_t owned = (size_t)(p->n_owned > 0 ? p->n_owned : 1), stride = (size_t)p->n_owned;
  double *N = peri_malloc(6 * sizeof(double) * owned);
  long n_broken = 0;
  LPS_FOR_EACH_NODE(items, loops, w, breaking, {
    if (i == i0) lps_item_coefficients(s, i0, i1, sums); /* (the item's nodes at once) */
    if (track_smin) p->smin[i] = r->smin;
    for (int c = 0; c < 6; ++c) N[(size_t)c * stride + (size_t)i] = r->tensor[c];
  })
  if (track_smin && update_s0) peri_update_lammps_s0(s);
  peri_tensor_return(s, N, n_broken > 0);
  free(N);
  lps_pair_forces(s);
  return n_broken;
}

static long lps_force(peri_sim *s) {
  if (s->state.plastic_tensor) return peri_force_in_breaking_order(s, lps_tensor_force_pass);
  if (s->state.plastic_reverse) return peri_force_in_breaking_order(s, lps_deviatoric_force_pass);
  if (s->state.plastic_stretch) return peri_force_in_breaking_order(s, lps_plastic_force_pass);
  return peri_force_in_breaking_order(s, s->disc.bonds.surface_G ? peri_corrected_lps_force : lps_force_pass);
}

/* W_i = K_theta theta_i^2/2 + (alpha_m/m_i)/2 sum_j omega (e^d)^2 beta V_j with e^d = q - theta_i
 * |xi|/3 (q = e - alpha_T dT_i |xi|), in one pass: theta_i = n_theta (sum w q)/m_i comes from
 * node i's own bonds, and sum omega beta V (q - theta |xi|/3)^2 = sum omega beta V q^2 - (2 theta/3)
 * sum w q + (theta^2/9) sum w |xi| (w = omega |xi| beta V). Not on the time-step path. */
static void lps_energy(peri_sim *s, double *W) {
  if (s->disc.bonds.surface_G) {
    peri_corrected_lps_energy(s, W);
    return;
  }
  if (s->state.plastic_reverse) {
    peri_deviatoric_energy(s, W);
    return;
  }
  if (s->state.plastic_stretch) {
    peri_plastic_lps_energy(s, W);
    return;
  }
  /* the tensor rule: the elastic energy from the same sums and, with them, the plastic tensors'
   * part (peri_tensor_energy) */
  const bool tensor = s->state.plastic_tensor != NULL;
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const lps_loops *loops = lps_pass1_loops(s, items, tensor ? lps_sums_table_tensor_energy : lps_sums_table_energy);
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  const peri_particles *p = &s->disc.p;
  const size_t owned = (size_t)(p->n_owned > 0 ? p->n_owned : 1), stride = (size_t)p->n_owned;
  double *N = tensor ? peri_malloc(6 * sizeof(double) * owned) : NULL,
         *theta_of = tensor ? peri_malloc(sizeof(double) * owned) : NULL;
  long n_broken = 0; /* (the energy breaks nothing) */
  LPS_FOR_EACH_NODE(items, loops, w, false, {
    const peri_material *mat = &s->mat.materials[p->material[i]];
    const double m = p->wvol[i];
    const double theta = mat->n_theta * r->sum[0] / m;
    const double deviatoric = r->sum[2] - (2.0 * theta / 3.0) * r->sum[0] + (theta * theta / 9.0) * r->sum[1];
    W[i] = mat->peer_force_state ? peri_lps_peer_energy(mat, theta, mat->alpha_m / m, r->sum[2])
                                 : 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / m) * deviatoric;
    if (tensor) {
      for (int c = 0; c < 6; ++c) N[(size_t)c * stride + (size_t)i] = r->tensor[c];
      theta_of[i] = theta;
    }
  })
  (void)n_broken;
  if (tensor) peri_tensor_energy(s, N, theta_of, W);
  free(N), free(theta_of);
}

static double lps_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  if (s->disc.bonds.surface_G) return peri_corrected_lps_pair(s, i, k, r);
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int32_t j = b->neighbor[k];
  const double L = peri_bond_length(p->x, i, j), omega = peri_bonds_omega(b, L);
  const size_t n = (size_t)p->n;
  if (s->state.plastic_reverse) /* the deviatoric rule: each end's plastic part of its deviatoric term */
    return omega * (L * (p->coef[i] + p->coef[j]) + (r - L) * (p->coef[n + (size_t)i] + p->coef[n + (size_t)j]) -
                    L * peri_deviatoric_pair_plastic(s, i, k));
  if (s->state.plastic_tensor) /* the tensor rule: n . (A_i + A_j) . n */
    return omega * (L * (p->coef[i] + p->coef[j] - peri_tensor_pair_term(s, i, j)) +
                    (r - L) * (p->coef[n + (size_t)i] + p->coef[n + (size_t)j]));
  const double e = r - L - peri_plastic_bond_stretch(s, i, k) * L; /* the elastic extension */
  /* node i's half, omega (n_theta (K theta - alpha P/3) L/m + alpha (e - eth L - theta L/3))
   * with its thermal strain eth, is omega (D L + B e) with i's coefficients D, B of the
   * dilatation pass, which the force pass exchanges for ghosts (theta and P it does not): a
   * node next to another rank's nodes gets their halves right */
  return omega * (L * (p->coef[i] + p->coef[j]) + e * (p->coef[n + (size_t)i] + p->coef[n + (size_t)j]));
}

static double lps_own_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  if (s->disc.bonds.surface_G_rev) return peri_position_aware_lps_own(s, i, k, r);
  return 0.5 * lps_pair_force(s, i, k, r);
}

const peri_model_ops peri_model_lps = {
    .name = "lps",
    .description = "ordinary state-based linear peridynamic solid (any Poisson ratio)",
    .fixed_poisson = 0,
    .init = lps_init,
    .force = lps_force,
    .energy = lps_energy,
    .pair_force = lps_pair_force,
    .own_force = lps_own_force,
    .tangent = peri_lps_tangent, .tangent_reach = 2, /* src/model/lps_tangent.c */
};
