/* Halo exchange (docs/parallel.md): each rank receives, from the ranks that own them, the
 * values of its ghost nodes, by non-blocking messages between neighbouring ranks only. The
 * ghosts owned by one rank are a contiguous run of local slots (ghosts are kept in global
 * order and each rank owns a contiguous range of it), so they are received in place. */
#ifndef PERI_HALO_H
#define PERI_HALO_H
#include <stdint.h>
#include "peri/comm.h"

typedef struct peri_halo {
  int n_neighbors;
  int *rank;             /* [n_neighbors] neighbouring ranks, ascending */
  int32_t *recv_start;   /* [n_neighbors] first local ghost slot owned by each neighbour */
  int32_t *recv_count;   /* [n_neighbors] number of those ghosts */
  int64_t *send_start;   /* [n_neighbors + 1] runs of send_node per neighbour */
  int32_t *send_node;    /* owned local nodes each neighbour holds as ghosts, ascending */
  double *send_buffer;   /* packed values, room for 3 components per sent node */
  peri_comm_request *requests;
} peri_halo;

/* Largest number of components one exchange carries. */
enum { PERI_HALO_MAX_COMPONENTS = 3 };

/* Ghost slots of `field` (ncomp doubles per node, 1 <= ncomp <= 3) from their owners. */
void peri_halo_exchange(peri_halo *h, double *field, int ncomp);
/* Doubles a rank sends in one exchange of a scalar field. */
int64_t peri_halo_send_volume(const peri_halo *h);
void peri_halo_free(peri_halo *h);

#endif
