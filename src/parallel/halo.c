/* Halo exchange between neighbouring ranks (include/peri/halo.h): receives are posted into
 * the ghost slots first, then the packed owned values are sent, then both are awaited. */
#include <stdlib.h>
#include "peri/error.h"
#include "peri/halo.h"

void peri_halo_exchange(peri_halo *h, double *field, int ncomp) {
  if (!h) return;
  peri_comm_check("halo exchange"); /* every rank takes part, with or without neighbours */
  if (h->n_neighbors == 0) return;
  if (ncomp < 1 || ncomp > PERI_HALO_MAX_COMPONENTS) {
    peri_error("internal: halo exchange of %d components (1 to %d)", ncomp, PERI_HALO_MAX_COMPONENTS);
    abort();
  }
  int n_req = 0;
  for (int m = 0; m < h->n_neighbors; ++m)
    if (h->recv_count[m] > 0)
      peri_comm_irecv(field + (size_t)ncomp * h->recv_start[m], (int64_t)ncomp * h->recv_count[m], h->rank[m],
                      h->requests, n_req++);
  for (int m = 0; m < h->n_neighbors; ++m) {
    const int64_t a = h->send_start[m], b = h->send_start[m + 1];
    if (b == a) continue;
    double *buf = h->send_buffer + (size_t)ncomp * a;
    for (int64_t k = a; k < b; ++k)
      for (int c = 0; c < ncomp; ++c) buf[(size_t)ncomp * (k - a) + c] = field[(size_t)ncomp * h->send_node[k] + c];
    peri_comm_isend(buf, (int64_t)ncomp * (b - a), h->rank[m], h->requests, n_req++);
  }
  peri_comm_waitall(h->requests, n_req);
}

int64_t peri_halo_send_volume(const peri_halo *h) { return h->n_neighbors ? h->send_start[h->n_neighbors] : 0; }

void peri_halo_free(peri_halo *h) {
  free(h->rank);
  free(h->recv_start);
  free(h->recv_count);
  free(h->send_start);
  free(h->send_node);
  free(h->send_buffer);
  free(h->requests);
}
