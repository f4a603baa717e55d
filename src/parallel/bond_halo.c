/* Per-bond values across ranks (include/peri/bond_halo.h): the bonds between this rank's
 * nodes and a neighbour's, listed from the global families, and their non-blocking exchange. */
#include <stdlib.h>
#include "peri/bond_halo.h"
#include "peri/error.h"

/* Appends v to the growing list *a of *n entries with room for *cap. */
static void append(int64_t **a, int64_t *n, int64_t *cap, int64_t v) {
  if (*n == *cap) {
    *cap = *cap ? 2 * *cap : 1024;
    *a = peri_realloc(*a, sizeof(int64_t) * (size_t)*cap);
  }
  (*a)[(*n)++] = v;
}

peri_bond_halo *peri_bond_halo_build(const peri_bonds *global, const int64_t *reverse, const int64_t *first,
                                     const int64_t *bond_first, int rank, int size) {
  peri_bond_halo *h = peri_calloc(1, sizeof *h);
  h->rank = peri_malloc(sizeof(int) * (size_t)(size > 0 ? size : 1));
  h->start = peri_calloc((size_t)size + 1, sizeof(int64_t));
  const int64_t g0 = first[rank], g1 = first[rank + 1], b0 = bond_first[rank], b1 = bond_first[rank + 1];
  int64_t n_send = 0, n_recv = 0, send_cap = 0, recv_cap = 0;
  for (int q = 0; q < size; ++q) {
    if (q == rank) continue;
    const int64_t before = n_recv;
    /* received: this rank's bonds into q's nodes, in bond order */
    for (int64_t k = b0; k < b1; ++k)
      if (global->neighbor[k] >= first[q] && global->neighbor[k] < first[q + 1]) append(&h->recv_bond, &n_recv, &recv_cap, k - b0);
    /* sent: the reverses of q's bonds into this rank's nodes, in q's bond order (its receive order) */
    for (int64_t k = bond_first[q]; k < bond_first[q + 1]; ++k)
      if (global->neighbor[k] >= g0 && global->neighbor[k] < g1) append(&h->send_bond, &n_send, &send_cap, reverse[k] - b0);
    if (n_send != n_recv) { /* the reverse index pairs every bond with one of the other direction */
      peri_error("internal: %lld bonds from rank %d into rank %d's nodes, %lld back", (long long)(n_send - before), q,
                 rank, (long long)(n_recv - before));
      abort();
    }
    if (n_recv == before) continue;
    h->rank[h->n_neighbors] = q;
    h->start[++h->n_neighbors] = n_recv;
  }
  if (!h->send_bond) h->send_bond = peri_malloc(sizeof(int64_t));
  if (!h->recv_bond) h->recv_bond = peri_malloc(sizeof(int64_t));
  h->send_buffer = peri_malloc(sizeof(double) * (size_t)(n_send > 0 ? n_send : 1));
  h->recv_buffer = peri_malloc(sizeof(double) * (size_t)(n_recv > 0 ? n_recv : 1));
  h->requests = peri_comm_requests(2 * h->n_neighbors);
  return h;
}

void peri_bond_halo_exchange(peri_bond_halo *h, peri_bond_pack pack, const void *context, double *into) {
  if (!h) return;
  peri_comm_check("bond halo exchange"); /* every rank takes part, with or without neighbours */
  int n_req = 0;
  for (int m = 0; m < h->n_neighbors; ++m)
    peri_comm_irecv(h->recv_buffer + h->start[m], h->start[m + 1] - h->start[m], h->rank[m], h->requests, n_req++);
  for (int m = 0; m < h->n_neighbors; ++m) {
    const int64_t a = h->start[m], n = h->start[m + 1] - a;
    pack(context, h->send_bond + a, n, h->send_buffer + a);
    peri_comm_isend(h->send_buffer + a, n, h->rank[m], h->requests, n_req++);
  }
  peri_comm_waitall(h->requests, n_req);
  const int64_t n = h->start[h->n_neighbors];
  for (int64_t a = 0; a < n; ++a) into[h->recv_bond[a]] = h->recv_buffer[a];
}

int64_t peri_bond_halo_volume(const peri_bond_halo *h) { return h ? h->start[h->n_neighbors] : 0; }

void peri_bond_halo_free(peri_bond_halo *h) {
  if (!h) return;
  free(h->rank);
  free(h->start);
  free(h->send_bond);
  free(h->recv_bond);
  free(h->send_buffer);
  free(h->recv_buffer);
  free(h->requests);
  free(h);
}
