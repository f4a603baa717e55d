/* The ghosts of short-range contact on MPI ranks (docs/contact.md section 2): contact
 * partners are not bonds, so the bond halo (halo.h) does not hold them. Each rank receives,
 * from every other rank, that rank's owned nodes whose deformed position lies within a reach
 * of the box around this rank's owned deformed positions. The contact nodes of a rank are
 * then laid out in the global node order: ghosts of lower ranks, the owned nodes, ghosts of
 * higher ranks, so that a sum over partners in index order is the sum of one process. */
#ifndef PERI_CONTACT_GHOSTS_H
#define PERI_CONTACT_GHOSTS_H
#include <stdint.h>
#include "peri/comm.h"

/* The nodes a rank's contact list is built over, in global order. In one process: the owned
 * nodes. */
typedef struct peri_contact_nodes {
  int32_t n;           /* ghosts below + owned + ghosts above */
  int32_t first_owned; /* index of the first owned node (the ghosts of lower ranks before it) */
  double *x;           /* [3n] reference positions (for the contact distances) */
  double *y;           /* [3n] deformed positions */
  double *volume;      /* [n] */
  int32_t *material;   /* [n] */
} peri_contact_nodes;

/* The messages of one set of ghosts: what is received from each peer rank, in rank order,
 * and the owned nodes sent to each. */
typedef struct peri_contact_ghosts {
  int n_peers;
  int *peer;            /* [n_peers] ranks that send or receive, ascending */
  int32_t *recv_start;  /* [n_peers] first slot of each peer's ghosts in peri_contact_nodes */
  int32_t *recv_count;  /* [n_peers] */
  int64_t *send_start;  /* [n_peers + 1] runs of send_node per peer */
  int32_t *send_node;   /* owned nodes sent to each peer, ascending */
  double *buffer;       /* packed values of the sent nodes */
  peri_comm_request *requests;
  long ghosts;          /* received at the last build */
} peri_contact_ghosts;

/* Collective. Finds this rank's ghosts for pairs closer than `reach` (the largest contact
 * distance plus the list's skin) and fills `nodes`: the ghosts' reference positions,
 * deformed positions, volumes and materials from their owners, and the owned nodes' (x, y,
 * volume, material of the n_owned owned nodes) in their place. */
void peri_contact_ghosts_build(peri_contact_ghosts *g, peri_contact_nodes *nodes, int32_t n_owned, const double *x,
                               const double *y, const double *volume, const int32_t *material, double reach);
/* Collective. The ghosts' deformed positions from their owners into nodes->y (the owned
 * slots of nodes->y must be current). */
void peri_contact_ghosts_refresh(peri_contact_ghosts *g, peri_contact_nodes *nodes);
void peri_contact_ghosts_free(peri_contact_ghosts *g, peri_contact_nodes *nodes);

#endif
