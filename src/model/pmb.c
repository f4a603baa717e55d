/* Bond-based prototype microelastic brittle (PMB) model (docs/model_reference.md 2; Le 2014 eqs. 1.3-1.8):
 * pair force f = c omega s M, with the micromodulus c of each end (half-bond rule,
 * c_ij = (c_i + c_j)/2, docs/model_reference.md 8). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/constants.h"
#include "peri/error.h"
#include "peri/interface_moduli.h"
#include "peri/model.h"
#include "bond_kernel.h"
#include "node_blocks.h"
#include "plastic_bonds.h"
#include "surface_correction.h"

static int pmb_init(peri_sim *s) {
  double calibration = peri_influence_calibration(s->disc.family.influence, s->disc.geom.dim, s->disc.geom.horizon);
  for (int m = 0; m < s->mat.n_materials; ++m) {
    peri_material *mat = &s->mat.materials[m];
    if (!mat->micromodulus_given)
      mat->micromodulus = peri_pmb_micromodulus(&s->disc.geom, mat->E, mat->K) * calibration;
    mat->c_stable = mat->micromodulus;
  }
  peri_interface_moduli_init(s); /* interfaces[].youngs_modulus (none: nothing) */
  peri_particles *p = &s->disc.p;
  p->coef = peri_malloc(sizeof(double) * (size_t)(p->n > 0 ? p->n : 1));
  if (peri_plastic_init(s) != PERI_OK) return PERI_ERR_INPUT; /* sublayer plasticity (docs/plasticity.md) */
  return peri_surface_factors(s, false); /* (none without discretization.surface_correction) */
}

/* Node i's own data, read once per family. */
typedef struct pmb_centre {
  double x0, x1, x2, u0, u1, u2, c, eth, bound, V;
} pmb_centre;

static inline pmb_centre pmb_centre_of(const peri_bond_view *w, int32_t i, bool thermal) {
  const pmb_centre c = {w->x0[i], w->x1[i], w->x2[i], w->u0[i], w->u1[i], w->u2[i],
                        w->coef[i], thermal ? w->eth[i] : 0.0, w->s0_bound[i], w->V[i]};
  return c;
}

/* Bond i-j: the factor g of the pair force density g (y_j - y_i) on i, with (y0, y1, y2) =
 * y_j - y_i, the mechanical stretch, and its margin above the screening bound. Both loops
 * below evaluate every bond through this one function, so a node's bonds give the same
 * numbers whichever loop runs them. */
static inline __attribute__((always_inline)) double pmb_bond(const pmb_centre ci_value, const peri_family_eval *fam,
                                                             double xj0, double xj1, double xj2, double uj0,
                                                             double uj1, double uj2, double cj, double eth_j,
                                                             double bound_j, double V_j, bool multi, bool thermal,
                                                             peri_influence influence, bool uniform, bool two_sided,
                                                             double *y0, double *y1, double *y2,
                                                             double *stretch_out, double *excess_out) {
  const pmb_centre *ci = &ci_value;
  const double x0 = xj0 - ci->x0, x1 = xj1 - ci->x1, x2 = xj2 - ci->x2;
  const double d0 = x0 + (uj0 - ci->u0), d1 = x1 + (uj1 - ci->u1), d2 = x2 + (uj2 - ci->u2);
  *y0 = d0, *y1 = d1, *y2 = d2;
  const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
  const double r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
  const double inv_r0_r = 1.0 / (r0 * r); /* the loop's one division */
  double stretch = (r - r0) * r * inv_r0_r;
  if (thermal) stretch -= 0.5 * (ci->eth + eth_j);
  /* two-sided: |s| against the bound (the plastic screen: sublayers yield in compression too) */
  *excess_out = (two_sided ? fabs(stretch) : stretch) - (peri_min(ci->bound, bound_j) - PERI_S0_SCREEN_MARGIN);
  *stretch_out = stretch;
  const double c = multi ? 0.5 * (ci->c + cj) : ci->c;
  const double scale = c * stretch * peri_eval_omega(fam, influence, r0) * peri_eval_beta(fam, r0) *
                       (uniform ? ci->V : V_j) * r0 * inv_r0_r;
  return r > 0.0 ? scale : 0.0;
}

#ifdef PERI_BOND_V8
/* pmb_bond for eight bonds (bond_kernel.h): the same quantities, lengths from reciprocal
 * square roots, no division. The node and block loops both use it (Gaussian influence,
 * which needs exp, keeps the scalar function on both). */
typedef struct pmb_centre_v8 {
  peri_v8d x0, x1, x2, u0, u1, u2, c, eth, bound, V;
} pmb_centre_v8;

/* The offsets of eight bonds from the neighbours' positions (PMB sums the squares as its
 * scalar loops do). */
static inline __attribute__((always_inline)) peri_offset_v8 pmb_offset_v8(const pmb_centre_v8 *ci, peri_v8d xj0,
                                                                         peri_v8d xj1, peri_v8d xj2) {
  const peri_v8d xj[3] = {xj0, xj1, xj2}, c[3] = {ci->x0, ci->x1, ci->x2};
  return peri_offset_of_positions_v8(xj, c, false);
}

/* From the reference offsets (bond_kernel.h: from the positions or a block's table, the same
 * numbers). */
static inline __attribute__((always_inline)) peri_v8d pmb_bond_offset_v8(
    const pmb_centre_v8 *ci, const peri_family_eval *fam, const peri_offset_v8 *o, peri_v8d uj0, peri_v8d uj1,
    peri_v8d uj2, peri_v8d cj, peri_v8d eth_j, peri_v8d bound_j, peri_v8d V_j, bool multi, bool thermal,
    peri_influence influence, bool uniform, bool two_sided, peri_v8d *y0, peri_v8d *y1, peri_v8d *y2,
    peri_v8d *stretch_out, peri_v8d *excess_out) {
  const peri_v8d uj[3] = {uj0, uj1, uj2}, cu[3] = {ci->u0, ci->u1, ci->u2};
  peri_v8d y[3], r, inv_r;
  const peri_v8d r_sq = peri_deformed_lengths_v8(o, uj, cu, false, y, &r, &inv_r);
  *y0 = y[0], *y1 = y[1], *y2 = y[2];
  const peri_v8d r0 = o->r0, inv_r0 = o->inv_r0;
  const peri_v8d half = v8_set1_pd(0.5);
  peri_v8d stretch = v8_mul_pd(v8_sub_pd(r, r0), inv_r0);
  if (thermal) stretch = v8_sub_pd(stretch, v8_mul_pd(half, v8_add_pd(ci->eth, eth_j)));
  const peri_v8d bound = v8_sub_pd(v8_min_pd(ci->bound, bound_j), v8_set1_pd(PERI_S0_SCREEN_MARGIN));
  *excess_out = v8_sub_pd(two_sided ? v8_abs_pd(stretch) : stretch, bound);
  *stretch_out = stretch;
  const peri_v8d c = multi ? v8_mul_pd(half, v8_add_pd(ci->c, cj)) : ci->c;
  peri_v8d scale = v8_mul_pd(c, stretch);
  if (influence == PERI_INFLUENCE_INVERSE) scale = v8_mul_pd(scale, inv_r0); /* omega = 1/|xi| */
  scale = v8_mul_pd(v8_mul_pd(v8_mul_pd(scale, peri_beta_v8(fam, r0)), uniform ? ci->V : V_j), inv_r);
  return v8_maskz_mov_pd(v8_cmp_pd_mask(r_sq, v8_setzero_pd(), _CMP_GT_OQ), scale);
}

static inline __attribute__((always_inline)) peri_v8d pmb_bond_v8(const pmb_centre_v8 *ci, const peri_family_eval *fam,
                                                                 peri_v8d xj0, peri_v8d xj1, peri_v8d xj2, peri_v8d uj0,
                                                                 peri_v8d uj1, peri_v8d uj2, peri_v8d cj, peri_v8d eth_j,
                                                                 peri_v8d bound_j, peri_v8d V_j, bool multi,
                                                                 bool thermal, peri_influence influence, bool uniform,
                                                                 bool two_sided, peri_v8d *y0, peri_v8d *y1,
                                                                 peri_v8d *y2, peri_v8d *stretch_out,
                                                                 peri_v8d *excess_out) {
  const peri_offset_v8 o = pmb_offset_v8(ci, xj0, xj1, xj2);
  return pmb_bond_offset_v8(ci, fam, &o, uj0, uj1, uj2, cj, eth_j, bound_j, V_j, multi, thermal, influence, uniform,
                            two_sided, y0, y1, y2, stretch_out, excess_out);
}

/* Whether a specialization runs on pmb_bond_v8. */
#define PMB_V8(influence) ((influence) != PERI_INFLUENCE_GAUSSIAN)
#endif

/* What the force loops return per node: the force density, the minimum mechanical stretch
 * and whether a stretch passes the screening bound (a candidate for breaking). */
typedef struct pmb_sums {
  double f[3], smin;
  bool candidate;
} pmb_sums;

/* Node i alone, over its intact bonds in family order (the bond values by a vector loop,
 * their sum in order). */
static inline __attribute__((always_inline)) pmb_sums pmb_node(const peri_bond_view *w, int32_t i, int64_t k0,
                                                               int64_t k1, bool multi, bool thermal,
                                                               peri_influence influence, bool uniform,
                                                               bool track_smin, bool two_sided) {
  const pmb_centre ci = pmb_centre_of(w, i, thermal);
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict c_node = w->coef,
                         *restrict eth = w->eth, *restrict s0_bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
  const bool damaged = memchr(w->broken + k0, 1, (size_t)(k1 - k0)) != NULL;
  double fx = 0.0, fy = 0.0, fz = 0.0, smin = INFINITY, excess = -INFINITY;
  int32_t intact[PERI_INTACT_CHUNK];
  double g[PERI_INTACT_CHUNK], y0[PERI_INTACT_CHUNK], y1[PERI_INTACT_CHUNK], y2[PERI_INTACT_CHUNK];
#ifdef PERI_BOND_V8
  if (PMB_V8(influence)) {
    const peri_v8d zero = v8_setzero_pd();
    const pmb_centre_v8 cv = {v8_set1_pd(ci.x0), v8_set1_pd(ci.x1), v8_set1_pd(ci.x2),
                              v8_set1_pd(ci.u0), v8_set1_pd(ci.u1), v8_set1_pd(ci.u2),
                              v8_set1_pd(ci.c),  v8_set1_pd(ci.eth), v8_set1_pd(ci.bound),
                              v8_set1_pd(ci.V)};
    peri_v8d smin_v = v8_set1_pd(INFINITY), excess_v = v8_set1_pd(-INFINITY);
    for (int64_t k = k0; k < k1;) {
      int n;
      const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &n);
      for (int a = 0; a < n; a += 8) {
        const peri_m8 m = peri_first_lanes(n - a);
        const peri_v8i j = v8_maskz_loadu_epi32(m, nbr + a);
#define PMB_GATHER(P) v8_mask_i32gather_pd(m, j, (P))
        peri_v8d gv, yv0, yv1, yv2, s, e;
        gv = pmb_bond_v8(&cv, &fam, PMB_GATHER(X0), PMB_GATHER(X1), PMB_GATHER(X2), PMB_GATHER(U0), PMB_GATHER(U1),
                         PMB_GATHER(U2), multi ? PMB_GATHER(c_node) : zero, thermal ? PMB_GATHER(eth) : zero,
                         PMB_GATHER(s0_bound), uniform ? zero : PMB_GATHER(V), multi, thermal, influence, uniform,
                         two_sided, &yv0, &yv1, &yv2, &s, &e);
#undef PMB_GATHER
        v8_mask_storeu_pd(g + a, m, gv);
        v8_mask_storeu_pd(y0 + a, m, yv0);
        v8_mask_storeu_pd(y1 + a, m, yv1);
        v8_mask_storeu_pd(y2 + a, m, yv2);
        if (track_smin) smin_v = v8_mask_min_pd(smin_v, m, smin_v, s);
        excess_v = v8_mask_max_pd(excess_v, m, excess_v, e);
      }
      for (int a = 0; a < n; ++a) {
        fx = fma(g[a], y0[a], fx);
        fy = fma(g[a], y1[a], fy);
        fz = fma(g[a], y2[a], fz);
      }
    }
    const pmb_sums r = {{fx, fy, fz}, v8_reduce_min_pd(smin_v), v8_reduce_max_pd(excess_v) > 0.0};
    return r;
  }
#endif
  for (int64_t k = k0; k < k1;) {
    int n;
    const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &n);
#pragma omp simd reduction(min : smin) reduction(max : excess)
    for (int a = 0; a < n; ++a) {
      const int32_t j = nbr[a];
      double s, e;
      g[a] = pmb_bond(ci, &fam, X0[j], X1[j], X2[j], U0[j], U1[j], U2[j], multi ? c_node[j] : 0.0,
                      thermal ? eth[j] : 0.0, s0_bound[j], uniform ? 0.0 : V[j], multi, thermal, influence, uniform,
                      two_sided, &y0[a], &y1[a], &y2[a], &s, &e);
      if (track_smin) smin = peri_min(smin, s);
      excess = peri_max(excess, e);
    }
    for (int a = 0; a < n; ++a) {
      fx = fma(g[a], y0[a], fx);
      fy = fma(g[a], y1[a], fy);
      fz = fma(g[a], y2[a], fz);
    }
  }
  const pmb_sums r = {{fx, fy, fz}, smin, excess > 0.0};
  return r;
}

/* The block of nodes i0 .. i0+7 (node_blocks.h), intact: lane l is node i0 + l and takes
 * template entry a, neighbour tj[a] + l, when bit l of lanes[a] is set; every read is
 * contiguous. Same sums as pmb_node. */
static inline __attribute__((always_inline)) void pmb_block(const peri_bond_view *w, int32_t i0,
                                                            const int32_t *restrict tj,
                                                            const uint8_t *restrict lanes, int64_t count,
                                                            bool multi, bool thermal, peri_influence influence,
                                                            bool uniform, bool track_smin, bool two_sided,
                                                            pmb_sums out[PERI_BLOCK], peri_break_marks *marks) {
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict c_node = w->coef,
                         *restrict eth = w->eth, *restrict s0_bound = w->s0_bound;
  const peri_family_eval fam = w->fam;
#ifdef PERI_BOND_V8
  if (PMB_V8(influence)) {
    const peri_v8d zero = v8_setzero_pd();
    const pmb_centre_v8 cv = {v8_loadu_pd(X0 + i0), v8_loadu_pd(X1 + i0), v8_loadu_pd(X2 + i0),
                              v8_loadu_pd(U0 + i0), v8_loadu_pd(U1 + i0), v8_loadu_pd(U2 + i0),
                              v8_loadu_pd(c_node + i0), thermal ? v8_loadu_pd(eth + i0) : zero,
                              v8_loadu_pd(s0_bound + i0), v8_loadu_pd(V + i0)};
    peri_v8d fx = zero, fy = zero, fz = zero, smin = v8_set1_pd(INFINITY);
    peri_m8 beyond = 0;
    /* every entry one offset for all lanes (a lattice): the offsets and their lengths from the
     * table, the positions not read; one loop for each source of the offsets (TABLE constant) */
    const uint16_t *restrict table = peri_block_offsets(w, tj, count);
#define PMB_BLOCK_LOOP(TABLE)                                                                               \
  for (int64_t a = 0; a < count; ++a) {                                                                    \
    const int64_t j = tj[a];                                                                               \
    const peri_m8 on = lanes[a];                                                                           \
    peri_prefetch_next_blocks(w, j, !(TABLE));                                                             \
    const peri_offset_v8 o = (TABLE) ? peri_offset_of_table_v8(w->geom + (size_t)table[a] * PERI_GEOM_STRIDE, false) \
                                     : pmb_offset_v8(&cv, v8_loadu_pd(X0 + j), v8_loadu_pd(X1 + j), v8_loadu_pd(X2 + j)); \
    peri_v8d y0, y1, y2, s, e;                                                                             \
    const peri_v8d g = pmb_bond_offset_v8(                                                                 \
        &cv, &fam, &o, v8_loadu_pd(U0 + j), v8_loadu_pd(U1 + j), v8_loadu_pd(U2 + j),                      \
        multi ? v8_loadu_pd(c_node + j) : zero, thermal ? v8_loadu_pd(eth + j) : zero, v8_loadu_pd(s0_bound + j), \
        uniform ? zero : v8_loadu_pd(V + j), multi, thermal, influence, uniform, two_sided, &y0, &y1, &y2, &s, &e); \
    /* a lane takes the bond when its bit is set: the node path's sums, in the same order */              \
    fx = v8_mask3_fmadd_pd(g, y0, fx, on);                                                                 \
    fy = v8_mask3_fmadd_pd(g, y1, fy, on);                                                                 \
    fz = v8_mask3_fmadd_pd(g, y2, fz, on);                                                                 \
    if (track_smin) smin = v8_mask_min_pd(smin, on, smin, s);                                              \
    const peri_m8 over = v8_mask_cmp_pd_mask(on, e, zero, _CMP_GT_OQ); /* beyond the screening bound */   \
    beyond |= over;                                                                                        \
    if (marks) peri_mark_entry(marks, a, over);                                                            \
  }
    if (table) {
      PMB_BLOCK_LOOP(true)
    } else {
      PMB_BLOCK_LOOP(false)
    }
#undef PMB_BLOCK_LOOP
    double sx[PERI_BLOCK], sy[PERI_BLOCK], sz[PERI_BLOCK], sm[PERI_BLOCK];
    v8_storeu_pd(sx, fx), v8_storeu_pd(sy, fy), v8_storeu_pd(sz, fz), v8_storeu_pd(sm, smin);
    for (int l = 0; l < PERI_BLOCK; ++l) {
      const pmb_sums r = {{sx[l], sy[l], sz[l]}, sm[l], (beyond >> l) & 1u};
      out[l] = r;
    }
    return;
  }
#endif
  /* the eight centres as arrays (one vector each), fx .. beyond the lanes' running sums */
  double c0[PERI_BLOCK], c1[PERI_BLOCK], c2[PERI_BLOCK], cu0[PERI_BLOCK], cu1[PERI_BLOCK], cu2[PERI_BLOCK],
      cc[PERI_BLOCK], ceth[PERI_BLOCK], cbound[PERI_BLOCK], cV[PERI_BLOCK];
  double fx[PERI_BLOCK], fy[PERI_BLOCK], fz[PERI_BLOCK], smin[PERI_BLOCK], beyond[PERI_BLOCK];
  if (marks) marks->n = PERI_BREAK_MARKS + 1; /* (not kept here: the candidates' families are tested) */
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const pmb_centre c = pmb_centre_of(w, i0 + l, thermal);
    c0[l] = c.x0, c1[l] = c.x1, c2[l] = c.x2, cu0[l] = c.u0, cu1[l] = c.u1, cu2[l] = c.u2;
    cc[l] = c.c, ceth[l] = c.eth, cbound[l] = c.bound, cV[l] = c.V;
    fx[l] = fy[l] = fz[l] = 0.0, smin[l] = INFINITY, beyond[l] = 0.0;
  }
  for (int64_t a = 0; a < count; ++a) {
    const int64_t j = tj[a];
    const double *restrict on_lanes = peri_lane_on[lanes[a]];
    peri_prefetch_next_blocks(w, j, true);
    /* (a second exit keeps GCC from versioning this loop for outer-loop vectorization, which
     * would leave the lane loop below without if-conversion) */
    if (j < 0) break;
    const double *restrict A0 = X0 + j, *restrict A1 = X1 + j, *restrict A2 = X2 + j, *restrict B0 = U0 + j,
                           *restrict B1 = U1 + j, *restrict B2 = U2 + j, *restrict Cj = c_node + j,
                           *restrict Ej = thermal ? eth + j : eth, *restrict Sj = s0_bound + j, *restrict Vj = V + j;
#pragma omp simd
    for (int l = 0; l < PERI_BLOCK; ++l) {
      const pmb_centre c = {c0[l], c1[l], c2[l], cu0[l], cu1[l], cu2[l], cc[l], ceth[l], cbound[l], cV[l]};
      double y0, y1, y2, s, e;
      const double g = pmb_bond(c, &fam, A0[l], A1[l], A2[l], B0[l], B1[l], B2[l], multi ? Cj[l] : 0.0,
                                thermal ? Ej[l] : 0.0, Sj[l], uniform ? 0.0 : Vj[l], multi, thermal, influence,
                                uniform, two_sided, &y0, &y1, &y2, &s, &e);
      const bool on = on_lanes[l] != 0.0;
      /* a lane without the bond adds exactly 0 (the sums start at +0, so are never -0) and
       * takes +inf into its minimum: unconditional updates keep the sums in registers, where
       * conditional ones would be masked stores to memory reloaded at every template entry */
      const double g_on = on ? g : 0.0;
      fx[l] = fma(g_on, y0, fx[l]);
      fy[l] = fma(g_on, y1, fy[l]);
      fz[l] = fma(g_on, y2, fz[l]);
      if (track_smin) smin[l] = peri_min(smin[l], on ? s : INFINITY);
      beyond[l] += on && e > 0.0 ? 1.0 : 0.0; /* the bonds beyond the screening bound */
    }
  }
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const pmb_sums r = {{fx[l], fy[l], fz[l]}, smin[l], beyond[l] > 0.0};
    out[l] = r;
  }
}

/* One pair of functions per specialization: the OpenMP region below is outlined before
 * inlining, so the constants must be fixed inside functions of their own to reach the
 * vector loops. */
typedef struct pmb_loops {
  pmb_sums (*node)(const peri_bond_view *, int32_t);
  void (*block)(const peri_bond_view *, int32_t, const int32_t *, const uint8_t *, int64_t, pmb_sums *,
                peri_break_marks *);
} pmb_loops;
#define PMB_VARIANT(NAME, MULTI, THERMAL, INFLUENCE, UNIFORM, SMIN, TWO)                                   \
  static pmb_sums NAME##_node(const peri_bond_view *w, int32_t i) {                                       \
    return pmb_node(w, i, w->offset[i], w->offset[i + 1], MULTI, THERMAL, INFLUENCE, UNIFORM, SMIN, TWO);  \
  }                                                                                                        \
  static void NAME##_block(const peri_bond_view *w, int32_t i0, const int32_t *tj, const uint8_t *lanes,   \
                           int64_t count, pmb_sums *out, peri_break_marks *marks) {                        \
    pmb_block(w, i0, tj, lanes, count, MULTI, THERMAL, INFLUENCE, UNIFORM, SMIN, TWO, out, marks);         \
  }                                                                                                        \
  static const pmb_loops NAME = {NAME##_node, NAME##_block};
/* The specializations, without and with the minimum stretch (the LAMMPS-form critical
 * stretch), in the order of pmb_loops_for; "uniform": every node has the same volume (a
 * grid), so the loop does not gather it */
#define PMB_VARIANTS(SUFFIX, SMIN, TWO)                                                                       \
  PMB_VARIANT(pmb_uniform##SUFFIX, false, false, PERI_INFLUENCE_CONSTANT, true, SMIN, TWO)                 \
  PMB_VARIANT(pmb_plain##SUFFIX, false, false, PERI_INFLUENCE_CONSTANT, false, SMIN, TWO)                  \
  PMB_VARIANT(pmb_multi##SUFFIX, true, false, PERI_INFLUENCE_CONSTANT, false, SMIN, TWO)                   \
  PMB_VARIANT(pmb_thermal##SUFFIX, false, true, PERI_INFLUENCE_CONSTANT, false, SMIN, TWO)                 \
  PMB_VARIANT(pmb_multi_thermal##SUFFIX, true, true, PERI_INFLUENCE_CONSTANT, false, SMIN, TWO)             \
  PMB_VARIANT(pmb_inverse##SUFFIX, true, false, PERI_INFLUENCE_INVERSE, false, SMIN, TWO)                  \
  PMB_VARIANT(pmb_inverse_thermal##SUFFIX, true, true, PERI_INFLUENCE_INVERSE, false, SMIN, TWO)            \
  PMB_VARIANT(pmb_gaussian##SUFFIX, true, false, PERI_INFLUENCE_GAUSSIAN, false, SMIN, TWO)                \
  PMB_VARIANT(pmb_gaussian_thermal##SUFFIX, true, true, PERI_INFLUENCE_GAUSSIAN, false, SMIN, TWO)         \
  static const pmb_loops *const pmb_set##SUFFIX[9] = {                                                    \
      &pmb_uniform##SUFFIX,  &pmb_plain##SUFFIX,         &pmb_multi##SUFFIX,                               \
      &pmb_thermal##SUFFIX,  &pmb_multi_thermal##SUFFIX, &pmb_inverse##SUFFIX,                             \
      &pmb_inverse_thermal##SUFFIX, &pmb_gaussian##SUFFIX, &pmb_gaussian_thermal##SUFFIX};
PMB_VARIANTS(, false, false)
PMB_VARIANTS(_smin, true, false)
/* the plastic screen (pmb_plastic_force_pass): |s| against the sublayers' first yield */
PMB_VARIANTS(_plastic, false, true)
PMB_VARIANTS(_plastic_smin, true, true)

/* The loops of a problem from a set of PMB_VARIANTS. */
static const pmb_loops *pmb_loops_for(const pmb_loops *const set[9], bool multi, bool thermal, bool uniform,
                                      peri_influence influence) {
  if (influence == PERI_INFLUENCE_INVERSE) return set[thermal ? 6 : 5];
  if (influence == PERI_INFLUENCE_GAUSSIAN) return set[thermal ? 8 : 7];
  if (multi) return set[thermal ? 4 : 2];
  return set[thermal ? 3 : uniform ? 0 : 1];
}

static long pmb_force_pass(peri_sim *s, bool update_s0) {
  peri_particles *p = &s->disc.p;
  /* per-node copies of the material data the loop gathers (O(n), refreshed so that they
   * follow any change of the materials) */
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i) p->coef[i] = s->mat.materials[p->material[i]].micromodulus;
  peri_update_s0_bound(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const bool uniform = items->uniform_volume;
  const bool multi = s->mat.n_materials > 1, thermal = s->state.thermal_strain != NULL;
  const bool track_smin = s->mat.s0_node != NULL, breaking = s->solver.breaking;
  const pmb_loops *loops = pmb_loops_for(track_smin ? pmb_set_smin : pmb_set, multi, thermal, uniform, s->disc.family.influence);
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  long n_broken = 0;
#pragma omp parallel reduction(+ : n_broken)
  PERI_FOR_EACH_ITEM(items, item) {
    const int32_t i0 = items->first[item], i1 = items->first[item + 1];
    pmb_sums sums[PERI_BLOCK];
    const bool block = peri_item_is_block(items, item);
    const int64_t t0 = items->tpl[item], entries = peri_item_entries(items, item);
    peri_break_marks marks;
    marks.n = 0;
    if (block) {
      loops->block(&w, i0, items->tpl_node + t0, items->tpl_lanes + t0, entries, sums, breaking ? &marks : NULL);
    } else {
      for (int32_t i = i0; i < i1; ++i) sums[i - i0] = loops->node(&w, i);
    }
    if (breaking)
      PERI_BREAK_AND_RECOMPUTE(s, items, item, i0, i1, sums, block, &marks, n_broken,
                               loops->block(&w, i0, items->tpl_node + t0, items->tpl_lanes + t0, entries, sums, NULL),
                               sums[i - i0] = loops->node(&w, i));
    for (int32_t i = i0; i < i1; ++i) {
      pmb_sums *r = &sums[i - i0];
      for (int d = 0; d < 3; ++d) p->f[3 * i + d] = r->f[d];
      if (track_smin) p->smin[i] = r->smin;
    }
  }
  if (s->mat.s0_node && update_s0) peri_update_lammps_s0(s);
  return n_broken;
}

/* Sublayer plasticity (docs/plasticity.md section 5): the elastic loops screen every node
 * with |s| against its plastic screen (the first yield stretch, the critical stretch's bound,
 * the elastic stretch of a critical bond work); a node with no bond beyond it that has never
 * yielded keeps the elastic force, exactly what the plastic path would give it (its plastic
 * stretches are 0 and stay 0), and every other node takes the plastic path. The
 * choice depends on the node's state only, not on threads or ranks. */
static long pmb_plastic_force_pass(peri_sim *s, bool update_s0) {
  peri_particles *p = &s->disc.p;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i) p->coef[i] = s->mat.materials[p->material[i]].micromodulus;
  peri_update_s0_bound(s);
  peri_plastic_pass pass = peri_plastic_pass_begin(s);
  peri_node_blocks *items = peri_node_blocks_refresh(s);
  const bool multi = s->mat.n_materials > 1, thermal = s->state.thermal_strain != NULL;
  const bool track_smin = s->mat.s0_node != NULL;
  const pmb_loops *loops = pmb_loops_for(track_smin ? pmb_set_plastic_smin : pmb_set_plastic, multi, thermal,
                                         items->uniform_volume, s->disc.family.influence);
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  peri_bond_view screened = w;
  screened.s0_bound = pass.screen, screened.s0_uniform = false;
  const uint8_t *yielded = s->state.plastic_nodes;
  long n_broken = 0;
#pragma omp parallel reduction(+ : n_broken)
  {
    peri_plastic_chunk *scratch = peri_plastic_chunk_new();
    PERI_FOR_EACH_ITEM(items, item) {
      const int32_t i0 = items->first[item], i1 = items->first[item + 1];
      pmb_sums sums[PERI_BLOCK];
      const bool all_yielded = peri_plastic_item_yielded(yielded, i0, i1); /* (no screen then) */
      if (!all_yielded) {
        if (peri_item_is_block(items, item)) {
          const int64_t t0 = items->tpl[item];
          loops->block(&screened, i0, items->tpl_node + t0, items->tpl_lanes + t0, peri_item_entries(items, item),
                       sums, NULL);
        } else {
          for (int32_t i = i0; i < i1; ++i) sums[i - i0] = loops->node(&screened, i);
        }
      }
      for (int32_t i = i0; i < i1; ++i) {
        pmb_sums *r = &sums[i - i0];
        if (all_yielded || r->candidate || yielded[i]) {
          const long broken_here = peri_plastic_pmb_node(s, &w, &pass, i, scratch, r->f, &r->smin);
          if (broken_here > 0) peri_node_blocks_clear_broken(items, &s->disc.bonds, item, i);
          n_broken += broken_here;
        }
        for (int d = 0; d < 3; ++d) p->f[3 * i + d] = r->f[d];
        if (track_smin) p->smin[i] = r->smin;
      }
    }
    free(scratch);
  }
  peri_plastic_pass_end(&pass);
  if (track_smin && update_s0) peri_update_lammps_s0(s);
  return n_broken;
}

/* The bond loops, then the interface bonds' micromodulus difference (interface_moduli.h):
 * one pass, so that the breaking order treats both alike. */
static long pmb_interface_force_pass(peri_sim *s, bool update_s0) {
  const long n_broken = pmb_force_pass(s, update_s0);
  peri_interface_moduli_force(s);
  return n_broken;
}

static long pmb_force(peri_sim *s) {
  if (s->state.plastic_stretch) return peri_force_in_breaking_order(s, pmb_plastic_force_pass);
  if (s->mat.interface_moduli) return peri_force_in_breaking_order(s, pmb_interface_force_pass);
  return peri_force_in_breaking_order(s, s->disc.bonds.surface_G ? peri_corrected_pmb_force : pmb_force_pass);
}

/* Bond i-j: w beta V_j with the micropotential w = c omega s^2 |xi| / 2, c = (c_i + c_j)/2. */
static inline __attribute__((always_inline)) double pmb_bond_energy(const pmb_centre ci_value,
                                                                    const peri_family_eval *fam, double xj0,
                                                                    double xj1, double xj2, double uj0, double uj1,
                                                                    double uj2, double cj, double eth_j, double V_j,
                                                                    bool thermal, peri_influence influence) {
  const pmb_centre *ci = &ci_value;
  const double x0 = xj0 - ci->x0, x1 = xj1 - ci->x1, x2 = xj2 - ci->x2;
  const double y0 = x0 + (uj0 - ci->u0), y1 = x1 + (uj1 - ci->u1), y2 = x2 + (uj2 - ci->u2);
  const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
  const double stretch = (sqrt(y0 * y0 + y1 * y1 + y2 * y2) - r0) / r0 - (thermal ? 0.5 * (ci->eth + eth_j) : 0.0);
  return 0.25 * (ci->c + cj) * peri_eval_omega(fam, influence, r0) * stretch * stretch * r0 *
         peri_eval_beta(fam, r0) * V_j;
}

#ifdef PERI_BOND_V8
/* pmb_bond_energy for eight bonds, lengths as in pmb_bond_v8 (no square root or division):
 * the history rows' energy pass then costs about one force pass. Both energy loops use it. */
static inline __attribute__((always_inline)) peri_v8d pmb_bond_energy_v8(const pmb_centre_v8 *ci,
                                                                        const peri_family_eval *fam, peri_v8d xj0,
                                                                        peri_v8d xj1, peri_v8d xj2, peri_v8d uj0,
                                                                        peri_v8d uj1, peri_v8d uj2, peri_v8d cj,
                                                                        peri_v8d eth_j, peri_v8d V_j, bool thermal,
                                                                        peri_influence influence) {
  const peri_v8d x0 = v8_sub_pd(xj0, ci->x0), x1 = v8_sub_pd(xj1, ci->x1), x2 = v8_sub_pd(xj2, ci->x2);
  const peri_v8d y0 = v8_add_pd(x0, v8_sub_pd(uj0, ci->u0)), y1 = v8_add_pd(x1, v8_sub_pd(uj1, ci->u1)),
                y2 = v8_add_pd(x2, v8_sub_pd(uj2, ci->u2));
  const peri_v8d r0_sq = peri_norm2_v8(x0, x1, x2), r_sq = peri_norm2_v8(y0, y1, y2);
  peri_v8d r0, inv_r0, r, inv_r;
  peri_root_v8(r0_sq, &r0, &inv_r0);
  peri_root_v8(r_sq, &r, &inv_r);
  /* (a collapsed bond, r = 0, has stretch -1: not NaN) */
  r = v8_maskz_mov_pd(v8_cmp_pd_mask(r_sq, v8_setzero_pd(), _CMP_GT_OQ), r);
  const peri_v8d half = v8_set1_pd(0.5);
  peri_v8d stretch = v8_mul_pd(v8_sub_pd(r, r0), inv_r0);
  if (thermal) stretch = v8_sub_pd(stretch, v8_mul_pd(half, v8_add_pd(ci->eth, eth_j)));
  peri_v8d e = v8_mul_pd(v8_set1_pd(0.25), v8_add_pd(ci->c, cj));
  if (influence == PERI_INFLUENCE_INVERSE) e = v8_mul_pd(e, inv_r0); /* omega = 1/|xi| */
  e = v8_mul_pd(v8_mul_pd(v8_mul_pd(e, stretch), stretch), r0);
  return v8_mul_pd(v8_mul_pd(e, peri_beta_v8(fam, r0)), V_j);
}
#endif

/* Node i's data for the energy (which may run before any force evaluation: no bounds). */
static inline pmb_centre pmb_energy_centre(const peri_bond_view *w, int32_t i, bool thermal) {
  const pmb_centre c = {w->x0[i], w->x1[i], w->x2[i], w->u0[i], w->u1[i], w->u2[i],
                        w->coef[i], thermal ? w->eth[i] : 0.0, 0.0, 0.0};
  return c;
}

/* Node i alone: the sum over its intact bonds in family order. */
static inline __attribute__((always_inline)) double pmb_node_energy(const peri_bond_view *w, int32_t i, bool thermal,
                                                                    peri_influence influence) {
  const pmb_centre ci = pmb_energy_centre(w, i, thermal);
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict c_node = w->coef,
                         *restrict eth = w->eth;
  const peri_family_eval fam = w->fam;
  const int64_t k0 = w->offset[i], k1 = w->offset[i + 1];
  const bool damaged = memchr(w->broken + k0, 1, (size_t)(k1 - k0)) != NULL;
  int32_t intact[PERI_INTACT_CHUNK];
  double e[PERI_INTACT_CHUNK], sum = 0.0;
#ifdef PERI_BOND_V8
  if (PMB_V8(influence)) {
    const peri_v8d zero = v8_setzero_pd();
    const pmb_centre_v8 cv = {v8_set1_pd(ci.x0), v8_set1_pd(ci.x1), v8_set1_pd(ci.x2),
                              v8_set1_pd(ci.u0), v8_set1_pd(ci.u1), v8_set1_pd(ci.u2),
                              v8_set1_pd(ci.c),  v8_set1_pd(ci.eth), zero, zero};
    for (int64_t k = k0; k < k1;) {
      int n;
      const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &n);
      for (int a = 0; a < n; a += 8) {
        const peri_m8 m = peri_first_lanes(n - a);
        const peri_v8i j = v8_maskz_loadu_epi32(m, nbr + a);
#define PMB_GATHER(P) v8_mask_i32gather_pd(m, j, (P))
        v8_mask_storeu_pd(e + a, m,
                              pmb_bond_energy_v8(&cv, &fam, PMB_GATHER(X0), PMB_GATHER(X1), PMB_GATHER(X2),
                                                 PMB_GATHER(U0), PMB_GATHER(U1), PMB_GATHER(U2), PMB_GATHER(c_node),
                                                 thermal ? PMB_GATHER(eth) : zero, PMB_GATHER(V), thermal, influence));
#undef PMB_GATHER
      }
      for (int a = 0; a < n; ++a) sum += e[a];
    }
    return sum;
  }
#endif
  for (int64_t k = k0; k < k1;) {
    int n;
    const int32_t *restrict nbr = peri_next_chunk(w, damaged, &k, k1, intact, &n);
#pragma omp simd
    for (int a = 0; a < n; ++a) {
      const int32_t j = nbr[a];
      e[a] = pmb_bond_energy(ci, &fam, X0[j], X1[j], X2[j], U0[j], U1[j], U2[j], c_node[j], thermal ? eth[j] : 0.0,
                             V[j], thermal, influence);
    }
    for (int a = 0; a < n; ++a) sum += e[a];
  }
  return sum;
}

/* The block of nodes i0 .. i0+7 (as pmb_block): the same sums, eight at a time. */
static inline __attribute__((always_inline)) void pmb_block_energy(const peri_bond_view *w, int32_t i0,
                                                                   const int32_t *restrict tj,
                                                                   const uint8_t *restrict lanes, int64_t count,
                                                                   bool thermal, peri_influence influence,
                                                                   double out[PERI_BLOCK]) {
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2, *restrict V = w->V, *restrict c_node = w->coef,
                         *restrict eth = w->eth;
  const peri_family_eval fam = w->fam;
#ifdef PERI_BOND_V8
  if (PMB_V8(influence)) {
    const peri_v8d zero = v8_setzero_pd();
    const pmb_centre_v8 cv = {v8_loadu_pd(X0 + i0), v8_loadu_pd(X1 + i0), v8_loadu_pd(X2 + i0),
                              v8_loadu_pd(U0 + i0), v8_loadu_pd(U1 + i0), v8_loadu_pd(U2 + i0),
                              v8_loadu_pd(c_node + i0), thermal ? v8_loadu_pd(eth + i0) : zero, zero, zero};
    peri_v8d sum = zero;
    for (int64_t a = 0; a < count; ++a) {
      const int64_t j = tj[a];
      peri_prefetch_next_blocks(w, j, true);
      const peri_v8d e = pmb_bond_energy_v8(&cv, &fam, v8_loadu_pd(X0 + j), v8_loadu_pd(X1 + j),
                                           v8_loadu_pd(X2 + j), v8_loadu_pd(U0 + j), v8_loadu_pd(U1 + j),
                                           v8_loadu_pd(U2 + j), v8_loadu_pd(c_node + j),
                                           thermal ? v8_loadu_pd(eth + j) : zero, v8_loadu_pd(V + j), thermal,
                                           influence);
      sum = v8_mask_add_pd(sum, lanes[a], sum, e); /* a lane adds the bond when its bit is set */
    }
    v8_storeu_pd(out, sum);
    return;
  }
#endif
  double c0[PERI_BLOCK], c1[PERI_BLOCK], c2[PERI_BLOCK], cu0[PERI_BLOCK], cu1[PERI_BLOCK], cu2[PERI_BLOCK],
      cc[PERI_BLOCK], ceth[PERI_BLOCK], sum[PERI_BLOCK];
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const pmb_centre c = pmb_energy_centre(w, i0 + l, thermal);
    c0[l] = c.x0, c1[l] = c.x1, c2[l] = c.x2, cu0[l] = c.u0, cu1[l] = c.u1, cu2[l] = c.u2;
    cc[l] = c.c, ceth[l] = c.eth, sum[l] = 0.0;
  }
  for (int64_t a = 0; a < count; ++a) {
    const int64_t j = tj[a];
    if (j < 0) break; /* (see pmb_block) */
    const double *restrict on_lanes = peri_lane_on[lanes[a]];
    const double *restrict A0 = X0 + j, *restrict A1 = X1 + j, *restrict A2 = X2 + j, *restrict B0 = U0 + j,
                           *restrict B1 = U1 + j, *restrict B2 = U2 + j, *restrict Cj = c_node + j,
                           *restrict Ej = thermal ? eth + j : eth, *restrict Vj = V + j;
#pragma omp simd
    for (int l = 0; l < PERI_BLOCK; ++l) {
      const pmb_centre c = {c0[l], c1[l], c2[l], cu0[l], cu1[l], cu2[l], cc[l], ceth[l], 0.0, 0.0};
      const double e = pmb_bond_energy(c, &fam, A0[l], A1[l], A2[l], B0[l], B1[l], B2[l], Cj[l],
                                       thermal ? Ej[l] : 0.0, Vj[l], thermal, influence);
      sum[l] += on_lanes[l] != 0.0 ? e : 0.0; /* (unconditional: see pmb_block) */
    }
  }
  for (int l = 0; l < PERI_BLOCK; ++l) out[l] = sum[l];
}

typedef struct pmb_energy_loops {
  double (*node)(const peri_bond_view *, int32_t);
  void (*block)(const peri_bond_view *, int32_t, const int32_t *, const uint8_t *, int64_t, double *);
} pmb_energy_loops;
#define PMB_ENERGY_VARIANT(NAME, THERMAL, INFLUENCE)                                                      \
  static double NAME##_node(const peri_bond_view *w, int32_t i) {                                        \
    return pmb_node_energy(w, i, THERMAL, INFLUENCE);                                                     \
  }                                                                                                       \
  static void NAME##_block(const peri_bond_view *w, int32_t i0, const int32_t *tj, const uint8_t *lanes,  \
                           int64_t count, double *out) {                                                  \
    pmb_block_energy(w, i0, tj, lanes, count, THERMAL, INFLUENCE, out);                                   \
  }                                                                                                       \
  static const pmb_energy_loops NAME = {NAME##_node, NAME##_block};
PMB_ENERGY_VARIANT(pmb_energy_constant, false, PERI_INFLUENCE_CONSTANT)
PMB_ENERGY_VARIANT(pmb_energy_constant_thermal, true, PERI_INFLUENCE_CONSTANT)
PMB_ENERGY_VARIANT(pmb_energy_inverse, false, PERI_INFLUENCE_INVERSE)
PMB_ENERGY_VARIANT(pmb_energy_inverse_thermal, true, PERI_INFLUENCE_INVERSE)
PMB_ENERGY_VARIANT(pmb_energy_gaussian, false, PERI_INFLUENCE_GAUSSIAN)
PMB_ENERGY_VARIANT(pmb_energy_gaussian_thermal, true, PERI_INFLUENCE_GAUSSIAN)

/* W_i = 1/2 sum_j w_ij beta V_j, on the node blocks like the force. Not on the time-step
 * path (history rows only). */
static void pmb_energy(peri_sim *s, double *W) {
  if (s->disc.bonds.surface_G) {
    peri_corrected_pmb_energy(s, W);
    return;
  }
  if (s->state.plastic_stretch) {
    peri_plastic_pmb_energy(s, W);
    return;
  }
  peri_particles *p = &s->disc.p;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n; ++i) p->coef[i] = s->mat.materials[p->material[i]].micromodulus;
  const peri_node_blocks *items = peri_node_blocks_refresh(s);
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  const bool thermal = s->state.thermal_strain != NULL;
  const pmb_energy_loops *loops = thermal ? &pmb_energy_constant_thermal : &pmb_energy_constant;
  if (s->disc.family.influence == PERI_INFLUENCE_INVERSE) loops = thermal ? &pmb_energy_inverse_thermal : &pmb_energy_inverse;
  if (s->disc.family.influence == PERI_INFLUENCE_GAUSSIAN)
    loops = thermal ? &pmb_energy_gaussian_thermal : &pmb_energy_gaussian;
#pragma omp parallel
  PERI_FOR_EACH_ITEM(items, item) {
    const int32_t i0 = items->first[item], i1 = items->first[item + 1];
    if (peri_item_is_block(items, item)) {
      double sums[PERI_BLOCK];
      const int64_t t0 = items->tpl[item];
      loops->block(&w, i0, items->tpl_node + t0, items->tpl_lanes + t0, peri_item_entries(items, item), sums);
      for (int32_t i = i0; i < i1; ++i) W[i] = 0.5 * sums[i - i0];
    } else {
      for (int32_t i = i0; i < i1; ++i) W[i] = 0.5 * loops->node(&w, i);
    }
  }
  peri_interface_moduli_energy(s, W); /* interfaces[].youngs_modulus (none: nothing) */
}

static double pmb_pair_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  if (s->disc.bonds.surface_G) return peri_corrected_pmb_pair(s, i, k, r);
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const int32_t j = b->neighbor[k];
  const double r0 = peri_bond_length(p->x, i, j);
  const double stretch = (r - r0) / r0 - peri_bond_thermal_stretch(s->state.thermal_strain, i, j) -
                         peri_plastic_bond_stretch(s, i, k);
  const double c = peri_pmb_bond_micromodulus(s, p->material[i], p->material[j]);
  return c * stretch * peri_bonds_omega(b, r0);
}

/* position_aware: i's half with its own factor g_i (surface_D), the pair's being (g_i + g_j)/2 */
static double pmb_own_force(const peri_sim *s, int32_t i, int64_t k, double r) {
  const peri_bonds *b = &s->disc.bonds;
  const double pair = pmb_pair_force(s, i, k, r);
  if (b->surface_G && b->surface_D && b->surface_G[k] != 0.0) return 0.5 * pair * b->surface_D[k] / b->surface_G[k];
  return 0.5 * pair;
}

const peri_model_ops peri_model_pmb = {
    .name = "pmb",
    .description = "bond-based PMB (Poisson ratio fixed: 1/4 in 1D, 3D and plane strain, 1/3 in plane stress)",
    .fixed_poisson = 1,
    .init = pmb_init,
    .force = pmb_force,
    .energy = pmb_energy,
    .pair_force = pmb_pair_force,
    .own_force = pmb_own_force,
    .tangent = peri_pmb_tangent, .tangent_reach = 1, /* src/model/pmb_tangent.c */
};
