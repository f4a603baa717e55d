/* The plastic bond loops of the PMB and LPS models (src/model/plastic_bonds.c,
 * docs/plasticity.md). The models call them instead of their elastic loops when a material
 * has sublayers (s->state.plastic_stretch set), so the elastic loops carry no plasticity. */
#ifndef PERI_PLASTIC_BONDS_H
#define PERI_PLASTIC_BONDS_H
#include "peri/plasticity.h"
#include "peri/sim.h"

/* Allocates the plastic state when a material has sublayers (nothing otherwise). Returns
 * PERI_OK or PERI_ERR_INPUT with a message (a combination plasticity does not take). */
int peri_plastic_init(peri_sim *s);
#include "bond_kernel.h"

/* What a plastic force pass needs: the sublayers of every pair of materials, padded to the
 * run's layer count with layers of weight 0 that never yield, so every bond maps the same
 * number of layers branch-free (W and Y [(a n_materials + b) layers + l]; an elastic pair has
 * only padding); the failure laws of each pair; and the screen of every node (owned and
 * ghost): a stretch below which none of its bonds yields or breaks, so that a node whose
 * bonds all stay within it and that has never yielded (s->state.plastic_nodes) has the
 * elastic force (docs/plasticity.md section 5). */
typedef struct peri_plastic_pass {
  int layers, nm;
  double *W, *Y;
  double *critical; /* [a n_materials + b] critical plastic stretch of the pair (INFINITY: none) */
  bool ductile;     /* some pair has one */
  /* energy failure: [a n_materials + b] the critical bond work (INFINITY: none) and the bond
   * micromodulus c of the work c omega |xi| sum_k W_k phi_k (the PMB one of each end, averaged) */
  double *work, *c;
  bool energetic; /* some pair has a critical bond work */
  /* Cowper-Symonds: [a n_materials + b] d and 1/p of the pair's sublayers (d = 0: none) */
  double *rate_d, *rate_inv_p;
  bool rate; /* some pair has it */
  double *screen; /* [n] min(s0 bound, first yield stretch, elastic stretch of the bond work) */
} peri_plastic_pass;
/* After peri_update_s0_bound (the screen takes the critical stretch's bound). */
peri_plastic_pass peri_plastic_pass_begin(peri_sim *s);
void peri_plastic_pass_end(peri_plastic_pass *pass);

/* A thread's scratch for the plastic node loops (free with free()). */
typedef struct peri_plastic_chunk peri_plastic_chunk;
peri_plastic_chunk *peri_plastic_chunk_new(void);
/* PMB node i (owned) through the plastic path: breaking (exact test, the ductile and energy
 * laws), the return mapping of its intact bonds, and the force density at their elastic
 * stretches into f, with the minimum stretch of its intact bonds in *smin. Returns the
 * number of bonds it broke; the caller counts a broken-flag edit. */
long peri_plastic_pmb_node(peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pass, int32_t i,
                           peri_plastic_chunk *scratch, double f[3], double *smin);
/* LPS node i (owned) through the plastic path, pass 1: breaking and the return mapping as
 * peri_plastic_pmb_node, then the sums sum w q and sum w |xi| at the elastic extensions into
 * sums (as the elastic loops of src/model/lps.c), the minimum stretch in *smin. Returns the
 * number of bonds it broke. */
long peri_plastic_lps_node_sums(peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pass, int32_t i,
                                peri_plastic_chunk *scratch, double sums[2], double *smin);
/* LPS node i, pass 2: the force density at the elastic extensions of its intact bonds, with
 * the coefficients D and B of pass 1 in w->coef. */
void peri_plastic_lps_node_force(const peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pass, int32_t i,
                                 double f[3]);
/* osb_mo node i (owned) through the plastic path, pass 1: breaking and the return mapping as
 * peri_plastic_pmb_node, then the dilatation sum sum_j (s^e L - eth_i) beta V_j at the
 * elastic stretches (src/model/osb_mo.c) into *sum. Returns the number of bonds it broke. */
long peri_plastic_mo_node_sums(peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pass, int32_t i,
                               peri_plastic_chunk *scratch, double *sum);
/* osb_mo node i, pass 2: the force density at the elastic stretches of its intact bonds, with
 * the coefficients A, B, C of pass 1 in w->coef. */
void peri_plastic_mo_node_force(const peri_sim *s, const peri_bond_view *w, const peri_plastic_pass *pass, int32_t i,
                                double f[3]);
/* Whether nodes i0 .. i1-1 (a work item) have all yielded (yielded: s->state.plastic_nodes): such
 * an item takes the plastic path whole, which writes every sum of the elastic screen, so the
 * passes skip the screen (a body that yields through). */
static inline bool peri_plastic_item_yielded(const uint8_t *yielded, int32_t i0, int32_t i1) {
  bool all = true;
  for (int32_t i = i0; i < i1; ++i) all &= yielded[i] != 0;
  return all;
}

/* Elastic strain energy densities at the current plastic state. */
void peri_plastic_pmb_energy(peri_sim *s, double *W);
void peri_plastic_lps_energy(peri_sim *s, double *W);
/* (peri_plastic_bond_stretch: include/peri/plasticity.h) */
/* Where layer l of the bond in slot `slot` is in a state kept in slots (peri_state.plastic_slots,
 * the deviatoric rule): in the blocks' slots (below block_slots, a multiple of 8) each 8 slots'
 * layers side by side, layer by layer, so that the 8 lanes of a template entry read one layer
 * as one vector; in the other nodes' slots (family order) a bond's layers in a row, so that
 * their loops read a node's state in place. */
static inline int64_t peri_plastic_layer_index(int64_t slot, int l, int L, int64_t block_slots) {
  return slot < block_slots ? (slot & ~(int64_t)7) * L + 8 * l + (slot & 7) : slot * L + l;
}

/* peri_plastic_row (include/peri/plasticity.h) inline, for the loops over every bond. */
static inline const double *peri_plastic_row_inline(const peri_sim *s, const double *state, int64_t k, double *row) {
  const int L = s->state.plastic_layers;
  if (!s->state.plastic_slots.state_in_slots) return state + k * L;
  const int64_t slot = s->state.plastic_slots.bond_slot[k], block_slots = s->state.plastic_slots.block_slots;
  if (slot >= block_slots) return state + slot * L;
  for (int l = 0; l < L; ++l) row[l] = state[peri_plastic_layer_index(slot, l, L, block_slots)];
  return row;
}

/* The yielded flags (s->state.plastic_nodes) rebuilt from the plastic state. */
void peri_plastic_flag_nodes(peri_sim *s);

/* The deviatoric yield rule of LPS (src/model/deviatoric_plasticity.c, docs/plasticity.md
 * section 8). Whether the run's plastic materials take it: */
bool peri_deviatoric_rule(const peri_sim *s);
/* The reverse index of the bonds (s->state.plastic_reverse) and, where the kernels do not
 * evaluate them, their weights (the terms and their slots come with the first return);
 * PERI_ERR_INPUT with a message when a neighbour is not a node of the body. */
int peri_deviatoric_init(peri_sim *s);
/* After the dilatation pass of LPS (theta and B = alpha of every owned node, the node blocks'
 * copies of the positions at this displacement): the radial return of every owned node's
 * sublayers, with elastic[i] = sum_j omega beta V_j (e^d_ij)^2 at the total extensions (a node
 * that has never yielded and stays below its first yield skips the return), the plastic terms
 * of the bonds' other ends (from other ranks through the bond halo); near[i] (owned nodes) says whether node i has a plastic state or a bond
 * with the other end's plastic term (else its force is the elastic one). */
void peri_deviatoric_return(peri_sim *s, const double *elastic, uint8_t *near);
/* The force density on node i, with the coefficients D and B of every node in w->coef: the
 * LPS pair forces with the plastic part of each bond. */
void peri_deviatoric_node_force(const peri_sim *s, const peri_bond_view *w, int32_t i, double f[3]);
/* The same for the eight nodes of block item `item` (node_blocks.h) at once, into f[lane],
 * bit for bit as node by node; false (nothing done) where the build has no eight-lane
 * functions or the block's template lost entries. */
struct peri_node_blocks;
bool peri_deviatoric_block_force(const peri_sim *s, const peri_bond_view *w, const struct peri_node_blocks *items,
                                 int32_t item, double f[8][3]);
/* alpha_i sum_l W_l s^dp_l,ij + alpha_j sum_l W_l s^dp_l,ji of bond k = i -> j (alpha the
 * coefficients B of the dilatation pass): the pair force t_ij + t_ji loses omega |xi| times it. */
double peri_deviatoric_pair_plastic(const peri_sim *s, int32_t i, int64_t k);
/* Strain energy densities: the elastic bulk term and each sublayer's deviatoric energy. */
void peri_deviatoric_energy(peri_sim *s, double *W);

#endif
