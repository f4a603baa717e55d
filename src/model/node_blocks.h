/* The bond loops' work items. A block is eight consecutive owned nodes whose families,
 * shifted by the lane (neighbour j of node i0 + l read as j - l), fit one short template:
 * the loops run the template once for the eight nodes, lane l taking entry a when bit l of
 * its mask is set, and read the neighbours j + l of a template entry j with contiguous
 * loads instead of gathers. On a lattice in row order (src/core/sfc_order.c) the interior
 * nodes of a row have identical shifted families (all bits set) and the nodes near a
 * surface nearly so. Other nodes are items of one node. Both paths add each node's bonds in
 * family order, so a node's force does not depend on which path it takes (nor on threads
 * or ranks). */
#ifndef PERI_NODE_BLOCKS_H
#define PERI_NODE_BLOCKS_H
#include <stdbool.h>
#include <stdint.h>
#include <string.h>
#include "peri/sim.h"
#include "peri/work_share.h"

#define PERI_BLOCK 8 /* nodes per block: one 512-bit vector of doubles */

/* A block's offsets (tpl_geom, geom): xi = x_j - x_i, then |xi| and 1/|xi| as the eight-lane
 * kernels compute them from xi (peri_offset_of_positions_v8, bond_kernel.h), with either sum of
 * squares, so a kernel that reads them gets each lane's numbers bit for bit. */
#define PERI_GEOM_NONE UINT16_MAX
#define PERI_GEOM_STRIDE 8
enum peri_geom_slot { PERI_GEOM_XI0, PERI_GEOM_XI1, PERI_GEOM_XI2, PERI_GEOM_R0_NORM2, PERI_GEOM_INV_R0_NORM2,
                      PERI_GEOM_R0_FMA, PERI_GEOM_INV_R0_FMA };

typedef struct peri_node_blocks {
  int32_t n_items;
  int32_t *first;      /* [n_items + 1] first node of each item (then n_owned) */
  int64_t *tpl;        /* [n_items + 1] a block's template entries are tpl[b] .. tpl[b+1]-1
                          (none for an item of one node) */
  int32_t *tpl_node;   /* template entries: neighbour of lane 0 (lane l reads tpl_node + l) */
  uint8_t *tpl_lanes;  /* template entries: bit l set when node i0 + l has that bond, intact */
  uint8_t *tpl_bonds;  /* the same with broken bonds too (the structure) */
  uint16_t *tpl_geom;  /* template entries: the entry's offset x_j - x_i in geom, the same number in
                          every lane (a lattice of exact coordinates, src/core/grid.c), or
                          PERI_GEOM_NONE in every entry of a block whose lanes differ */
  double *geom;        /* [n_geom][PERI_GEOM_STRIDE] the distinct offsets (peri_geom_slot) */
  int32_t n_geom;
  int64_t *tpl_end;    /* [n_items] end of a block's live entries: the entries none of whose lanes
                          keeps a bond are dropped at the next refresh (a fragmenting body loses
                          a third of them), so the loops stop visiting them */
  uint8_t *emptied;    /* [n_items] an entry of the block lost its last lane since the refresh */
  bool compacted;      /* entries were dropped: a resync from the flags (bonds restored by a
                          cut-back or a checkpoint) rebuilds the templates first */
  int64_t block_bonds, tpl_entries, lattice_bonds; /* lattice_bonds: in blocks with offsets in geom */
  int64_t *cost;             /* [n_items + 1] bonds of items 0 .. k-1 */
  peri_work_share *share;    /* the items among the threads (peri_work_share_start) */
  uint64_t broken_edits; /* bonds.broken_edits when tpl_lanes last followed the flags */
  uint64_t generation;   /* a number of its own for each build of the items and templates (layouts
                            kept beside them, such as the deviatoric rule's terms, follow it) */
  /* what the items were built for (rebuilt when the bonds or the nodes change; the reference
   * positions and volumes of the nodes do not change after set-up) */
  const int64_t *offset;
  const int32_t *neighbor;
  const double *x, *volume;
  bool uniform_volume; /* every node has the same volume */
  int32_t n, n_owned;
  bool generic;
  /* structure-of-arrays copies the loops read: x0 x1 x2 u0 u1 u2, n each */
  double *soa;
} peri_node_blocks;

/* The work items of s (built on first use, and again when the bonds change), with the
 * structure-of-arrays copy of the displacements refreshed and the
 * lane masks following the broken flags (rebuilt from them after an edit outside the force
 * loops, peri_bonds.broken_edits). With s->disc.generic_bond_loops set every item is a single
 * node (tests compare the two paths). */
peri_node_blocks *peri_node_blocks_refresh(peri_sim *s);

/* The template entries of a block whose bonds passed the breaking screen in its sums loop,
 * with the lanes that did: the exact test then visits only those bonds instead of every bond
 * of each candidate's family (most of a fracturing step's breaking time went to rescreening
 * families whose few candidates the loop had already found). */
#define PERI_BREAK_MARKS 128
typedef struct peri_break_marks {
  int n;                             /* entries marked; beyond PERI_BREAK_MARKS only counted */
  int32_t entry[PERI_BREAK_MARKS];   /* relative to the block's first entry */
  uint8_t lanes[PERI_BREAK_MARKS];
} peri_break_marks;

/* Marks entry a with the lanes in `over` (none: nothing marked). The loops that do not
 * break bonds get no marks (NULL: the plastic screens, the energy, the reruns); the portable
 * block loops, which do not keep them, set n past the capacity, so that the candidates'
 * families are tested whole. */
static inline void peri_mark_entry(peri_break_marks *marks, int64_t a, unsigned over) {
  if (!over) return;
  if (marks->n < PERI_BREAK_MARKS) {
    marks->entry[marks->n] = (int32_t)a;
    marks->lanes[marks->n] = (uint8_t)over;
  }
  ++marks->n;
}

/* The exact breaking test of the marked bonds of block item `item` (symmetric in i and j, as
 * peri_node_blocks_break_family's), which clears those it breaks from the lane masks; sets in
 * *lost_lanes the lanes that lost a bond and returns the number broken. The same bonds break
 * as when each candidate's whole family is tested: the sums loop's screen keeps every bond the
 * exact test breaks (PERI_S0_SCREEN_MARGIN). */
long peri_node_blocks_break_marked(peri_sim *s, peri_node_blocks *nb, int32_t item, const peri_break_marks *marks,
                                   unsigned *lost_lanes);

/* Breaks, in node i's family (node i of item `item`), every intact bond beyond its critical
 * stretch (exact test, symmetric in i and j) and clears the broken bonds from the item's lane
 * masks; returns the number broken. For the force loops, from the thread that runs the item. */
long peri_node_blocks_break_family(peri_sim *s, peri_node_blocks *nb, int32_t item, int32_t i);

/* Clears from the lane masks the broken bonds of node i (in item `item`), after a loop other
 * than peri_node_blocks_break_family broke some (the plastic paths): cheaper than a whole
 * resync through peri_bonds.broken_edits. From the thread that runs the item. */
void peri_node_blocks_clear_broken(peri_node_blocks *nb, const peri_bonds *b, int32_t item, int32_t i);

/* After the sums of item `item` (nodes i0 .. i1-1, sums[] with fields candidate and smin):
 * the exact breaking test, of the bonds in *marks when the item is a block whose loop kept
 * them all, else of each candidate node's family, adding the bonds broken to
 * n_broken; then the sums again for the nodes that lost bonds: the whole block at once
 * (RERUN_BLOCK) when two or more did, a block pass costing about what two single-node passes
 * with gathers do, else each such node alone (RERUN_NODE, with i the node). Both paths give
 * the same sums bit for bit. smin stays that of the bonds as they were at the test. */
#define PERI_BREAK_AND_RECOMPUTE(s, items, item, i0, i1, sums, is_block, marks, n_broken, RERUN_BLOCK, RERUN_NODE) \
  do {                                                                                                      \
    unsigned lost_lanes = 0;                                                                                \
    const peri_break_marks *marked = (marks);                                                               \
    if ((is_block) && marked && marked->n <= PERI_BREAK_MARKS) {                                            \
      if (marked->n > 0) (n_broken) += peri_node_blocks_break_marked((s), (items), (item), marked, &lost_lanes); \
    } else {                                                                                                \
      for (int32_t i = (i0); i < (i1); ++i)                                                                 \
        if ((sums)[i - (i0)].candidate) {                                                                   \
          const long broken_here = peri_node_blocks_break_family((s), (items), (item), i);                  \
          (n_broken) += broken_here;                                                                        \
          if (broken_here > 0) lost_lanes |= 1u << (i - (i0));                                              \
        }                                                                                                   \
    }                                                                                                       \
    if (lost_lanes) {                                                                                       \
      double smin_at_test[PERI_BLOCK];                                                                      \
      for (int32_t i = (i0); i < (i1); ++i) smin_at_test[i - (i0)] = (sums)[i - (i0)].smin;                 \
      if ((is_block) && __builtin_popcount(lost_lanes) >= 2) {                                              \
        RERUN_BLOCK;                                                                                        \
      } else {                                                                                              \
        for (int32_t i = (i0); i < (i1); ++i)                                                               \
          if (lost_lanes >> (i - (i0)) & 1u) RERUN_NODE;                                                    \
      }                                                                                                     \
      for (int32_t i = (i0); i < (i1); ++i) (sums)[i - (i0)].smin = smin_at_test[i - (i0)];                 \
    }                                                                                                       \
  } while (0)

/* peri_lane_on[m][l] = 1.0 when bit l of m is set, else 0.0: the lane masks as doubles, so
 * that the lane loops keep the width of their double vectors */
extern const double peri_lane_on[256][PERI_BLOCK];

/* Runs the statement that follows for each item of nb, the items shared among the threads
 * of the enclosing parallel region (include/peri/work_share.h: each thread one long run of
 * consecutive items, its neighbour rows in its own core's cache, the same run in every pass;
 * small chunks at the end balance the load). One statement, so that it can follow an omp
 * parallel directive; every thread of the team must reach it. */
#define PERI_FOR_EACH_ITEM(nb, item)                                                                  \
  for (int32_t item##_begin = (peri_work_share_start((nb)->share, (nb)->cost, (nb)->n_items), 0),       \
               item##_end = 0;                                                                         \
       peri_work_share_next((nb)->share, &item##_begin, &item##_end);)                                 \
    for (int32_t item = item##_begin; item < item##_end; ++item)

/* Whether item `item` is a block (else a single node). */
static inline bool peri_item_is_block(const peri_node_blocks *nb, int32_t item) {
  return nb->tpl[item + 1] > nb->tpl[item];
}

/* The template entries a block's loops visit (its live entries, node_blocks.h tpl_end). */
static inline int64_t peri_item_entries(const peri_node_blocks *nb, int32_t item) {
  return nb->tpl_end[item] - nb->tpl[item];
}


#endif
