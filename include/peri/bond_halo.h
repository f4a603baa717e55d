/* Per-bond values across ranks (docs/parallel.md, "Bond halo"): for a bond i -> j between an
 * owned node i and a ghost j, the value that j's owner keeps on the reverse bond j -> i (the
 * deviatoric yield rule's plastic term of the other end, docs/plasticity.md section 8). The
 * lists are built from the global families and their reverse-bond index, which every rank
 * holds before the split, so the two sides agree on the order without a message: each rank
 * sends its values in the order of the receiving rank's bonds. */
#ifndef PERI_BOND_HALO_H
#define PERI_BOND_HALO_H
#include <stdint.h>
#include "peri/bonds.h"
#include "peri/comm.h"

typedef struct peri_bond_halo {
  int n_neighbors;
  int *rank;           /* [n_neighbors] neighbouring ranks, ascending */
  int64_t *start;      /* [n_neighbors + 1] runs of send_bond and recv_bond per neighbour */
  int64_t *send_bond;  /* local bond j -> i of each value sent, in the receiver's order of i -> j */
  int64_t *recv_bond;  /* local bond i -> j that takes each value received, ascending */
  double *send_buffer, *recv_buffer;
  peri_comm_request *requests;
} peri_bond_halo;

/* The lists of rank `rank` of `size`: `global` the whole families, reverse[k] the global index
 * of bond k's reverse, rank r owning nodes first[r] .. first[r+1]-1 and bonds bond_first[r] ..
 * bond_first[r+1]-1. Local bond indices count from bond_first[rank]. */
peri_bond_halo *peri_bond_halo_build(const peri_bonds *global, const int64_t *reverse, const int64_t *first,
                                     const int64_t *bond_first, int rank, int size);
/* Fills out[a] with the value of local bond bonds[a], a < n, for the receiving rank. */
typedef void (*peri_bond_pack)(const void *context, const int64_t *bonds, int64_t n, double *out);
/* into[k] of every bond k from an owned node to a ghost takes the ghost owner's value of the
 * reverse bond, packed there by `pack`. Every rank calls it (collective); NULL: nothing. */
void peri_bond_halo_exchange(peri_bond_halo *h, peri_bond_pack pack, const void *context, double *into);
/* Bonds whose values one exchange sends from this rank. */
int64_t peri_bond_halo_volume(const peri_bond_halo *h);
void peri_bond_halo_free(peri_bond_halo *h);

#endif
