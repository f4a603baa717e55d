/* Bonds in compressed sparse rows: the family of node i is
 * neighbor[offset[i] .. offset[i+1]-1]. Each bond appears from both ends (directed
 * bonds). Per-bond arrays are parallel to neighbor[]: 5 bytes per directed bond. The
 * reference length, partial volume and influence of a bond are functions of the reference
 * positions and the family (below), evaluated where needed rather than stored. Built once in
 * the reference configuration; bonds only break. */
#ifndef PERI_BONDS_H
#define PERI_BONDS_H
#include <stdint.h>
#include <stddef.h>
#include <math.h>
#include "peri/particles.h"

/* Partial-volume rules (model reference section 5):
 *  NONE:   beta = 1 for |xi| <= delta;
 *  LINEAR: Le / Hu-Ha-Bobaru ramp, beta = 1/2 + (delta - |xi|)/dx over delta +- dx/2,
 *          neighbors out to delta + dx/2 (the default);
 *  LAMMPS: the same ramp truncated at delta (LAMMPS peri: beta falls to 1/2 at delta). */
typedef enum { PERI_PV_NONE = 0, PERI_PV_LINEAR = 1, PERI_PV_LAMMPS = 2 } peri_partial_volume;
typedef enum { PERI_INFLUENCE_CONSTANT = 0, PERI_INFLUENCE_INVERSE = 1,
               PERI_INFLUENCE_GAUSSIAN = 2 } peri_influence;

/* Family search parameters. */
typedef struct peri_family_params {
  double horizon;             /* delta */
  double spacing;             /* grid spacing dx (for the partial-volume ramp) */
  peri_partial_volume rule;   /* NONE: |xi| <= delta; LINEAR: ramp over delta +- dx/2 */
  peri_influence influence;
  /* [n] the horizon of each node when it varies (docs/variable_horizon.md), else NULL: the
   * pair i-j is then bonded within max(delta_i, delta_j) (with the rule's ramp), and
   * `horizon` is the largest delta_i */
  const double *node_horizon;
} peri_family_params;

typedef struct peri_bonds {
  int32_t n_nodes;
  int64_t n_bonds;  /* directed bonds = offset[n_nodes] */
  int64_t *offset;  /* [n_nodes+1] */
  int32_t *neighbor;/* [n_bonds] */
  uint8_t *broken;  /* 0 intact, 1 broken */
  /* incremented by every change of the broken flags other than the models' force loops
   * (pre-cracks, growing thermal cracks, restarts, undone load steps), so that the loops'
   * copies of them (src/model/node_blocks.c) follow */
  uint64_t broken_edits;
  peri_family_params family; /* what the per-bond reference data are evaluated from */
  /* surface-correction factors of the bonds (src/model/surface_correction.c), NULL without:
   * G scales the bond (PMB) or deviatoric (LPS) term, D the LPS dilatation term */
  double *surface_G, *surface_D;
  /* position_aware LPS: the other end's own factors on the bond (src/model/position_aware.c),
   * NULL otherwise; and the smallest factor of the correction (a check that none is negative) */
  double *surface_G_rev, *surface_D_rev;
  double surface_lowest;
} peri_bonds;

/* The largest surface-correction factor of bond k (its stiffness over the uncorrected one,
 * for the stable-step and stiffness bounds): G, D, and the mean of the two ends' own. */
static inline double peri_bond_surface_factor(const peri_bonds *b, int64_t k) {
  double f = b->surface_G[k];
  if (b->surface_D) f = f > b->surface_D[k] ? f : b->surface_D[k];
  if (b->surface_G_rev) {
    const double own = f, other = b->surface_G_rev[k] > b->surface_D_rev[k] ? b->surface_G_rev[k] : b->surface_D_rev[k];
    f = 0.5 * (own + other);
  }
  return f;
}

/* Reference bond vector xi = x_j - x_i (x: reference positions, stride 3) and |xi|. */
static inline double peri_bond_xi(const double *x, int32_t i, int32_t j, double xi[3]) {
  for (int c = 0; c < 3; ++c) xi[c] = x[3 * j + c] - x[3 * i + c];
  return sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
}
/* Reference length |x_j - x_i|. */
static inline double peri_bond_length(const double *x, int32_t i, int32_t j) {
  double xi[3];
  return peri_bond_xi(x, i, j, xi);
}
/* Partial-volume factor of a bond of the family with reference length r (r within the
 * cutoff): min(1, 1/2 + (delta - r)/dx) for the ramp rules, 1 for NONE. */
static inline double peri_bonds_beta(const peri_bonds *b, double r) {
  const peri_family_params *f = &b->family;
  if (f->rule == PERI_PV_NONE || !(f->spacing > 0)) return 1.0;
  const double beta = 0.5 + (f->horizon - r) / f->spacing;
  return beta < 1.0 ? (beta > 0.0 ? beta : 0.0) : 1.0;
}
/* Influence function omega(r) of the family. */
static inline double peri_bonds_omega(const peri_bonds *b, double r) {
  switch (b->family.influence) {
  case PERI_INFLUENCE_INVERSE: return 1.0 / r;
  case PERI_INFLUENCE_GAUSSIAN: return exp(-(r * r) / (b->family.horizon * b->family.horizon));
  default: return 1.0;
  }
}


/* Builds the families of all owned nodes by a cell-list search (O(n)): bins of side
 * >= the cutoff (delta, or delta + dx/2 for LINEAR). A neighbor j of i is kept when
 * |xi| <= cutoff (with a relative tolerance of 1e-12 * delta so lattice points exactly at
 * delta are included) and beta > 0. Neighbors of each node are sorted by index. */
void peri_bonds_build(peri_bonds *b, const peri_particles *p, const peri_family_params *fp);
/* The partial-volume factor beta(|xi|) of the rule (section 5 of the model reference). */
double peri_partial_volume_factor(peri_partial_volume rule, double r, double delta, double dx);
/* The influence function omega(|xi|). */
double peri_influence_value(peri_influence w, double r, double delta);
/* Index of bond j in the family of i, or -1. */
int64_t peri_bonds_find(const peri_bonds *b, int32_t i, int32_t j);
/* Bytes used by all per-bond arrays, divided by n_bonds. */
double peri_bonds_bytes_per_bond(const peri_bonds *b);
void peri_bonds_free(peri_bonds *b);
/* Removes every bond i-j whose ends have different labels (label[] over all n nodes, owned
 * and ghosts), keeping each family sorted; returns the number of directed bonds removed.
 * Separate bodies of one deck (docs/contact.md "Bodies"). */
int64_t peri_bonds_keep_within(peri_bonds *b, const int32_t *label);
/* Number of broken directed bonds. */
long peri_broken_count(const peri_bonds *b);
/* FNV-1a hash of the bond families of nodes 0..n-1 (CSR offsets and neighbours): a
 * checkpoint is only resumed on the same families. */
uint64_t peri_bonds_hash(const peri_bonds *b, int32_t n);

/* The most bonds a node of 0..n-1 has (its family's length; 0 for no node). */
int64_t peri_bonds_longest_family(const peri_bonds *b, int32_t n);

#endif
