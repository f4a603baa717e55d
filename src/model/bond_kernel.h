/* Helpers shared by the bond loops of the mechanical models. */
#ifndef PERI_BOND_KERNEL_H
#define PERI_BOND_KERNEL_H
#include <math.h>
#include "peri/sim.h"
#include "peri/tensor_plasticity.h"
#include "node_blocks.h"

/* Deformed bond vector y_j - y_i and its length. Computed identically from both ends up
 * to sign, so the stretch (and so every breaking decision) is symmetric in i and j. */
static inline double peri_deformed_bond(const double *x, const double *u, int32_t i, int32_t j,
                                        double dy[3]) {
  for (int c = 0; c < 3; ++c) dy[c] = (x[3 * j + c] + u[3 * j + c]) - (x[3 * i + c] + u[3 * i + c]);
  return sqrt(dy[0] * dy[0] + dy[1] * dy[1] + dy[2] * dy[2]);
}

/* |(a, b, c)| with two fused multiply-adds: the one expression of a bond's lengths in the
 * LPS loops (fewer operations, and a rounding less) */
static inline double peri_length3(double a, double b, double c) { return sqrt(fma(c, c, fma(b, b, a * a))); }

/* Critical stretch of bond i-j: LAMMPS form min(s0_i, s0_j), else the pair table.
 * INFINITY when either end is a no-fail node. */
static inline double peri_bond_s0(const peri_sim *s, int32_t i, int32_t j) {
  const peri_particles *p = &s->disc.p;
  if ((p->flags[i] | p->flags[j]) & PERI_NODE_NO_FAIL) return INFINITY;
  if (s->mat.s0_node) return fmin(s->mat.s0_node[i], s->mat.s0_node[j]);
  return s->mat.pair_s0[p->material[i] * s->mat.n_materials + p->material[j]];
}

/* Thermal stretch of bond i-j, 1/2 (alpha_i dT_i + alpha_j dT_j) (docs/model_reference.md 9): subtracted
 * from the stretch by the bond-based model and by every breaking test; 0 without
 * thermomechanics. */
static inline double peri_bond_thermal_stretch(const double *eth, int32_t i, int32_t j) {
  return eth ? 0.5 * (eth[i] + eth[j]) : 0.0;
}

/* The family's partial-volume and influence rules in the form the bond loops evaluate per
 * bond (the same values as peri_bonds_beta / peri_bonds_omega up to rounding). */
typedef struct peri_family_eval {
  double beta0, inv_dx;   /* beta = min(1, beta0 - |xi| inv_dx) */
  double inv_delta2;      /* Gaussian influence */
  peri_influence influence;
} peri_family_eval;

static inline peri_family_eval peri_family_eval_of(const peri_bonds *b) {
  const peri_family_params *f = &b->family;
  peri_family_eval e = {1.0, 0.0, 1.0 / (f->horizon * f->horizon), f->influence};
  if (f->rule != PERI_PV_NONE && f->spacing > 0) {
    e.beta0 = 0.5 + f->horizon / f->spacing;
    e.inv_dx = 1.0 / f->spacing;
  }
  return e;
}
/* min without fmin's NaN rules, so that it compiles to one vector instruction */
static inline double peri_min(double a, double b) { return a < b ? a : b; }
static inline double peri_max(double a, double b) { return a > b ? a : b; }
static inline double peri_eval_beta(const peri_family_eval *e, double r0) {
  return peri_min(1.0, e->beta0 - r0 * e->inv_dx);
}
/* `influence` is passed separately so that a constant argument specializes the loop. */
static inline double peri_eval_omega(const peri_family_eval *e, peri_influence influence, double r0) {
  if (influence == PERI_INFLUENCE_INVERSE) return 1.0 / r0;
  if (influence == PERI_INFLUENCE_GAUSSIAN) return exp(-(r0 * r0) * e->inv_delta2);
  return 1.0;
}

#include "vector8.h"
#ifdef PERI_BOND_V8
/* Eight bonds at a time (vector8.h: one 512-bit register, or two 256-bit ones on AVX2; the
 * PMB and LPS bond functions of pmb.c and lps.c): lengths from reciprocal square roots instead of square roots and divisions, whose
 * one unit takes 16-32 cycles for a 512-bit vector on Intel Ice Lake. Every path of a model
 * (node blocks and single nodes) evaluates its bonds through the same eight-lane function,
 * so they still agree bit for bit; the numbers differ from the scalar functions at
 * round-off (a few units in the last place of a length), and between AVX-512 and AVX2 builds
 * (their first estimates differ). */
/* sqrt(x) and 1/sqrt(x) for positive normal x: vrsqrt14pd's estimate y0 (relative error below
 * 2^-14; on AVX2 v8_rsqrt14_pd's, below 2^-23) corrected by one third-order step of the series
 * (1 - e)^(-1/2) = 1 + e/2 + 3e²/8 + 5e³/16 + ..., e = 1 - x y0² (truncation 35e⁴/128 < 2^-57),
 * applied to y0 for 1/sqrt(x) and to x y0 for sqrt(x). Over 8 million values the two are within
 * 1.27 and 1.04 units in the last place (two Newton steps and x times the reciprocal root: 1.19
 * and 1.71), in 9 operations for both, as before, and 7 instead of 9 for a caller that needs
 * only sqrt(x) (the compiler drops what is not used). x = 0 gives NaN here and 1/0 = inf by
 * the hardware way below (callers mask a zero length either way). */
/* Which way peri_root_v8 takes. On an AMD EPYC of the Zen 5 kind (GCC 12 names it znver3 under
 * -march=native and enables its AVX-512; later compilers say znver5) the 512-bit square root and
 * division are quick enough that sqrt(x), then 1/sqrt(x) by one division, take less time than
 * the estimate and its series: on the LAMMPS problem at 26k nodes, one thread, LPS 1.04 -> 0.83 s
 * and PMB 0.55 -> 0.51 s (docs/performance.md). Everywhere else (Intel, where one unit does them
 * in 16-32 cycles a vector; Zen 4, not measured; AVX2) the series. -DPERI_ROOT_HARDWARE=0 or 1
 * overrides the choice. The two ways differ at round-off: the square root is correctly rounded
 * and the reciprocal within one unit in the last place (tests/unit/test_bond_lengths.c holds
 * both to the series' bound), so builds for the two kinds differ there, as AVX2 and AVX-512
 * builds do. Every path of a model takes the same way, so they still agree bit for bit. */
#ifndef PERI_ROOT_HARDWARE
#define PERI_ROOT_HARDWARE PERI_AVX512_ZEN5
#endif
static inline __attribute__((always_inline)) void peri_root_v8(peri_v8d x, peri_v8d *root, peri_v8d *inv_root) {
#if PERI_ROOT_HARDWARE
  *root = v8_sqrt_pd(x);
  *inv_root = v8_div_pd(v8_set1_pd(1.0), *root);
#else
  const peri_v8d y0 = v8_rsqrt14_pd(x), x_y0 = v8_mul_pd(x, y0);
  const peri_v8d e = v8_fnmadd_pd(x_y0, y0, v8_set1_pd(1.0));
  const peri_v8d series = v8_fmadd_pd(v8_fmadd_pd(e, v8_set1_pd(5.0 / 16.0), v8_set1_pd(3.0 / 8.0)), e, v8_set1_pd(0.5));
  *inv_root = v8_fmadd_pd(v8_mul_pd(y0, e), series, y0);
  *root = v8_fmadd_pd(v8_mul_pd(x_y0, e), series, x_y0);
#endif
}
/* a0² + a1² + a2² in the order of the scalar loops (PMB), or by FMAs (the other models) */
static inline __attribute__((always_inline)) peri_v8d peri_norm2_v8(peri_v8d a0, peri_v8d a1, peri_v8d a2) {
  return v8_add_pd(v8_add_pd(v8_mul_pd(a0, a0), v8_mul_pd(a1, a1)), v8_mul_pd(a2, a2));
}
static inline __attribute__((always_inline)) peri_v8d peri_norm2_fma_v8(peri_v8d a0, peri_v8d a1, peri_v8d a2) {
  return v8_fmadd_pd(a2, a2, v8_fmadd_pd(a1, a1, v8_mul_pd(a0, a0)));
}
/* The reference offsets xi = x_j - x_i of eight bonds with |xi| and 1/|xi|, from the
 * neighbours' positions xj and the centre's c, or from a block's table of offsets
 * (node_blocks.h), which holds the numbers the positions give, for either sum of squares. */
typedef struct peri_offset_v8 {
  peri_v8d x[3], r0, inv_r0;
} peri_offset_v8;
static inline __attribute__((always_inline)) peri_offset_v8 peri_offset_of_positions_v8(const peri_v8d xj[3],
                                                                                       const peri_v8d c[3],
                                                                                       bool fma_sum) {
  peri_offset_v8 o;
  for (int d = 0; d < 3; ++d) o.x[d] = v8_sub_pd(xj[d], c[d]);
  const peri_v8d r0_sq = fma_sum ? peri_norm2_fma_v8(o.x[0], o.x[1], o.x[2]) : peri_norm2_v8(o.x[0], o.x[1], o.x[2]);
  peri_root_v8(r0_sq, &o.r0, &o.inv_r0);
  return o;
}
static inline __attribute__((always_inline)) peri_offset_v8 peri_offset_of_table_v8(const double *restrict g,
                                                                                   bool fma_sum) {
  const peri_offset_v8 o = {{v8_set1_pd(g[PERI_GEOM_XI0]), v8_set1_pd(g[PERI_GEOM_XI1]), v8_set1_pd(g[PERI_GEOM_XI2])},
                            v8_set1_pd(g[fma_sum ? PERI_GEOM_R0_FMA : PERI_GEOM_R0_NORM2]),
                            v8_set1_pd(g[fma_sum ? PERI_GEOM_INV_R0_FMA : PERI_GEOM_INV_R0_NORM2])};
  return o;
}
/* The relative vectors y = xi + (u_j - u_i) from the offsets, the neighbours' displacements
 * uj and the centre's cu, and their lengths r and 1/r: the same function as for |xi|, so an
 * undeformed bond has r == r0. Returns |y|². */
static inline __attribute__((always_inline)) peri_v8d peri_deformed_lengths_v8(const peri_offset_v8 *o,
                                                                               const peri_v8d uj[3], const peri_v8d cu[3],
                                                                               bool fma_sum, peri_v8d y[3], peri_v8d *r,
                                                                               peri_v8d *inv_r) {
  for (int d = 0; d < 3; ++d) y[d] = v8_add_pd(o->x[d], v8_sub_pd(uj[d], cu[d]));
  const peri_v8d r_sq = fma_sum ? peri_norm2_fma_v8(y[0], y[1], y[2]) : peri_norm2_v8(y[0], y[1], y[2]);
  peri_root_v8(r_sq, r, inv_r);
  return r_sq;
}
/* Both lengths of eight bonds from the positions (the FMA sums): one function for every
 * model's kernels, so their paths agree bit for bit. */
static inline __attribute__((always_inline)) void peri_bond_lengths_v8(const peri_v8d xj[3], const peri_v8d uj[3],
                                                                       const peri_v8d c[3], const peri_v8d cu[3],
                                                                       peri_v8d y[3], peri_v8d *r0, peri_v8d *inv_r0,
                                                                       peri_v8d *r, peri_v8d *inv_r) {
  const peri_offset_v8 o = peri_offset_of_positions_v8(xj, c, true);
  peri_deformed_lengths_v8(&o, uj, cu, true, y, r, inv_r);
  *r0 = o.r0, *inv_r0 = o.inv_r0;
}
/* the partial-volume factor min(1, beta0 - r0 / dx) of peri_eval_beta */
static inline __attribute__((always_inline)) peri_v8d peri_beta_v8(const peri_family_eval *e, peri_v8d r0) {
  return v8_min_pd(v8_set1_pd(1.0),
                       v8_sub_pd(v8_set1_pd(e->beta0), v8_mul_pd(r0, v8_set1_pd(e->inv_dx))));
}
/* Whether beta is 1 on every bond (a family without partial volumes: min(1, 1 - r0 0) = 1
 * exactly), so that a loop may skip peri_beta_v8 and give the same sums bit for bit. */
static inline bool peri_family_unit_beta(const peri_family_eval *e) { return e->beta0 == 1.0 && e->inv_dx == 0.0; }
/* peri_beta_v8, or 1 where the loop was specialized for peri_family_unit_beta. */
static inline __attribute__((always_inline)) peri_v8d peri_beta_or_one_v8(const peri_family_eval *e, peri_v8d r0,
                                                                          bool unit_beta) {
  return unit_beta ? v8_set1_pd(1.0) : peri_beta_v8(e, r0);
}
/* The lane mask of the first n of eight lanes. */
static inline peri_m8 peri_first_lanes(int n) { return n >= 8 ? (peri_m8)0xFF : (peri_m8)((1u << n) - 1u); }
#endif

/* What the bond loops of the models read, as restrict pointers so that the compiler
 * vectorizes: structure-of-arrays copies of the positions and displacements (node_blocks.h),
 * volumes, the model's per-node coefficients (p->coef), thermal strain (NULL without), the
 * breaking bounds, and the bonds. */
typedef struct peri_bond_view {
  const double *restrict x0, *restrict x1, *restrict x2, *restrict u0, *restrict u1, *restrict u2;
  const double *restrict V, *restrict coef, *restrict eth, *restrict s0_bound;
  bool s0_uniform; /* every node's s0_bound is the same number (a loop may take the centre's) */
  const int64_t *restrict offset;
  const int32_t *restrict neighbor;
  const uint8_t *restrict broken;
  peri_family_eval fam;
  int32_t n; /* nodes (owned and ghosts): the stride of per-node fields with several parts */
  /* the blocks' offsets (node_blocks.h): a block's entries tj have theirs at
   * tpl_geom[tj - tpl_node] in geom; NULL before the blocks are built */
  const int32_t *tpl_node;
  const uint16_t *tpl_geom;
  const double *geom;
  /* the tensor yield rule's per-node plastic terms ([6][n], src/model/tensor_plasticity.c), or NULL */
  const double *restrict plastic_term;
} peri_bond_view;

/* The view of s with the copies in `soa` (6 n doubles: x0 x1 x2 u0 u1 u2). */
static inline peri_bond_view peri_bond_view_of(const peri_sim *s, const double *soa) {
  const size_t n = (size_t)s->disc.p.n;
  const peri_bond_view w = {soa, soa + n, soa + 2 * n, soa + 3 * n, soa + 4 * n, soa + 5 * n,
                            s->disc.p.volume, s->disc.p.coef, s->state.thermal_strain, s->disc.p.s0_bound,
                            s->disc.p.s0_bound != NULL && s->disc.p.s0_bound_uniform,
                            s->disc.bonds.offset, s->disc.bonds.neighbor, s->disc.bonds.broken, peri_family_eval_of(&s->disc.bonds),
                            s->disc.p.n,
                            s->disc.node_blocks ? s->disc.node_blocks->tpl_node : NULL,
                            s->disc.node_blocks ? s->disc.node_blocks->tpl_geom : NULL,
                            s->disc.node_blocks ? s->disc.node_blocks->geom : NULL,
                            s->state.plastic_tensor ? s->state.plastic_tensor->term : NULL};
  return w;
}

/* The next blocks of a row (node_blocks.h) read the same template entries shifted by 8 nodes:
 * the block loops fetch them two blocks ahead, as they touch more rows than the hardware
 * prefetcher follows; the positions only where the loop reads them (not with a table of
 * offsets). */
static inline void peri_prefetch_next_blocks(const peri_bond_view *w, int64_t j, bool positions) {
  const int64_t ahead = j + 16;
  if (positions) __builtin_prefetch(w->x0 + ahead), __builtin_prefetch(w->x1 + ahead), __builtin_prefetch(w->x2 + ahead);
  __builtin_prefetch(w->u0 + ahead), __builtin_prefetch(w->u1 + ahead), __builtin_prefetch(w->u2 + ahead);
}

/* The table indices of the offsets of a block's entries tj (node_blocks.h), or NULL when the
 * block's lanes compute theirs from the positions. */
static inline const uint16_t *peri_block_offsets(const peri_bond_view *w, const int32_t *tj, int64_t count) {
  const uint16_t *index = w->tpl_geom && count > 0 ? w->tpl_geom + (tj - w->tpl_node) : NULL;
  return index && index[0] != PERI_GEOM_NONE ? index : NULL;
}

/* The bond loops run on lists of intact neighbours: a family without broken bonds is its own
 * list; the intact neighbours of a damaged family are copied a chunk at a time, so the loops
 * never read the 1-byte flags (whose type would force 64-lane vectors and a scalar tail)
 * and skip broken bonds at no cost. */
#define PERI_INTACT_CHUNK 256
static inline int peri_next_intact(const int32_t *neighbor, const uint8_t *broken, int64_t *k, int64_t k1,
                                   int32_t *out) {
  /* branch-free: broken flags of a damaged region are unpredictable */
  int n = 0;
  int64_t kk = *k;
  const int64_t end = k1 - kk < PERI_INTACT_CHUNK ? k1 : kk + PERI_INTACT_CHUNK;
  for (; kk < end; ++kk) {
    out[n] = neighbor[kk];
    n += !broken[kk];
  }
  *k = kk;
  return n;
}

/* The next chunk of node i's intact neighbours (bonds k .. k1-1 of the family): the family
 * itself when it is intact (`damaged` false), else copied into `intact`. Returns the chunk,
 * sets *count (at most PERI_INTACT_CHUNK) and advances *k. */
static inline const int32_t *peri_next_chunk(const peri_bond_view *w, bool damaged, int64_t *k, int64_t k1,
                                             int32_t *intact, int *count) {
  if (damaged) {
    *count = peri_next_intact(w->neighbor, w->broken, k, k1, intact);
    return intact;
  }
  const int n = (int)(k1 - *k < PERI_INTACT_CHUNK ? k1 - *k : PERI_INTACT_CHUNK);
  const int32_t *chunk = w->neighbor + *k;
  *count = n;
  *k += n;
  return chunk;
}

/* Bonds whose mechanical stretch is within this margin of the screening bound are re-checked
 * exactly (scalar) by the breaking pass, so vector rounding never decides a break. */
#define PERI_S0_SCREEN_MARGIN 1e-9

/* Fills p->s0_bound (allocated on first use, n entries) with a lower bound of the critical
 * stretch of every bond of each node: the smallest entry of its material's row of the pair
 * table, or the LAMMPS-form s0 of the node; INFINITY for no-fail nodes. */
void peri_update_s0_bound(peri_sim *s);
/* Whether every node (owned and ghost) has the same volume. */
bool peri_uniform_volume(const peri_particles *p);

/* Publishes the LAMMPS-form critical stretches for the next step, s0_i = s00 - alpha *
 * (min stretch of i's bonds this step), computed in p->smin by the force pass. */
void peri_update_lammps_s0(peri_sim *s);

/* The energy density whose gradient is the peer LPS force state (docs/models.md 3.5), the
 * Madenci-Oterkus / LAMMPS form K_MO theta^2/2 + (alpha_i/2) sum omega e^2 beta V with
 * K_MO = K_theta - (alpha m)(2/(3 n_theta) - 1/9) (K - 5 mu/3 in 3D); sum_e2 is that sum. */
static inline double peri_lps_peer_bulk(const peri_material *mat) {
  return mat->n_theta > 0.0 ? mat->K_theta - mat->alpha_m * (2.0 / (3.0 * mat->n_theta) - 1.0 / 9.0) : 0.0;
}
static inline double peri_lps_peer_energy(const peri_material *mat, double theta, double alpha, double sum_e2) {
  return 0.5 * peri_lps_peer_bulk(mat) * theta * theta + 0.5 * alpha * sum_e2;
}

/* One force evaluation of a model, with the LAMMPS-form critical stretches published at its
 * end when `update_s0`. */
typedef long (*peri_force_pass)(peri_sim *s, bool update_s0);
/* Runs `pass` in the breaking order of s->solver (docs/models.md 5.1): by default the bonds
 * beyond their critical stretch are cut before the force; with break_after_force the force is
 * that of the bonds intact at the start and the cut follows at the same displacement (the
 * critical stretches of the test are those of the previous evaluation either way). Returns
 * the number of directed bonds broken. */
long peri_force_in_breaking_order(peri_sim *s, peri_force_pass pass);

#endif
