/* Domain decomposition for distributed runs (docs/parallel.md). Every rank builds the whole
 * discretization from the deck; peri_decompose then keeps a contiguous range of the
 * space-filling-curve (Morton) node order, split so that the ranks hold equal numbers of
 * bonds, and the ghosts its families reference. */
#ifndef PERI_DECOMPOSE_H
#define PERI_DECOMPOSE_H
#include <stdint.h>
#include <stdio.h>
#include "peri/sim.h"
#include "peri/halo.h"

/* Global sums run over blocks of this many nodes of the global order: each block is summed
 * in node order, then the block sums in block order. Rank ranges start on block boundaries,
 * so the result is the same, bit for bit, on any number of ranks. */
enum { PERI_SUM_BLOCK = 64 };

typedef struct peri_decomposition {
  int rank, size;
  int64_t n_global;        /* nodes of the whole problem */
  int64_t n_bonds_global;  /* directed bonds of the whole problem */
  int64_t *first;          /* [size + 1]: rank r owns global nodes first[r] .. first[r+1]-1 */
  int64_t *owned;          /* [size]: nodes owned by each rank */
  int64_t *blocks;         /* [size]: sum blocks of each rank */
  int32_t *global_id;      /* [p.n]: global (Morton order) index of each local node */
  int64_t *bond_first;     /* [size + 1]: rank r's families are global bonds bond_first[r] .. bond_first[r+1]-1 */
  uint64_t bond_hash;      /* of the global families, for checkpoints (0 without output.checkpoint_every) */
  peri_halo halo;
  /* the bonds to other ranks' nodes, for the deviatoric yield rule's plastic terms (NULL
   * without it) */
  struct peri_bond_halo *bond_halo;
} peri_decomposition;

/* Splits the built simulation over the ranks (nothing in a single process): keeps this
 * rank's nodes and ghosts, families with local indices, regions, conditions and the heat
 * operator, and installs the halo exchange as s->par.exchange. Returns 0. Whether the solver
 * runs on this many ranks is checked before (peri_solver_check_ranks). */
int peri_decompose(peri_sim *s);
void peri_decomposition_free(peri_decomposition *d);
/* Rank 0 prints, for the ranks together, the nodes owned, ghosts, neighbour ranks and the
 * values one exchange of a scalar field sends (the halo volume); every rank must call it. */
void peri_print_decomposition(const peri_sim *s, FILE *out);
/* Before a force evaluation: the ghosts' displacements, and their compression-dependent
 * critical stretch when the deck uses it (a no-op in a single process). */
void peri_exchange_state(peri_sim *s);

/* The sum over every owned node of all ranks of terms[ncomp * i + c], in
 * fixed-order blocks (PERI_SUM_BLOCK): independent of the number of ranks and threads.
 * Every rank gets the result. */
void peri_sum_owned(const peri_sim *s, const double *terms, int ncomp, double *out);
/* The same sum from the caller's block sums: block[ncomp * k + c] is the sum, from 0.0 in node
 * order, of component c over owned nodes k * PERI_SUM_BLOCK .. (k + 1) * PERI_SUM_BLOCK - 1
 * (peri_sum_blocks_owned of them). For a pass over the nodes that sums as it goes. */
void peri_sum_blocks(const peri_sim *s, const double *block, int ncomp, double *out);
int64_t peri_sum_blocks_owned(const peri_sim *s);
/* Global counts: nodes, directed bonds, broken directed bonds. */
int64_t peri_global_nodes(const peri_sim *s);
int64_t peri_global_bonds(const peri_sim *s);
long peri_global_broken(const peri_sim *s);
/* Rank 0 receives ncomp values per node of every rank's owned nodes in global order
 * (`out`: ncomp * global nodes, used on rank 0 only; in a single process a copy). */
void peri_gather_owned(const peri_sim *s, const double *local, int ncomp, double *out);
/* Rank 0 receives a per-bond byte array (broken flags, cut flags) of every rank's families in
 * the global bond order (`out`: global bonds, used on rank 0 only; in a single process a copy). */
void peri_gather_owned_bonds(const peri_sim *s, const uint8_t *local, uint8_t *out);

#endif
