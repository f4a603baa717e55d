/* The deviatoric state-based sublayer rule of LPS in 3D (docs/plasticity.md section 8): the
 * overlay of Besseling on Mitchell's ordinary state-based plasticity (Mitchell 2011,
 * SAND2011-3166). Every node keeps, for each directed bond of its family and each sublayer k,
 * a plastic deviatoric stretch s^dp_k (the deviatoric plastic extension e^dp_k over |xi|), in
 * the per-bond, per-sublayer storage of the bond rule (s->state.plastic_stretch), kept in the
 * slots below from the first return on. The
 * deviatoric force state of node i is
 *   t^d_ij = alpha_i omega (e^d_ij - |xi| sum_k W_k s^dp_k,ij),   e^d = e - (theta_i/3) |xi|
 * with theta_i the elastic dilatation of the total extension (the bulk term stays elastic).
 * Sublayer k of node i is elastic-perfectly plastic on the deviatoric energy of its own force
 * state over the family,
 *   S_k = sum_j omega beta V_j |xi|^2 (s^d_ij - s^dp_k,ij)^2  <=  (3 mu / alpha_m) m_i e_yk^2,
 * the von Mises (distortion energy) criterion: in the continuum under a homogeneous
 * deviatoric strain eps^d, S = (2/15) m eps^d : eps^d, and at the uniaxial deviatoric yield
 * strain e_y (axial e_y, lateral -e_y/2) eps^d : eps^d = 3 e_y^2 / 2, so with alpha_m = 15 mu
 * the bound is m e_y^2 / 5. With omega = 1 it is Mitchell's ||t^d||^2 / 2 <= psi_0,
 * psi_0 = 25 sigma_y^2 / (8 pi delta^5). A sublayer beyond it returns radially: its elastic
 * deviatoric stretches s^d - s^dp_k are scaled by sqrt(bound / S_k) on every bond of the
 * family at once, the closest point in the energy norm (associated flow). All bonds of a node
 * therefore yield together.
 *
 * Each end of a bond keeps its own state. The pair force t_ij + t_ji needs the other end's
 * plastic term alpha_j sum_k W_k s^dp_k,ji: each node's return writes its own terms
 * (s->state.plastic_bond_term), and i's force pass reads j's at the reverse bond's slot (a
 * gather, where writing each term into the other end's entry made the return's scattered
 * stores its largest cost). The terms and the state are kept in slots (build_slots,
 * peri_state.plastic_slots): a block of eight nodes keeps its bonds' in its template's order,
 * an entry's eight lanes side by side (the state layer by layer), so that the block loops load
 * and store them as vectors and the other ends' terms of an entry lie in one or two cache
 * lines; the other nodes keep theirs in family order. On MPI ranks the reverse slot of a bond
 * into a ghost points past the slots, where the ghost's owner sends the term through the bond
 * halo (src/parallel/bond_halo.c) after the return. No periodic images (a bond to an image has
 * no reverse).
 *
 * Cost (docs/plasticity.md section 8): a block of eight nodes (node_blocks.h) runs the return
 * and the force on its template, the nodes in vector lanes; other nodes run a chunk of their
 * bonds at a time in vector loops. The lengths come from the eight-lane functions of the
 * elastic kernels (bond_kernel.h: reciprocal square roots, no square root or division, which
 * cost 16-32 cycles a vector) and so do the bond weights omega beta V_j (stored only where
 * those functions cannot evaluate them); the force of the nodes with a plastic state on either
 * end of a bond replaces their elastic force pass rather than adding to it and reads the
 * bonds' terms, not their sublayers. The return streams the state (32 bytes a bond read and
 * written per step with 4 sublayers). The energy of the history rows runs on the same
 * eight-lane arithmetic (block_energy, node_energy). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "peri/bond_halo.h"
#include "peri/decompose.h"
#include "peri/error.h"
#include "peri/plasticity.h"
#include "bond_kernel.h"
#include "node_blocks.h"
#include "plastic_bonds.h"

bool peri_deviatoric_rule(const peri_sim *s) {
  for (int m = 0; m < s->mat.n_materials; ++m)
    if (s->mat.materials[m].sublayers && s->mat.materials[m].sublayers->deviatoric &&
        !s->mat.materials[m].sublayers->tensor)
      return true;
  return false;
}

int peri_deviatoric_init(peri_sim *s) {
  const peri_bonds *b = &s->disc.bonds;
  const peri_particles *p = &s->disc.p;
  int64_t *reverse = peri_malloc(sizeof(int64_t) * (size_t)(b->n_bonds > 0 ? b->n_bonds : 1));
  int32_t missing = -1;
#pragma omp parallel for schedule(static) reduction(max : missing)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      reverse[k] = j < p->n_owned ? peri_bonds_find(b, j, i) : -1;
      if (reverse[k] < 0) missing = i > missing ? i : missing;
    }
  if (missing >= 0) {
    free(reverse);
    peri_error("plasticity.yield_rule deviatoric: node %d at (%g, %g, %g) has a neighbour that is not a node of the "
               "body (a periodic image): the rule reads both ends' state of each bond",
               missing, p->x[3 * missing], p->x[3 * missing + 1], p->x[3 * missing + 2]);
    return PERI_ERR_INPUT;
  }
  s->state.plastic_reverse = reverse;
  /* each bond's omega beta V_j, stored where the eight-lane kernels cannot evaluate it (a
   * Gaussian influence needs exp; the scalar loops have no branch-free form of the influence
   * and the partial volume): they evaluate it from |xi| otherwise (bond_weight_v8), which
   * saves the 8 bytes a bond and their stream, twice a step */
#ifdef PERI_BOND_V8
  if (b->family.influence != PERI_INFLUENCE_GAUSSIAN) return PERI_OK;
#endif
  double *weight = peri_malloc(sizeof(double) * (size_t)(b->n_bonds > 0 ? b->n_bonds : 1));
  const peri_family_eval fam = peri_family_eval_of(b);
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      const double x0 = p->x[3 * j] - p->x[3 * i], x1 = p->x[3 * j + 1] - p->x[3 * i + 1], x2 = p->x[3 * j + 2] - p->x[3 * i + 2];
      const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2);
      weight[k] = peri_eval_omega(&fam, fam.influence, r0) * peri_eval_beta(&fam, r0) * p->volume[j];
    }
  s->state.plastic_bond_weight = weight;
  return PERI_OK;
}

/* The sublayers of node i's material, or NULL for an elastic one. */
static const peri_sublayers *node_layers(const peri_sim *s, int32_t i) {
  return s->mat.materials[s->disc.p.material[i]].sublayers;
}

/* A radial return is taken only beyond the bound by this relative margin: the state it leaves
 * sits on the bound to round-off, and a second evaluation at the same displacement (the
 * breaking order, the energy) must change nothing. */
#define RETURN_MARGIN 1e-10
/* The screen of pass 1's sum (whose lengths come from other arithmetic) keeps this margin. */
#define SCREEN_MARGIN 1e-6

/* The weights W_l of node i's material, 0 beyond its sublayers up to L (the storage's layers
 * per bond), so that loops over the L layers of a bond add nothing for the unused ones. */
static inline void padded_weights(const peri_sublayers *sl, int L, double *W) {
  for (int l = 0; l < L; ++l) W[l] = sl && l < sl->n ? sl->weight[l] : 0.0;
}

/* The bond halo's values: node i's term alpha_i sum_l W_l s^dp_l,ij of each listed bond i -> j,
 * as its return wrote it. */
static void pack_plastic_terms(const void *context, const int64_t *bonds, int64_t n, double *out) {
  const peri_sim *s = context;
  for (int64_t a = 0; a < n; ++a) out[a] = s->state.plastic_bond_term[s->state.plastic_slots.bond_slot[bonds[a]]];
}

/* Bonds per vector loop of the return and the force (a node's family is one or more chunks) */
#define DEVIATORIC_CHUNK 256

#ifdef PERI_BOND_V8
/* The lengths of eight bonds from their offsets (peri_deformed_lengths_v8, bond_kernel.h),
 * with r 0 for coincident ends. */
static inline __attribute__((always_inline)) void offset_lengths_v8(const peri_offset_v8 *o, const peri_v8d uj[3],
                                                                    const peri_v8d cu[3], peri_v8d y[3],
                                                                    peri_v8d *r0, peri_v8d *inv_r0, peri_v8d *r,
                                                                    peri_v8d *inv_r) {
  const peri_v8d r_sq = peri_deformed_lengths_v8(o, uj, cu, true, y, r, inv_r);
  *r = v8_maskz_mov_pd(v8_cmp_pd_mask(r_sq, v8_setzero_pd(), _CMP_GT_OQ), *r);
  *r0 = o->r0, *inv_r0 = o->inv_r0;
}

/* peri_bond_lengths_v8 (bond_kernel.h), with r 0 for coincident ends. */
static inline __attribute__((always_inline)) void bond_lengths_v8(const peri_v8d xj[3], const peri_v8d uj[3],
                                                                  const peri_v8d c[3], const peri_v8d cu[3],
                                                                  peri_v8d y[3], peri_v8d *r0, peri_v8d *inv_r0,
                                                                  peri_v8d *r, peri_v8d *inv_r) {
  const peri_offset_v8 o = peri_offset_of_positions_v8(xj, c, true);
  offset_lengths_v8(&o, uj, cu, y, r0, inv_r0, r, inv_r);
}

/* The same for template entry a of a block (neighbours tj[a] + l, contiguous): the offsets
 * and |xi| from the block's table on a lattice (from_table, the table's indices in table:
 * bond_kernel.h peri_block_offsets), the same numbers as from the positions. from_table is a
 * constant of each copy of the block loops: a source chosen per entry compiles to a branch
 * over both paths in the loop (on an AMD EPYC the elastic LPS block loop took 1.2 times as long). */
static inline __attribute__((always_inline)) void entry_lengths_v8(const peri_bond_view *w, bool from_table,
                                                                   const uint16_t *table,
                                                                   int64_t a, int64_t j, const peri_v8d c[3],
                                                                   const peri_v8d cu[3], const peri_v8d uj[3],
                                                                   peri_v8d y[3], peri_v8d *r0, peri_v8d *inv_r0,
                                                                   peri_v8d *r, peri_v8d *inv_r) {
  if (from_table) {
    const peri_offset_v8 o = peri_offset_of_table_v8(w->geom + (size_t)table[a] * PERI_GEOM_STRIDE, true);
    offset_lengths_v8(&o, uj, cu, y, r0, inv_r0, r, inv_r);
  } else {
    const peri_v8d xj[3] = {v8_loadu_pd(w->x0 + j), v8_loadu_pd(w->x1 + j), v8_loadu_pd(w->x2 + j)};
    bond_lengths_v8(xj, uj, c, cu, y, r0, inv_r0, r, inv_r);
  }
}

/* The table indices of a work item's offsets (peri_block_offsets), or NULL: the block loops
 * below run one copy per source, with from_table (table not NULL) a constant of the copy. */
static inline const uint16_t *item_offsets(const peri_bond_view *w, const peri_node_blocks *items, int32_t item) {
  const int64_t t0 = items->tpl[item];
  return peri_block_offsets(w, items->tpl_node + t0, items->tpl_end[item] - t0);
}

/* The same for the neighbours j of the lanes in m (gathered). */
static inline __attribute__((always_inline)) void gathered_lengths_v8(const peri_bond_view *w, peri_m8 m, peri_v8i j,
                                                                      const peri_v8d c[3], const peri_v8d cu[3],
                                                                      peri_v8d y[3], peri_v8d *r0, peri_v8d *inv_r0,
                                                                      peri_v8d *r, peri_v8d *inv_r) {
  const peri_v8d xj[3] = {v8_mask_i32gather_pd(m, j, w->x0), v8_mask_i32gather_pd(m, j, w->x1),
                          v8_mask_i32gather_pd(m, j, w->x2)};
  const peri_v8d uj[3] = {v8_mask_i32gather_pd(m, j, w->u0), v8_mask_i32gather_pd(m, j, w->u1),
                          v8_mask_i32gather_pd(m, j, w->u2)};
  bond_lengths_v8(xj, uj, c, cu, y, r0, inv_r0, r, inv_r);
}

/* t_ij + t_ji = omega (|xi| (D_i + D_j - alpha_i sum W s^dp_ij - alpha_j sum W s^dp_ji) + e (B_i + B_j))
 * of eight bonds, as the factor g of the force density g y on i (won = omega beta V_j, 0 for a
 * broken bond, P the bond's two plastic terms): the node and the block paths both use it, so
 * they agree bit for bit. Coincident ends have no direction and give no force. */
static inline __attribute__((always_inline)) peri_v8d bond_force_v8(peri_v8d r0, peri_v8d r, peri_v8d inv_r,
                                                                    peri_v8d Di, peri_v8d Dj, peri_v8d Bi, peri_v8d Bj,
                                                                    peri_v8d P, peri_v8d won) {
  const peri_v8d t = v8_fmadd_pd(r0, v8_sub_pd(v8_add_pd(Di, Dj), P), v8_mul_pd(v8_sub_pd(r, r0), v8_add_pd(Bi, Bj)));
  return v8_maskz_mov_pd(v8_cmp_pd_mask(r, v8_setzero_pd(), _CMP_GT_OQ), v8_mul_pd(v8_mul_pd(won, t), inv_r));
}

/* The weights omega beta V_j of eight bonds of lengths r0 (1/r0 in inv_r0), the stored ones
 * (at the bonds' indices k, 0 outside m) where the rule keeps them (peri_deviatoric_init); the
 * node and block paths both take them from here. */
static inline __attribute__((always_inline)) peri_v8d bond_weight_v8(const peri_bond_view *w, const double *weight,
                                                                     peri_m8 m, peri_v8i k, peri_v8d r0,
                                                                     peri_v8d inv_r0, peri_v8d V_j) {
  if (weight) return v8_mask_i32gather_pd(m, k, weight);
  const peri_v8d beta_V = v8_mul_pd(peri_beta_v8(&w->fam, r0), V_j);
  return v8_maskz_mov_pd(m, w->fam.influence == PERI_INFLUENCE_INVERSE ? v8_mul_pd(inv_r0, beta_V) : beta_V);
}

/* Each lane's next bond index along a template: the lanes whose bit of the entry's structure
 * (the bonds intact or broken) is set move on by one. */
static inline __attribute__((always_inline)) peri_v8i lanes_next_bond(peri_v8i k, uint8_t structure) {
  const __m256i lane_shift = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  return _mm256_add_epi32(k, _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32(structure), lane_shift),
                                              _mm256_set1_epi32(1)));
}
#endif

/* Node i's deviatoric stretches s^d = (r - |xi|)/|xi| - eth_i - theta_i/3 and weights
 * omega beta V_j |xi|^2 of its bonds k0 .. k0+n-1 (0 for a broken bond: on[] holds the
 * intact flags as doubles) into sd[] and wt[], arrays of DEVIATORIC_CHUNK. */
static inline __attribute__((always_inline)) void deviatoric_stretches(const peri_sim *s, const peri_bond_view *w,
                                                                       int32_t i, int64_t k0, int n, double shift,
                                                                       const double *restrict on,
                                                                       double *restrict sd, double *restrict wt) {
  const int32_t *restrict nbr = s->disc.bonds.neighbor + k0;
  const double *restrict weight = s->state.plastic_bond_weight ? s->state.plastic_bond_weight + k0 : NULL;
#ifdef PERI_BOND_V8
  /* (each eight-lane load below stays inside the chunk's arrays) */
  const __m256i lane_index = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const peri_v8d c[3] = {v8_set1_pd(w->x0[i]), v8_set1_pd(w->x1[i]), v8_set1_pd(w->x2[i])},
                 cu[3] = {v8_set1_pd(w->u0[i]), v8_set1_pd(w->u1[i]), v8_set1_pd(w->u2[i])};
  const peri_v8d vshift = v8_set1_pd(shift);
  for (int a = 0; a < n; a += 8) {
    const peri_m8 m = peri_first_lanes(n - a);
    const peri_v8i j = v8_maskz_loadu_epi32(m, nbr + a);
    peri_v8d y[3], r0, inv_r0, r, inv_r;
    gathered_lengths_v8(w, m, j, c, cu, y, &r0, &inv_r0, &r, &inv_r);
    const peri_v8d on_a = v8_loadu_pd(on + a);
    const peri_v8d weight_a = bond_weight_v8(w, weight, m, _mm256_add_epi32(_mm256_set1_epi32(a), lane_index), r0,
                                             inv_r0, v8_mask_i32gather_pd(m, j, w->V));
    const peri_v8d sd_a = v8_mul_pd(on_a, v8_fmsub_pd(v8_sub_pd(r, r0), inv_r0, vshift));
    v8_mask_storeu_pd(sd + a, m, sd_a);
    v8_mask_storeu_pd(wt + a, m, v8_mul_pd(v8_mul_pd(on_a, weight_a), v8_mul_pd(r0, r0)));
  }
#else
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2;
  const double xi0 = X0[i], xi1 = X1[i], xi2 = X2[i], ui0 = U0[i], ui1 = U1[i], ui2 = U2[i];
#pragma omp simd
  for (int a = 0; a < n; ++a) {
    const int32_t j = nbr[a];
    const double x0 = X0[j] - xi0, x1 = X1[j] - xi1, x2 = X2[j] - xi2;
    const double d0 = x0 + (U0[j] - ui0), d1 = x1 + (U1[j] - ui1), d2 = x2 + (U2[j] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2), r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    sd[a] = on[a] * ((r - r0) / r0 - shift), wt[a] = on[a] * weight[a] * r0 * r0;
  }
#endif
}

/* Each layer's energy S_l = sum wt (s^d - s^dp_l)^2 over n bonds of the L layers of the state
 * `base`, added to S[] bond by bond in family order (the block path's lanes add them in the
 * same order, so the two agree bit for bit; the layers' sums are independent chains). */
static inline __attribute__((always_inline)) void layer_energies(const double *restrict base,
                                                                 const double *restrict sd,
                                                                 const double *restrict wt, int n, const int L,
                                                                 double *S) {
  for (int a = 0; a < n; ++a)
    for (int l = 0; l < L; ++l) {
      const double e = sd[a] - base[a * L + l];
      S[l] = fma(wt[a], e * e, S[l]);
    }
}

/* The return of a node's bonds from the state `from` into `out` (the same array when mapping in
 * place: one pointer, so that the vector loop needs no test of overlap): layer l moves to
 * s^d - factor[l] (s^d - s^dp_l) where take = flows[l] on = 1 (it flows and the bond is intact),
 * else keeps its value (a select, as the block path's lanes take it); each bond's term
 * alpha sum_l W_l s^dp_l into term[]. Returns whether a plastic stretch (or, `committed`, one of the state mapped
 * from) is nonzero: a sum of magnitudes, 0 only when every one is. */
static inline __attribute__((always_inline)) bool flow_from(const double *from, double *out,
                                                            const double *restrict sd, double *restrict term,
                                                            const double *restrict on, const double *restrict factor,
                                                            const double *restrict flows, const double *restrict W,
                                                            double alpha, int64_t nb, const bool committed,
                                                            const int L) {
  double magnitude = 0.0;
#pragma omp simd reduction(+ : magnitude)
  for (int64_t a = 0; a < nb; ++a) {
    double plastic = 0.0;
    for (int l = 0; l < L; ++l) {
      /* (explicit fused operations, as the block path's lanes evaluate them) */
      const double f = from[a * L + l], moved = fma(-factor[l], sd[a] - f, sd[a]), take = on[a] * flows[l];
      const double v = take != 0.0 ? moved : f;
      out[a * L + l] = v;
      magnitude += fabs(v) + (committed ? fabs(f) : 0.0);
      plastic = fma(W[l], v, plastic);
    }
    term[a] = alpha * plastic;
  }
  return magnitude != 0.0;
}

/* Without flow: each bond's term into term[]; whether a plastic stretch is nonzero. */
static inline __attribute__((always_inline)) bool bond_terms(const double *restrict state, double *restrict term,
                                                             const double *restrict W, double alpha, int64_t nb,
                                                             const int L) {
  double magnitude = 0.0;
#pragma omp simd reduction(+ : magnitude)
  for (int64_t a = 0; a < nb; ++a) {
    double plastic = 0.0;
    for (int l = 0; l < L; ++l) {
      magnitude += fabs(state[a * L + l]);
      plastic = fma(W[l], state[a * L + l], plastic);
    }
    term[a] = alpha * plastic;
  }
  return magnitude != 0.0;
}

/* Each layer's radial factor sqrt(bound / S_l) beyond its bound (else 1) and whether it flows
 * (1.0 or 0.0) from the energies S[] of a node whose bounds are scale e_yl^2; returns whether
 * a layer flows. */
static inline bool layer_factors(const peri_sublayers *sl, double scale, const double *S, int L, double *factor,
                                 double *flows) {
  bool flow = false;
  for (int l = 0; l < L; ++l) {
    const double bound = l < sl->n ? scale * sl->yield[l] * sl->yield[l] : INFINITY;
    factor[l] = S[l] > bound * (1.0 + RETURN_MARGIN) ? sqrt(bound / S[l]) : 1.0;
    flows[l] = factor[l] < 1.0 ? 1.0 : 0.0;
    flow |= factor[l] < 1.0;
  }
  return flow;
}

/* The return mapping of node i's sublayers (from the committed state in quasi-static load
 * steps, else in place), L layers stored per bond (a constant for the common counts: the
 * layers of a bond are then unrolled in vector loops over the bonds). Returns whether a
 * plastic stretch of the node (or a committed one) is nonzero. Node i's terms alpha_i sum_l
 * W_l s^dp_l,ij go into its bonds' entries of s->state.plastic_bond_term (0 for a node without
 * a plastic state; a node that skips the return keeps its zeros). Scratch: sd, wt, on of the
 * longest family, rounded up to a multiple of 8. */
static inline __attribute__((always_inline)) bool node_return(peri_sim *s, const peri_bond_view *w, int32_t i,
                                                              double elastic, bool before, double *restrict sd,
                                                              double *restrict wt, double *restrict on,
                                                              double *restrict term, double *restrict rows,
                                                              const int L) {
  const peri_sublayers *sl = node_layers(s, i);
  if (!sl) return false;
  const peri_bonds *b = &s->disc.bonds;
  const peri_material *mat = &s->mat.materials[s->disc.p.material[i]];
  const int64_t k0 = b->offset[i], nb = b->offset[i + 1] - k0;
  const bool committed = s->state.plastic_committed != NULL;
  /* the bound of sublayer k is (3 mu / alpha_m) m_i e_yk^2 */
  const double scale = 3.0 * mat->mu / mat->alpha_m * s->disc.p.wvol[i];
  /* every plastic stretch 0 and the elastic deviatoric energy of pass 1 below the first
   * yield (with a margin for that sum's rounding; nearer, the exact sums below decide) */
  if (!before && elastic <= scale * sl->yield[0] * sl->yield[0] * (1.0 - SCREEN_MARGIN)) return false;
  double S[PERI_MAX_SUBLAYERS > 4 ? PERI_MAX_SUBLAYERS : 4] = {0}, factor[PERI_MAX_SUBLAYERS],
      flows[PERI_MAX_SUBLAYERS], W[PERI_MAX_SUBLAYERS];
  /* the node's state as rows of L layers, bond by bond: in place for a node outside the blocks
   * (its slots in family order, block_slots and on), else copied out of the block's slots (a
   * bond's layers 8 apart) into rows[] (and the committed state's after them) and back */
  const int64_t *restrict slot = s->state.plastic_slots.bond_slot + k0;
  const int64_t block_slots = s->state.plastic_slots.block_slots;
  const int64_t first = nb > 0 ? slot[0] : block_slots;
  const bool in_place = first >= block_slots;
  double *restrict state = s->state.plastic_stretch, *restrict out = in_place ? state + first * L : rows;
  const double *base = committed ? s->state.plastic_committed + first * L : out;
  if (!in_place) {
    for (int64_t a = 0; a < nb; ++a)
      for (int l = 0; l < L; ++l) out[a * L + l] = state[peri_plastic_layer_index(slot[a], l, L, block_slots)];
    if (committed) {
      base = rows + nb * L;
      for (int64_t a = 0; a < nb; ++a)
        for (int l = 0; l < L; ++l)
          rows[(nb + a) * L + l] = s->state.plastic_committed[peri_plastic_layer_index(slot[a], l, L, block_slots)];
    }
  }
  const uint8_t *restrict broken = b->broken + k0;
  /* the 1-byte flags as doubles first: read in the vector loops they would force 64-lane
   * vectors and a scalar tail (bond_kernel.h) */
  for (int64_t a = 0; a < nb; ++a) on[a] = broken[a] ? 0.0 : 1.0;
  deviatoric_stretches(s, w, i, k0, (int)nb, (w->eth ? w->eth[i] : 0.0) + s->disc.p.theta[i] / 3.0, on, sd, wt);
  layer_energies(base, sd, wt, (int)nb, L, S);
  const bool flow = layer_factors(sl, scale, S, L, factor, flows) || committed;
  padded_weights(sl, L, W);
  const double alpha = s->disc.p.coef[(size_t)s->disc.p.n + (size_t)i];
  /* the new state (a broken bond keeps its own) and each bond's term, in family order into
   * term[], then to the terms' slots */
  const bool plastic = !flow      ? bond_terms(out, term, W, alpha, nb, L)
                       : committed ? flow_from(base, out, sd, term, on, factor, flows, W, alpha, nb, true, L)
                                   : flow_from(out, out, sd, term, on, factor, flows, W, alpha, nb, false, L);
  double *restrict all_terms = s->state.plastic_bond_term;
  for (int64_t a = 0; a < nb; ++a) all_terms[slot[a]] = term[a];
  if (flow && !in_place)
    for (int64_t a = 0; a < nb; ++a)
      for (int l = 0; l < L; ++l) state[peri_plastic_layer_index(slot[a], l, L, block_slots)] = out[a * L + l];
  return plastic;
}

/* node_return with constant layer counts for the common ones. */
static bool node_return_any(peri_sim *s, const peri_bond_view *w, int32_t i, double elastic, bool before,
                            double *scratch, int64_t longest) {
  double *sd = scratch, *wt = scratch + longest, *on = scratch + 2 * longest, *term = scratch + 3 * longest,
         *rows = scratch + 4 * longest;
  switch (s->state.plastic_layers) {
  case 1: return node_return(s, w, i, elastic, before, sd, wt, on, term, rows, 1);
  case 2: return node_return(s, w, i, elastic, before, sd, wt, on, term, rows, 2);
  case 3: return node_return(s, w, i, elastic, before, sd, wt, on, term, rows, 3);
  case 4: return node_return(s, w, i, elastic, before, sd, wt, on, term, rows, 4);
  default: return node_return(s, w, i, elastic, before, sd, wt, on, term, rows, s->state.plastic_layers);
  }
}

#ifdef PERI_BOND_V8
/* The return reads its block's state as one stream, L cache lines a template entry (the state in
 * slots, peri_plastic_layer_index), and asks for the lines this many entries ahead: the
 * hardware's prefetch did not keep up with it on Zen 5, and 8 or 32 entries were 5% slower
 * (docs/plasticity.md section 8). */
#define STATE_ENTRIES_AHEAD 16
/* The force asks for its terms ahead too: the own terms and reverse slots (one stream each)
 * this many entries ahead, the other ends' terms (one or two lines an entry) this many */
#define TERMS_AHEAD 16
#define OTHER_TERMS_AHEAD 4

/* The return of a block of eight nodes of one material (node_blocks.h) on its template, the
 * nodes in vector lanes: contiguous loads of the neighbours (the node path gathers them) and of
 * the state and terms in their slots, each lane's bond index counted along the template (its
 * bit of the structure) to reach a stored weight in family order. Each lane evaluates
 * node_return's operations in its order (the energies bond by bond, the factors by
 * layer_factors), so both paths agree bit for bit.
 * Returns false, having changed nothing, where the block cannot take it (entries dropped from
 * its template, nodes of different materials, more than 4 layers); else sets yielded[] of its
 * nodes. Scratch: 48 doubles per template entry and 8 more (the lanes' stretches, which the
 * second loop reads instead of evaluating the lengths again; it reads the state again from
 * the cache). */
static inline __attribute__((always_inline)) bool block_return(peri_sim *s, const peri_bond_view *w,
                                                               const peri_node_blocks *items, int32_t item,
                                                               const double *elastic, uint8_t *yielded,
                                                               double *restrict scratch, const int L,
                                                               const uint16_t *restrict table,
                                                               const bool from_table) {
  if (L > 4 || items->tpl_end[item] != items->tpl[item + 1]) return false;
  const peri_particles *p = &s->disc.p;
  const int32_t i0 = items->first[item];
  for (int l = 1; l < PERI_BLOCK; ++l)
    if (p->material[i0 + l] != p->material[i0]) return false;
  const peri_sublayers *sl = node_layers(s, i0);
  if (!sl) {
    memset(yielded + i0, 0, PERI_BLOCK);
    return true;
  }
  const peri_material *mat = &s->mat.materials[p->material[i0]];
  const bool committed = s->state.plastic_committed != NULL;
  const int64_t t0 = items->tpl[item], count = items->tpl_end[item] - t0, base = w->offset[i0];
  double *restrict sd_of = scratch;
  /* the state and the terms in template order (build_slots; slot0 a multiple of 8): entry a's
   * lanes' layer l at out + 8 (L a + l), their terms at term + 8 a */
  const int64_t slot0 = s->state.plastic_slots.item_slot[item];
  double *out = s->state.plastic_stretch + slot0 * L; /* (from is out when mapping in place) */
  const double *from = committed ? s->state.plastic_committed + slot0 * L : out;
  const double *restrict weight = s->state.plastic_bond_weight ? s->state.plastic_bond_weight + base : NULL;
  double *restrict term = s->state.plastic_bond_term + slot0;
  double scale[PERI_BLOCK], shift[PERI_BLOCK], alpha[PERI_BLOCK];
  int32_t first[PERI_BLOCK];
  unsigned act = 0;
  for (int l = 0; l < PERI_BLOCK; ++l) {
    const int32_t i = i0 + l;
    scale[l] = 3.0 * mat->mu / mat->alpha_m * p->wvol[i];
    /* node_return's screen: a lane that skips the return keeps its state and terms */
    if (yielded[i] || !(elastic[i] <= scale[l] * sl->yield[0] * sl->yield[0] * (1.0 - SCREEN_MARGIN))) act |= 1u << l;
    else yielded[i] = 0;
    shift[l] = (w->eth ? w->eth[i] : 0.0) + p->theta[i] / 3.0;
    alpha[l] = p->coef[(size_t)p->n + (size_t)i];
    first[l] = (int32_t)(w->offset[i] - base);
  }
  if (!act) return true;
  const peri_m8 active = (peri_m8)act;
  const int32_t *restrict tj = items->tpl_node + t0;
  const uint8_t *restrict lanes = items->tpl_lanes + t0, *restrict structure = items->tpl_bonds + t0;
  const peri_v8d c[3] = {v8_loadu_pd(w->x0 + i0), v8_loadu_pd(w->x1 + i0), v8_loadu_pd(w->x2 + i0)},
                 cu[3] = {v8_loadu_pd(w->u0 + i0), v8_loadu_pd(w->u1 + i0), v8_loadu_pd(w->u2 + i0)};
  const peri_v8d vshift = v8_loadu_pd(shift), one = v8_set1_pd(1.0), zero = v8_setzero_pd();
  /* 1. the lanes' deviatoric stretches and each layer's energy */
  peri_v8d S[4] = {zero, zero, zero, zero};
  peri_v8i k = _mm256_loadu_si256((const __m256i *)first);
  for (int64_t a = 0; a < count; ++a) {
    const int64_t j = tj[a];
    const peri_m8 m = structure[a] & active;
    peri_prefetch_next_blocks(w, j, !from_table);
    const peri_v8d uj[3] = {v8_loadu_pd(w->u0 + j), v8_loadu_pd(w->u1 + j), v8_loadu_pd(w->u2 + j)};
    peri_v8d y[3], r0, inv_r0, r, inv_r;
    entry_lengths_v8(w, from_table, table, a, j, c, cu, uj, y, &r0, &inv_r0, &r, &inv_r);
    /* (deviatoric_stretches' operations: the intact flags as 1.0 or 0.0) */
    const peri_v8d on = v8_maskz_mov_pd(lanes[a], one);
    const peri_v8d wt =
        v8_mul_pd(v8_mul_pd(on, bond_weight_v8(w, weight, m, k, r0, inv_r0, v8_loadu_pd(w->V + j))), v8_mul_pd(r0, r0));
    const peri_v8d sd = v8_mul_pd(on, v8_fmsub_pd(v8_sub_pd(r, r0), inv_r0, vshift));
    v8_storeu_pd(sd_of + 8 * a, sd);
    peri_v8d f[4];
    {
      const int64_t ahead = a + STATE_ENTRIES_AHEAD < count ? a + STATE_ENTRIES_AHEAD : count - 1; /* (in the block) */
      for (int l = 0; l < L; ++l) _mm_prefetch((const char *)(from + PERI_BLOCK * (L * ahead + l)), _MM_HINT_T0);
    }
    for (int l = 0; l < L; ++l) f[l] = v8_maskz_mov_pd(m, v8_loadu_pd(from + PERI_BLOCK * (L * a + l)));
    for (int l = 0; l < L; ++l) {
      const peri_v8d e = v8_sub_pd(sd, f[l]);
      S[l] = v8_mask3_fmadd_pd(wt, v8_mul_pd(e, e), S[l], m);
    }
    k = lanes_next_bond(k, structure[a]);
  }
  /* 2. each lane's factors; the lanes whose layer l flows in flows[l] */
  double S_of[4][PERI_BLOCK], factor_of[4][PERI_BLOCK];
  for (int l = 0; l < L; ++l) v8_storeu_pd(S_of[l], S[l]);
  unsigned flowing = 0, flows[4] = {0, 0, 0, 0};
  for (int lane = 0; lane < PERI_BLOCK; ++lane) {
    double S_lane[4], factor[4] = {1.0, 1.0, 1.0, 1.0}, flows_lane[4] = {0.0, 0.0, 0.0, 0.0};
    for (int l = 0; l < L; ++l) S_lane[l] = S_of[l][lane];
    if (act >> lane & 1u)
      if (layer_factors(sl, scale[lane], S_lane, L, factor, flows_lane) || committed) flowing |= 1u << lane;
    for (int l = 0; l < L; ++l) {
      factor_of[l][lane] = factor[l];
      if (flows_lane[l] != 0.0) flows[l] |= 1u << lane;
    }
  }
  /* 3. the new state of the lanes that flow (node_return's flow_from; the others keep theirs, as
   * its bond_terms) and every lane's terms; whether a lane's state is nonzero from the bits of
   * its values or'ed together (a sum of magnitudes in the node path: the same test) */
  double W[PERI_MAX_SUBLAYERS];
  padded_weights(sl, L, W);
  peri_v8d vfactor[4];
  for (int l = 0; l < L; ++l) vfactor[l] = v8_loadu_pd(factor_of[l]);
  const peri_v8d valpha = v8_loadu_pd(alpha);
  peri_v8d bits = zero;
  for (int64_t a = 0; a < count; ++a) {
    const peri_m8 m = structure[a] & active;
    const peri_v8d sd = v8_loadu_pd(sd_of + 8 * a);
    peri_v8d plastic = zero, v[4];
    for (int l = 0; l < L; ++l) {
      /* (the entry's state again, from the cache: the first loop read it) */
      const peri_v8d f = v8_maskz_mov_pd(m, v8_loadu_pd(from + PERI_BLOCK * (L * a + l)));
      const peri_v8d moved = v8_fnmadd_pd(vfactor[l], v8_sub_pd(sd, f), sd);
      v[l] = v8_mask_mov_pd(f, (peri_m8)(flows[l] & lanes[a]), moved);
      bits = v8_mask_mov_pd(bits, m, v8_or_pd(bits, committed ? v8_or_pd(v[l], f) : v[l]));
      plastic = v8_fmadd_pd(v8_set1_pd(W[l]), v[l], plastic);
    }
    v8_mask_storeu_pd(term + PERI_BLOCK * a, m, v8_mul_pd(valpha, plastic));
    for (int l = 0; l < L; ++l) v8_mask_storeu_pd(out + PERI_BLOCK * (L * a + l), (peri_m8)(m & flowing), v[l]);
  }
  const peri_m8 nonzero = v8_cmp_pd_mask(v8_abs_pd(bits), zero, _CMP_NEQ_UQ);
  for (int lane = 0; lane < PERI_BLOCK; ++lane)
    if (act >> lane & 1u) yielded[i0 + lane] = nonzero >> lane & 1u;
  return true;
}

/* block_return with constant layer counts. */
static bool block_return_any(peri_sim *s, const peri_bond_view *w, const peri_node_blocks *items, int32_t item,
                             const double *elastic, uint8_t *yielded, double *scratch) {
  const uint16_t *table = item_offsets(w, items, item);
#define BLOCK_RETURN(L)                                                                                          \
  (table ? block_return(s, w, items, item, elastic, yielded, scratch, L, table, true)                            \
         : block_return(s, w, items, item, elastic, yielded, scratch, L, NULL, false))
  switch (s->state.plastic_layers) {
  case 1: return BLOCK_RETURN(1);
  case 2: return BLOCK_RETURN(2);
  case 3: return BLOCK_RETURN(3);
  case 4: return BLOCK_RETURN(4);
  default: return false;
  }
#undef BLOCK_RETURN
}
#endif

/* The longest family, rounded up to a multiple of 8 (the eight-lane loops' scratch). */
static int64_t longest_family(const peri_bonds *b, int32_t n) {
  const int64_t longest = peri_bonds_longest_family(b, n);
  return longest > 0 ? (longest + 7) / 8 * 8 : 8;
}

/* Whether block item `item` keeps its bonds' terms in template order: its whole template, no
 * entry dropped, as the block loops take it (a block compacted later leaves its terms where
 * they are to the node loops; one compacted now is whole again only after a new build). Each
 * lane's bonds are then its entries with its bit of the structure set, in family order. */
static bool template_order(const peri_node_blocks *items, int32_t item) {
  return peri_item_is_block(items, item) && items->tpl_end[item] == items->tpl[item + 1];
}

/* The state `rows` (bond k's layers at k L .. k L + L - 1) in the slots' order of bond_slot
 * (peri_plastic_layer_index), in an array of n_slots rounded up to 8; `rows` freed. */
static double *rows_to_slots(double *rows, const int64_t *bond_slot, int64_t block_slots, int64_t n_bonds,
                             int64_t n_slots, int L) {
  const size_t size = (size_t)(((n_slots + 7) & ~(int64_t)7) * L + 1);
  bool plastic = false; /* (a state at rest, every run's start: freed first, so the memory never holds both) */
#pragma omp parallel for schedule(static) reduction(|| : plastic)
  for (int64_t k = 0; k < n_bonds * L; ++k) plastic = plastic || rows[k] != 0.0;
  if (!plastic) {
    free(rows);
    return peri_calloc_aligned(size, sizeof(double));
  }
  double *slots = peri_calloc_aligned(size, sizeof(double));
#pragma omp parallel for schedule(static)
  for (int64_t k = 0; k < n_bonds; ++k)
    for (int l = 0; l < L; ++l) slots[peri_plastic_layer_index(bond_slot[k], l, L, block_slots)] = rows[k * L + l];
  free(rows);
  return slots;
}

/* The inverse: the state in slots back into bond rows; `slots` freed. */
static double *slots_to_rows(double *slots, const int64_t *bond_slot, int64_t block_slots, int64_t n_bonds, int L) {
  double *rows = peri_calloc_aligned((size_t)(n_bonds * L + 1), sizeof(double));
#pragma omp parallel for schedule(static)
  for (int64_t k = 0; k < n_bonds; ++k)
    for (int l = 0; l < L; ++l) rows[k * L + l] = slots[peri_plastic_layer_index(bond_slot[k], l, L, block_slots)];
  free(slots);
  return rows;
}

void peri_plastic_state_in_bond_order(peri_sim *s) {
  struct peri_plastic_slots *t = &s->state.plastic_slots;
  if (!t->state_in_slots) return;
  const int64_t n_bonds = s->disc.bonds.n_bonds;
  const int L = s->state.plastic_layers;
  s->state.plastic_stretch = slots_to_rows(s->state.plastic_stretch, t->bond_slot, t->block_slots, n_bonds, L);
  if (s->state.plastic_committed)
    s->state.plastic_committed = slots_to_rows(s->state.plastic_committed, t->bond_slot, t->block_slots, n_bonds, L);
  t->state_in_slots = false;
}

/* The slots of the plastic state and terms (peri_state.plastic_slots) for the node blocks'
 * items: a block's first slot a multiple of 8, so that an entry's lanes fill one 64-byte line
 * of terms and L of state. The state (and its committed copy) is moved into them; the terms
 * start at zero: the return writes every term of a node that has a plastic state before
 * anything reads them, and the others' are 0. */
static void build_slots(peri_sim *s, const peri_node_blocks *items) {
  const peri_bonds *b = &s->disc.bonds;
  const int64_t n_bonds = b->n_bonds;
  struct peri_plastic_slots *t = &s->state.plastic_slots;
  peri_plastic_state_in_bond_order(s); /* (from the slots of an earlier build of the items) */
  free(t->item_slot), free(t->bond_slot), free(t->entry_reverse);
  t->item_slot = peri_malloc(sizeof(int64_t) * ((size_t)items->n_items + 1)); /* (one more for no items) */
  uint8_t *in_order = peri_malloc((size_t)items->n_items + 1);
  int64_t slots = 0;
  for (int32_t item = 0; item < items->n_items; ++item)
    if ((in_order[item] = template_order(items, item))) {
      t->item_slot[item] = slots;
      slots += PERI_BLOCK * (items->tpl[item + 1] - items->tpl[item]);
    }
  t->block_slots = slots; /* (a multiple of 8) */
  for (int32_t item = 0; item < items->n_items; ++item)
    if (!in_order[item]) {
      t->item_slot[item] = slots;
      slots += b->offset[items->first[item + 1]] - b->offset[items->first[item]];
    }
  t->n_slots = slots;
  t->bond_slot = peri_malloc(sizeof(int64_t) * (size_t)(n_bonds > 0 ? n_bonds : 1));
#pragma omp parallel for schedule(dynamic, 64)
  for (int32_t item = 0; item < items->n_items; ++item) {
    const int32_t i0 = items->first[item];
    if (in_order[item]) {
      int64_t k[PERI_BLOCK];
      for (int l = 0; l < PERI_BLOCK; ++l) k[l] = b->offset[i0 + l];
      const int64_t t0 = items->tpl[item];
      for (int64_t a = 0; a < items->tpl[item + 1] - t0; ++a)
        for (int l = 0; l < PERI_BLOCK; ++l)
          if (items->tpl_bonds[t0 + a] >> l & 1) t->bond_slot[k[l]++] = t->item_slot[item] + PERI_BLOCK * a + l;
    } else {
      const int64_t k0 = b->offset[i0];
      for (int64_t k = k0; k < b->offset[items->first[item + 1]]; ++k) t->bond_slot[k] = t->item_slot[item] + (k - k0);
    }
  }
  free(in_order);
  t->entry_reverse = peri_calloc((size_t)(slots > 0 ? slots : 1), sizeof(int64_t));
  const int64_t *restrict reverse = s->state.plastic_reverse;
#pragma omp parallel for schedule(static)
  for (int64_t k = 0; k < n_bonds; ++k)
    /* (a bond into a ghost: its entry past the slots, where the bond halo puts the ghost's term) */
    t->entry_reverse[t->bond_slot[k]] =
        reverse[k] < n_bonds ? t->bond_slot[reverse[k]] : slots + (reverse[k] - n_bonds);
  free(s->state.plastic_bond_term);
  s->state.plastic_bond_term = peri_calloc_aligned((size_t)(slots + (s->par.dd ? n_bonds : 0) + 1), sizeof(double));
  const int L = s->state.plastic_layers;
  s->state.plastic_stretch = rows_to_slots(s->state.plastic_stretch, t->bond_slot, t->block_slots, n_bonds, slots, L);
  if (s->state.plastic_committed)
    s->state.plastic_committed =
        rows_to_slots(s->state.plastic_committed, t->bond_slot, t->block_slots, n_bonds, slots, L);
  t->state_in_slots = true;
  t->generation = items->generation;
}

void peri_deviatoric_return(peri_sim *s, const double *elastic, uint8_t *near) {
  if (!s->state.plastic_nodes) peri_plastic_flag_nodes(s);
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const peri_bond_view w = peri_bond_view_of(s, s->disc.node_blocks->soa);
  const int64_t longest = longest_family(b, p->n_owned);
  uint8_t *yielded = s->state.plastic_nodes;
  const peri_node_blocks *items = s->disc.node_blocks;
  if (s->state.plastic_slots.generation != items->generation || !s->state.plastic_slots.state_in_slots)
    build_slots(s, items);
#pragma omp parallel
  {
    /* the node path's sd, wt, on, term and rows (two states), then the block path's stretches
     * (a template has at most 1.5 times the entries of its largest family, node_blocks.c) */
    const int64_t node_scratch = (4 + 2 * (int64_t)s->state.plastic_layers) * longest;
    double *scratch = peri_malloc(sizeof(double) * (size_t)(node_scratch + 48 * 2 * longest));
    PERI_FOR_EACH_ITEM(items, item) {
#ifdef PERI_BOND_V8
      if (peri_item_is_block(items, item) &&
          block_return_any(s, &w, items, item, elastic, yielded, scratch + node_scratch))
        continue;
#endif
      for (int32_t i = items->first[item]; i < items->first[item + 1]; ++i)
        yielded[i] = node_return_any(s, &w, i, elastic[i], yielded[i], scratch, longest);
    }
    free(scratch);
  }
  /* the other ends' terms of the bonds into ghosts, past the owned bonds' (their reverse index) */
  if (s->par.dd)
    peri_bond_halo_exchange(s->par.dd->bond_halo, pack_plastic_terms, s,
                            s->state.plastic_bond_term + s->state.plastic_slots.n_slots);
  /* whether the node has a plastic state or a bond with the other end's plastic term (else
   * its force is the elastic one) */
  const double *restrict term = s->state.plastic_bond_term;
  const int64_t *restrict slot = s->state.plastic_slots.bond_slot,
                         *restrict reverse = s->state.plastic_slots.entry_reverse;
#pragma omp parallel for schedule(static)
  for (int32_t i = 0; i < p->n_owned; ++i) {
    if (yielded[i]) {
      near[i] = 1;
      continue;
    }
    /* only a neighbour with a plastic state has nonzero terms (a node without one has written
     * zeros or skipped its return, keeping them); a ghost's state is its owner's */
    bool plastic_neighbour = false;
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) {
      const int32_t j = b->neighbor[k];
      plastic_neighbour |= j >= p->n_owned || yielded[j];
    }
    if (!plastic_neighbour) {
      near[i] = 0;
      continue;
    }
    double other = 0.0; /* (a sum of magnitudes, which keeps the loop a vector one: 0 only when every term is) */
#pragma omp simd reduction(+ : other)
    for (int64_t k = b->offset[i]; k < b->offset[i + 1]; ++k) other += fabs(term[reverse[slot[k]]]);
    near[i] = other != 0.0;
  }
}

/* Node i's force over bonds k0 .. k0+n-1 of its family: the bond values by a vector loop,
 * their sums in family order into f. */
static void force_chunk(const peri_sim *s, const peri_bond_view *w, int32_t i, int64_t k0, int n, double f[3]) {
  const size_t nn = (size_t)w->n;
  const int32_t *restrict nbr = w->neighbor + k0;
  const uint8_t *restrict broken = w->broken + k0;
  const int64_t *restrict own = s->state.plastic_slots.bond_slot + k0,
                         *restrict reverse = s->state.plastic_slots.entry_reverse;
  const double *restrict all_terms = s->state.plastic_bond_term,
                         *restrict weight = s->state.plastic_bond_weight ? s->state.plastic_bond_weight + k0 : NULL;
  const double *restrict D = w->coef, *restrict B = w->coef + nn;
  const double Di = D[i], Bi = B[i];
  /* (the chunk's own arrays: every eight-lane load stays inside them) */
  double g[DEVIATORIC_CHUNK], y0[DEVIATORIC_CHUNK], y1[DEVIATORIC_CHUNK], y2[DEVIATORIC_CHUNK],
      won[DEVIATORIC_CHUNK], plastic[DEVIATORIC_CHUNK];
  for (int a = 0; a < n; ++a) {
    won[a] = broken[a] ? 0.0 : 1.0; /* (the flags as doubles: see node_return) */
    plastic[a] = all_terms[own[a]] + all_terms[reverse[own[a]]]; /* (the other end's: a gather) */
  }
#ifdef PERI_BOND_V8
  const __m256i lane_index = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const peri_v8d c[3] = {v8_set1_pd(w->x0[i]), v8_set1_pd(w->x1[i]), v8_set1_pd(w->x2[i])},
                 cu[3] = {v8_set1_pd(w->u0[i]), v8_set1_pd(w->u1[i]), v8_set1_pd(w->u2[i])};
  const peri_v8d vDi = v8_set1_pd(Di), vBi = v8_set1_pd(Bi);
  for (int a = 0; a < n; a += 8) {
    const peri_m8 m = peri_first_lanes(n - a);
    const peri_v8i j = v8_maskz_loadu_epi32(m, nbr + a);
    peri_v8d y[3], r0, inv_r0, r, inv_r;
    gathered_lengths_v8(w, m, j, c, cu, y, &r0, &inv_r0, &r, &inv_r);
    /* the weights of the intact bonds, 0 for the broken ones (as the block path masks them) */
    const peri_m8 intact = v8_mask_cmp_pd_mask(m, v8_loadu_pd(won + a), v8_setzero_pd(), _CMP_NEQ_OQ);
    const peri_v8d wv = bond_weight_v8(w, weight, intact, _mm256_add_epi32(_mm256_set1_epi32(a), lane_index), r0,
                                       inv_r0, v8_mask_i32gather_pd(m, j, w->V));
    const peri_v8d gv = bond_force_v8(r0, r, inv_r, vDi, v8_mask_i32gather_pd(m, j, D), vBi,
                                      v8_mask_i32gather_pd(m, j, B), v8_loadu_pd(plastic + a), wv);
    v8_mask_storeu_pd(g + a, m, gv);
    v8_mask_storeu_pd(y0 + a, m, y[0]);
    v8_mask_storeu_pd(y1 + a, m, y[1]);
    v8_mask_storeu_pd(y2 + a, m, y[2]);
  }
#else
  const double *restrict X0 = w->x0, *restrict X1 = w->x1, *restrict X2 = w->x2, *restrict U0 = w->u0,
                         *restrict U1 = w->u1, *restrict U2 = w->u2;
  const double xi0 = X0[i], xi1 = X1[i], xi2 = X2[i], ui0 = U0[i], ui1 = U1[i], ui2 = U2[i];
#pragma omp simd
  for (int a = 0; a < n; ++a) {
    const int32_t j = nbr[a];
    const double x0 = X0[j] - xi0, x1 = X1[j] - xi1, x2 = X2[j] - xi2;
    const double d0 = x0 + (U0[j] - ui0), d1 = x1 + (U1[j] - ui1), d2 = x2 + (U2[j] - ui2);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2), r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    /* t_ij + t_ji = omega (|xi| (D_i + D_j - alpha_i sum W s^dp_ij - alpha_j sum W s^dp_ji) + e (B_i + B_j)) */
    const double t = fma(r0, (Di + D[j]) - plastic[a], (r - r0) * (Bi + B[j]));
    /* coincident ends have no direction and give no force (arithmetic, not a select, which
     * would keep the loop scalar) */
    const double apart = r != 0.0;
    g[a] = apart * (won[a] * weight[a]) * t / (r + (1.0 - apart)); /* (the weights are stored here) */
    y0[a] = d0, y1[a] = d1, y2[a] = d2;
  }
#endif
  for (int a = 0; a < n; ++a) {
    f[0] = fma(g[a], y0[a], f[0]);
    f[1] = fma(g[a], y1[a], f[1]);
    f[2] = fma(g[a], y2[a], f[2]);
  }
}

void peri_deviatoric_node_force(const peri_sim *s, const peri_bond_view *w, int32_t i, double f[3]) {
  f[0] = f[1] = f[2] = 0.0;
  const int64_t k1 = w->offset[i + 1];
  for (int64_t k = w->offset[i]; k < k1; k += DEVIATORIC_CHUNK)
    force_chunk(s, w, i, k, (int)(k1 - k < DEVIATORIC_CHUNK ? k1 - k : DEVIATORIC_CHUNK), f);
}

#ifdef PERI_BOND_V8
static inline __attribute__((always_inline)) bool block_force(const peri_sim *s, const peri_bond_view *w,
                                                              const peri_node_blocks *items, int32_t item,
                                                              double f[PERI_BLOCK][3], const uint16_t *restrict table,
                                                              const bool from_table) {
  /* a lane's bonds are its template entries with its bit of the structure set, in family
   * order: counting them gives each lane's bond index, unless entries were dropped */
  if (items->tpl_end[item] != items->tpl[item + 1]) return false;
  const int32_t i0 = items->first[item];
  const int64_t t0 = items->tpl[item], count = items->tpl_end[item] - t0, base = w->offset[i0];
  const int32_t *restrict tj = items->tpl_node + t0;
  const uint8_t *restrict lanes = items->tpl_lanes + t0, *restrict structure = items->tpl_bonds + t0;
  const size_t nn = (size_t)w->n;
  const double *restrict D = w->coef, *restrict B = w->coef + nn;
  /* the terms in template order (build_slots): entry a's own at term + 8 a, the other
   * ends' at the slots reverse[8 a + lane] */
  const int64_t slot0 = s->state.plastic_slots.item_slot[item];
  const double *restrict all_terms = s->state.plastic_bond_term, *restrict term = all_terms + slot0,
                         *restrict weight = s->state.plastic_bond_weight ? s->state.plastic_bond_weight + base : NULL;
  const int64_t *restrict reverse = s->state.plastic_slots.entry_reverse + slot0;
  int32_t first[PERI_BLOCK];
  for (int l = 0; l < PERI_BLOCK; ++l) first[l] = (int32_t)(w->offset[i0 + l] - base);
  peri_v8i k = _mm256_loadu_si256((const __m256i *)first);
  const peri_v8d c[3] = {v8_loadu_pd(w->x0 + i0), v8_loadu_pd(w->x1 + i0), v8_loadu_pd(w->x2 + i0)},
                 cu[3] = {v8_loadu_pd(w->u0 + i0), v8_loadu_pd(w->u1 + i0), v8_loadu_pd(w->u2 + i0)};
  const peri_v8d Di = v8_loadu_pd(D + i0), Bi = v8_loadu_pd(B + i0);
  peri_v8d s0 = v8_setzero_pd(), s1 = v8_setzero_pd(), s2 = v8_setzero_pd();
  for (int64_t a = 0; a < count; ++a) {
    const int64_t j = tj[a];
    const peri_m8 on = lanes[a];
    peri_prefetch_next_blocks(w, j, !from_table);
    const peri_v8d uj[3] = {v8_loadu_pd(w->u0 + j), v8_loadu_pd(w->u1 + j), v8_loadu_pd(w->u2 + j)};
    peri_v8d y[3], r0, inv_r0, r, inv_r;
    entry_lengths_v8(w, from_table, table, a, j, c, cu, uj, y, &r0, &inv_r0, &r, &inv_r);
    /* the bond's two plastic terms, the other end's at the reverse bond's slot (as the node path
     * adds them); a lane without the bond takes 0 */
    {
      /* asked for ahead (in the block): the entry's own terms and reverse slots, and the other
       * ends' terms of a nearer entry, whose slots are then in the cache (its first and last
       * lanes': the one or two lines of the eight) */
      const int64_t ahead = a + TERMS_AHEAD < count ? a + TERMS_AHEAD : count - 1,
                    near = PERI_BLOCK * (a + OTHER_TERMS_AHEAD < count ? a + OTHER_TERMS_AHEAD : count - 1);
      _mm_prefetch((const char *)(term + PERI_BLOCK * ahead), _MM_HINT_T0);
      _mm_prefetch((const char *)(reverse + PERI_BLOCK * ahead), _MM_HINT_T0);
      _mm_prefetch((const char *)(all_terms + reverse[near]), _MM_HINT_T0);
      _mm_prefetch((const char *)(all_terms + reverse[near + PERI_BLOCK - 1]), _MM_HINT_T0);
    }
    const peri_v8d P = v8_add_pd(v8_maskz_mov_pd(on, v8_loadu_pd(term + PERI_BLOCK * a)),
                                 v8_mask_gather_at_pd(on, reverse + PERI_BLOCK * a, all_terms));
    const peri_v8d g = bond_force_v8(r0, r, inv_r, Di, v8_loadu_pd(D + j), Bi, v8_loadu_pd(B + j), P,
                                     bond_weight_v8(w, weight, on, k, r0, inv_r0, v8_loadu_pd(w->V + j)));
    /* a lane takes the bond when its bit is set: the node path's sums, in the same order */
    s0 = v8_mask3_fmadd_pd(g, y[0], s0, on);
    s1 = v8_mask3_fmadd_pd(g, y[1], s1, on);
    s2 = v8_mask3_fmadd_pd(g, y[2], s2, on);
    k = lanes_next_bond(k, structure[a]); /* (the lanes that have the entry's bond move to their next one) */
  }
  double a0[PERI_BLOCK], a1[PERI_BLOCK], a2[PERI_BLOCK];
  v8_storeu_pd(a0, s0), v8_storeu_pd(a1, s1), v8_storeu_pd(a2, s2);
  for (int l = 0; l < PERI_BLOCK; ++l) f[l][0] = a0[l], f[l][1] = a1[l], f[l][2] = a2[l];
  return true;
}

bool peri_deviatoric_block_force(const peri_sim *s, const peri_bond_view *w, const peri_node_blocks *items,
                                 int32_t item, double f[PERI_BLOCK][3]) {
  const uint16_t *table = item_offsets(w, items, item);
  return table ? block_force(s, w, items, item, f, table, true) : block_force(s, w, items, item, f, NULL, false);
}
#else
bool peri_deviatoric_block_force(const peri_sim *s, const peri_bond_view *w, const peri_node_blocks *items,
                                 int32_t item, double f[PERI_BLOCK][3]) {
  (void)s, (void)w, (void)items, (void)item, (void)f;
  return false;
}
#endif

double peri_deviatoric_pair_plastic(const peri_sim *s, int32_t i, int64_t k) {
  (void)i;
  if (!s->state.plastic_slots.generation) return 0.0; /* (before the first return every term is 0) */
  const int64_t slot = s->state.plastic_slots.bond_slot[k];
  return s->state.plastic_bond_term[slot] + s->state.plastic_bond_term[s->state.plastic_slots.entry_reverse[slot]];
}

/* Bond i-j's deformed length, and its reference length in *r0 (xi + (u_j - u_i), as the energy's
 * two passes over the family both need). */
/* The energy W_i = K_theta theta_i^2/2 + (alpha_m/m_i)/2 sum_k W_k sum_j omega beta V_j |xi|^2
 * (s^d - s^dp_k)^2 (theta_i of the total extension, s^d = (r - |xi|)/|xi| - eth_i - theta_i/3:
 * each sublayer's deviatoric energy at its elastic deviatoric stretches, weighted), on the
 * return's eight-lane arithmetic: a block of eight nodes on its template (the state in its
 * slots, loaded as vectors), the other nodes bond by bond; the two agree bit for bit. The
 * dilatation is evaluated here (the force's theta may belong to another displacement). */

/* Node i's dilatation sum omega beta V |xi| (r - |xi| - eth_i |xi|) over its intact bonds (on[]
 * their flags as doubles), bond by bond in family order as a block's lane adds them; x[] and q[]
 * (the longest family each) hold each bond's omega beta V |xi| and r - |xi| - eth_i |xi|. */
static double node_dilatation_sum(const peri_sim *s, const peri_bond_view *w, int32_t i, double *restrict x,
                                  double *restrict q, const double *restrict on) {
  const int64_t k0 = w->offset[i], n = w->offset[i + 1] - k0;
  const double *restrict weight = s->state.plastic_bond_weight ? s->state.plastic_bond_weight + k0 : NULL;
#ifdef PERI_BOND_V8
  const int32_t *restrict nbr = w->neighbor + k0;
  const __m256i lane_index = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const peri_v8d c[3] = {v8_set1_pd(w->x0[i]), v8_set1_pd(w->x1[i]), v8_set1_pd(w->x2[i])},
                 cu[3] = {v8_set1_pd(w->u0[i]), v8_set1_pd(w->u1[i]), v8_set1_pd(w->u2[i])};
  const peri_v8d eth = v8_set1_pd(w->eth ? w->eth[i] : 0.0);
  for (int64_t a = 0; a < n; a += 8) {
    const peri_m8 m = peri_first_lanes((int)(n - a));
    const peri_v8i j = v8_maskz_loadu_epi32(m, nbr + a);
    peri_v8d y[3], r0, inv_r0, r, inv_r;
    gathered_lengths_v8(w, m, j, c, cu, y, &r0, &inv_r0, &r, &inv_r);
    const peri_v8d wt0 = bond_weight_v8(w, weight, m, _mm256_add_epi32(_mm256_set1_epi32((int)a), lane_index), r0,
                                        inv_r0, v8_mask_i32gather_pd(m, j, w->V));
    v8_mask_storeu_pd(x + a, m, v8_mul_pd(wt0, r0));
    v8_mask_storeu_pd(q + a, m, v8_fnmadd_pd(eth, r0, v8_sub_pd(r, r0)));
  }
#else
  const double eth = w->eth ? w->eth[i] : 0.0;
  for (int64_t a = 0; a < n; ++a) {
    const int32_t j = w->neighbor[k0 + a];
    const double x0 = w->x0[j] - w->x0[i], x1 = w->x1[j] - w->x1[i], x2 = w->x2[j] - w->x2[i];
    const double d0 = x0 + (w->u0[j] - w->u0[i]), d1 = x1 + (w->u1[j] - w->u1[i]), d2 = x2 + (w->u2[j] - w->u2[i]);
    const double r0 = sqrt(x0 * x0 + x1 * x1 + x2 * x2), r = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    x[a] = weight[a] * r0, q[a] = fma(-eth, r0, r - r0);
  }
#endif
  double sum = 0.0;
  for (int64_t a = 0; a < n; ++a)
    if (on[a] != 0.0) sum = fma(x[a], q[a], sum);
  return sum;
}

/* W_i from its sums: the dilatation's (theta) and the layers' energies S (weights W of L). */
static inline double node_energy_of(const peri_material *mat, double m, double theta, const double *S,
                                    const double *W, int L) {
  double deviatoric = 0.0;
  for (int l = 0; l < L; ++l) deviatoric = fma(W[l], S[l], deviatoric);
  return 0.5 * mat->K_theta * theta * theta + 0.5 * (mat->alpha_m / m) * deviatoric;
}

/* The weights of the energy's layers: the material's sublayers (padded_weights), or for a
 * material without them its whole deviatoric energy as layer 0 of a state of zeros. */
static inline void energy_weights(const peri_sublayers *sl, int L, double *W) {
  padded_weights(sl, L, W);
  if (!sl) W[0] = 1.0;
}

/* Node i's energy bond by bond. Scratch: (5 + L) times the longest family. */
static double node_energy(const peri_sim *s, const peri_bond_view *w, int32_t i, double *scratch, int64_t longest,
                          int L) {
  const peri_particles *p = &s->disc.p;
  const peri_bonds *b = &s->disc.bonds;
  const peri_material *mat = &s->mat.materials[p->material[i]];
  const int64_t k0 = b->offset[i], nb = b->offset[i + 1] - k0;
  double *on = scratch, *x = scratch + longest, *q = scratch + 2 * longest, *sd = scratch + 3 * longest,
         *wt = scratch + 4 * longest, *rows = scratch + 5 * longest;
  for (int64_t a = 0; a < nb; ++a) on[a] = b->broken[k0 + a] ? 0.0 : 1.0;
  const double m = p->wvol[i], theta = mat->n_theta * node_dilatation_sum(s, w, i, x, q, on) / m;
  deviatoric_stretches(s, w, i, k0, (int)nb, (w->eth ? w->eth[i] : 0.0) + theta / 3.0, on, sd, wt);
  const peri_sublayers *sl = mat->sublayers;
  if (sl)
    for (int64_t a = 0; a < nb; ++a) {
      double row[PERI_MAX_SUBLAYERS];
      const double *sp = peri_plastic_row_inline(s, s->state.plastic_stretch, k0 + a, row);
      for (int l = 0; l < L; ++l) rows[a * L + l] = sp[l];
    }
  else
    memset(rows, 0, sizeof(double) * (size_t)(nb * L));
  double S[PERI_MAX_SUBLAYERS] = {0}, W[PERI_MAX_SUBLAYERS];
  layer_energies(rows, sd, wt, (int)nb, L, S);
  energy_weights(sl, L, W);
  return node_energy_of(mat, m, theta, S, W, L);
}

#ifdef PERI_BOND_V8
/* The energies of a block of eight nodes of one material, its state in its slots in template
 * order (build_slots); false, having written nothing, where it cannot (see block_return).
 * Scratch: 24 doubles per template entry. */
static inline __attribute__((always_inline)) bool block_energy(const peri_sim *s, const peri_bond_view *w,
                                                               const peri_node_blocks *items, int32_t item,
                                                               double *W_out, double *restrict scratch, const int L,
                                                               const uint16_t *restrict table, const bool from_table) {
  if (L > 4 || items->tpl_end[item] != items->tpl[item + 1]) return false;
  const peri_particles *p = &s->disc.p;
  const int32_t i0 = items->first[item];
  for (int l = 1; l < PERI_BLOCK; ++l)
    if (p->material[i0 + l] != p->material[i0]) return false;
  const peri_material *mat = &s->mat.materials[p->material[i0]];
  const peri_sublayers *sl = mat->sublayers;
  const int64_t t0 = items->tpl[item], count = items->tpl_end[item] - t0, base = w->offset[i0];
  const double *state = s->state.plastic_stretch + s->state.plastic_slots.item_slot[item] * L;
  const double *restrict weight = s->state.plastic_bond_weight ? s->state.plastic_bond_weight + base : NULL;
  const int32_t *restrict tj = items->tpl_node + t0;
  const uint8_t *restrict lanes = items->tpl_lanes + t0, *restrict structure = items->tpl_bonds + t0;
  int32_t first[PERI_BLOCK];
  double eth[PERI_BLOCK];
  for (int l = 0; l < PERI_BLOCK; ++l)
    first[l] = (int32_t)(w->offset[i0 + l] - base), eth[l] = w->eth ? w->eth[i0 + l] : 0.0;
  const peri_v8d c[3] = {v8_loadu_pd(w->x0 + i0), v8_loadu_pd(w->x1 + i0), v8_loadu_pd(w->x2 + i0)},
                 cu[3] = {v8_loadu_pd(w->u0 + i0), v8_loadu_pd(w->u1 + i0), v8_loadu_pd(w->u2 + i0)};
  const peri_v8d veth = v8_loadu_pd(eth), one = v8_set1_pd(1.0), zero = v8_setzero_pd();
  /* 1. the dilatation sums (node_dilatation_sum's operations), the lengths kept */
  peri_v8d wq = zero;
  peri_v8i k = _mm256_loadu_si256((const __m256i *)first);
  for (int64_t a = 0; a < count; ++a) {
    const int64_t j = tj[a];
    const peri_v8d uj[3] = {v8_loadu_pd(w->u0 + j), v8_loadu_pd(w->u1 + j), v8_loadu_pd(w->u2 + j)};
    peri_v8d y[3], r0, inv_r0, r, inv_r;
    entry_lengths_v8(w, from_table, table, a, j, c, cu, uj, y, &r0, &inv_r0, &r, &inv_r);
    const peri_v8d wt0 = bond_weight_v8(w, weight, structure[a], k, r0, inv_r0, v8_loadu_pd(w->V + j));
    const peri_v8d d = v8_sub_pd(r, r0);
    wq = v8_mask3_fmadd_pd(v8_mul_pd(wt0, r0), v8_fnmadd_pd(veth, r0, d), wq, lanes[a]);
    v8_storeu_pd(scratch + 24 * a, d);
    v8_storeu_pd(scratch + 24 * a + 8, inv_r0);
    v8_storeu_pd(scratch + 24 * a + 16, v8_mul_pd(v8_mul_pd(v8_maskz_mov_pd(lanes[a], one), wt0), v8_mul_pd(r0, r0)));
    k = lanes_next_bond(k, structure[a]);
  }
  double wq_of[PERI_BLOCK], theta[PERI_BLOCK], shift[PERI_BLOCK];
  v8_storeu_pd(wq_of, wq);
  for (int l = 0; l < PERI_BLOCK; ++l)
    theta[l] = mat->n_theta * wq_of[l] / p->wvol[i0 + l], shift[l] = eth[l] + theta[l] / 3.0;
  /* 2. each layer's energy (deviatoric_stretches' and layer_energies' operations) */
  const peri_v8d vshift = v8_loadu_pd(shift);
  peri_v8d S[4] = {zero, zero, zero, zero};
  for (int64_t a = 0; a < count; ++a) {
    const peri_m8 m = structure[a];
    const peri_v8d on = v8_maskz_mov_pd(lanes[a], one), wt = v8_loadu_pd(scratch + 24 * a + 16);
    const peri_v8d sd =
        v8_mul_pd(on, v8_fmsub_pd(v8_loadu_pd(scratch + 24 * a), v8_loadu_pd(scratch + 24 * a + 8), vshift));
    for (int l = 0; l < L; ++l) {
      const peri_v8d f = sl ? v8_maskz_mov_pd(m, v8_loadu_pd(state + PERI_BLOCK * (L * a + l))) : zero;
      const peri_v8d e = v8_sub_pd(sd, f);
      S[l] = v8_mask3_fmadd_pd(wt, v8_mul_pd(e, e), S[l], m);
    }
  }
  double S_of[4][PERI_BLOCK], W[PERI_MAX_SUBLAYERS];
  for (int l = 0; l < L; ++l) v8_storeu_pd(S_of[l], S[l]);
  energy_weights(sl, L, W);
  for (int lane = 0; lane < PERI_BLOCK; ++lane) {
    double S_lane[4];
    for (int l = 0; l < L; ++l) S_lane[l] = S_of[l][lane];
    W_out[i0 + lane] = node_energy_of(mat, p->wvol[i0 + lane], theta[lane], S_lane, W, L);
  }
  return true;
}

/* block_energy with constant layer counts. */
static bool block_energy_any(const peri_sim *s, const peri_bond_view *w, const peri_node_blocks *items, int32_t item,
                             double *W, double *scratch) {
  const uint16_t *table = item_offsets(w, items, item);
#define BLOCK_ENERGY(L)                                                                                          \
  (table ? block_energy(s, w, items, item, W, scratch, L, table, true)                                           \
         : block_energy(s, w, items, item, W, scratch, L, NULL, false))
  switch (s->state.plastic_layers) {
  case 1: return BLOCK_ENERGY(1);
  case 2: return BLOCK_ENERGY(2);
  case 3: return BLOCK_ENERGY(3);
  case 4: return BLOCK_ENERGY(4);
  default: return false;
  }
#undef BLOCK_ENERGY
}
#endif

void peri_deviatoric_energy(peri_sim *s, double *W) {
  const peri_particles *p = &s->disc.p;
  /* the blocks with the current displacements (their copies of u are the loops' input) */
  const peri_node_blocks *items = peri_node_blocks_refresh(s);
  const peri_bond_view w = peri_bond_view_of(s, items->soa);
  const int64_t longest = longest_family(&s->disc.bonds, p->n_owned);
  const int L = s->state.plastic_layers;
  /* the blocks' state is in their template's order when the slots follow these items */
  const bool in_slots = s->state.plastic_slots.state_in_slots && s->state.plastic_slots.generation == items->generation;
#pragma omp parallel
  {
    const int64_t node_scratch = (5 + (int64_t)L) * longest;
    double *scratch = peri_malloc(sizeof(double) * (size_t)(node_scratch + 24 * 2 * longest));
    PERI_FOR_EACH_ITEM(items, item) {
#ifdef PERI_BOND_V8
      if (in_slots && template_order(items, item) && block_energy_any(s, &w, items, item, W, scratch + node_scratch))
        continue;
#else
      (void)in_slots;
#endif
      for (int32_t i = items->first[item]; i < items->first[item + 1]; ++i)
        W[i] = node_energy(s, &w, i, scratch, longest, L);
    }
    free(scratch);
  }
}
