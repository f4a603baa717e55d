/* The ghosts of short-range contact (include/peri/contact_ghosts.h). A rank's owned nodes
 * are a contiguous range of the global order and each peer's nodes are sent in their owned
 * order, so the slots filled peer by peer in rank order are in global order, with the owned
 * nodes between the lower and the higher ranks' ghosts. */
#include <float.h>
#include <stdlib.h>
#include <string.h>
#include "peri/contact_ghosts.h"
#include "peri/error.h"

/* Values of a node sent at a build: x (3), y (3), volume, material (exact as a double). */
enum { BUILD_VALUES = 8 };

static void free_plan(peri_contact_ghosts *g) {
  free(g->peer);
  free(g->recv_start);
  free(g->recv_count);
  free(g->send_start);
  free(g->send_node);
  free(g->buffer);
  free(g->requests);
  const long ghosts = g->ghosts;
  memset(g, 0, sizeof *g);
  g->ghosts = ghosts;
}

static void size_nodes(peri_contact_nodes *nodes, int32_t n) {
  const size_t m = n > 0 ? (size_t)n : 1;
  nodes->x = peri_realloc(nodes->x, sizeof(double) * 3 * m);
  nodes->y = peri_realloc(nodes->y, sizeof(double) * 3 * m);
  nodes->volume = peri_realloc(nodes->volume, sizeof(double) * m);
  nodes->material = peri_realloc(nodes->material, sizeof(int32_t) * m);
  nodes->n = n;
}

/* The box of the owned deformed positions (empty: lo above hi). */
static void owned_box(const double *y, int32_t n_owned, double box[6]) {
  for (int a = 0; a < 3; ++a) box[a] = DBL_MAX, box[3 + a] = -DBL_MAX;
  for (int32_t i = 0; i < n_owned; ++i)
    for (int a = 0; a < 3; ++a) {
      const double v = y[3 * (size_t)i + a];
      if (v < box[a]) box[a] = v;
      if (v > box[3 + a]) box[3 + a] = v;
    }
}

static bool within(const double *y, const double box[6], double reach) {
  for (int a = 0; a < 3; ++a)
    if (!(y[a] >= box[a] - reach && y[a] <= box[3 + a] + reach)) return false;
  return true;
}

void peri_contact_ghosts_build(peri_contact_ghosts *g, peri_contact_nodes *nodes, int32_t n_owned, const double *x,
                               const double *y, const double *volume, const int32_t *material, double reach) {
  peri_comm_check("contact ghosts build");
  const int rank = peri_comm_rank(), size = peri_comm_size();
  free_plan(g);
  /* every rank's box, then what each rank sends to each other one */
  double mine[6], *boxes = peri_malloc(sizeof(double) * 6 * (size_t)size);
  owned_box(y, n_owned, mine);
  int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)size);
  for (int q = 0; q < size; ++q) counts[q] = 6;
  peri_comm_allgather_doubles(mine, 6, counts, boxes);
  double *send_count = peri_calloc((size_t)size, sizeof(double));
  int64_t n_send = 0;
  for (int q = 0; q < size; ++q) {
    if (q == rank) continue;
    for (int32_t i = 0; i < n_owned; ++i)
      if (within(&y[3 * (size_t)i], &boxes[6 * (size_t)q], reach)) ++send_count[q];
    n_send += (int64_t)send_count[q];
  }
  double *matrix = peri_malloc(sizeof(double) * (size_t)size * (size_t)size); /* [from * size + to] */
  for (int q = 0; q < size; ++q) counts[q] = size;
  peri_comm_allgather_doubles(send_count, size, counts, matrix);
  free(counts);

  /* peers in rank order; ghost slots: lower ranks', the owned nodes, higher ranks' */
  g->peer = peri_malloc(sizeof(int) * (size_t)size);
  g->recv_start = peri_malloc(sizeof(int32_t) * (size_t)size);
  g->recv_count = peri_malloc(sizeof(int32_t) * (size_t)size);
  g->send_start = peri_calloc((size_t)size + 1, sizeof(int64_t));
  g->send_node = peri_malloc(sizeof(int32_t) * (size_t)(n_send > 0 ? n_send : 1));
  int32_t slot = 0, below = 0;
  for (int q = 0; q < size; ++q) {
    if (q == rank) {
      below = slot;
      slot += n_owned;
      continue;
    }
    const int32_t from_q = (int32_t)matrix[(size_t)q * (size_t)size + (size_t)rank];
    if (from_q == 0 && send_count[q] == 0.0) continue;
    const int m = g->n_peers++;
    g->peer[m] = q;
    g->recv_start[m] = slot;
    g->recv_count[m] = from_q;
    slot += from_q;
    int64_t k = g->send_start[m];
    for (int32_t i = 0; i < n_owned; ++i)
      if (within(&y[3 * (size_t)i], &boxes[6 * (size_t)q], reach)) g->send_node[k++] = i;
    g->send_start[m + 1] = k;
  }
  free(matrix);
  free(send_count);
  free(boxes);
  g->ghosts = slot - n_owned;
  size_nodes(nodes, slot);
  nodes->first_owned = below;
  memcpy(&nodes->x[3 * (size_t)below], x, sizeof(double) * 3 * (size_t)n_owned);
  memcpy(&nodes->y[3 * (size_t)below], y, sizeof(double) * 3 * (size_t)n_owned);
  memcpy(&nodes->volume[below], volume, sizeof(double) * (size_t)n_owned);
  memcpy(&nodes->material[below], material, sizeof(int32_t) * (size_t)n_owned);

  /* the ghosts' values, received packed and laid out in their slots */
  const int64_t sent = g->send_start[g->n_peers];
  g->buffer = peri_malloc(sizeof(double) * BUILD_VALUES * (size_t)(sent > 0 ? sent : 1));
  double *received = peri_malloc(sizeof(double) * BUILD_VALUES * (size_t)(g->ghosts > 0 ? g->ghosts : 1));
  g->requests = peri_comm_requests(2 * g->n_peers);
  int n_req = 0;
  for (int m = 0; m < g->n_peers; ++m) {
    const int32_t at = g->recv_start[m] - (g->peer[m] > rank ? n_owned : 0); /* ghost index */
    if (g->recv_count[m] > 0)
      peri_comm_irecv(&received[BUILD_VALUES * (size_t)at], (int64_t)BUILD_VALUES * g->recv_count[m], g->peer[m], g->requests,
                      n_req++);
  }
  for (int m = 0; m < g->n_peers; ++m) {
    const int64_t a = g->send_start[m], b = g->send_start[m + 1];
    if (b == a) continue;
    for (int64_t k = a; k < b; ++k) {
      const int32_t i = g->send_node[k];
      double *v = &g->buffer[BUILD_VALUES * (size_t)k];
      for (int c = 0; c < 3; ++c) v[c] = x[3 * (size_t)i + c], v[3 + c] = y[3 * (size_t)i + c];
      v[6] = volume[i];
      v[7] = (double)material[i];
    }
    peri_comm_isend(&g->buffer[BUILD_VALUES * (size_t)a], BUILD_VALUES * (b - a), g->peer[m], g->requests, n_req++);
  }
  peri_comm_waitall(g->requests, n_req);
  for (int32_t k = 0; k < (int32_t)g->ghosts; ++k) {
    const int32_t s = k < below ? k : k + n_owned; /* the ghost's slot */
    const double *v = &received[BUILD_VALUES * (size_t)k];
    for (int c = 0; c < 3; ++c) nodes->x[3 * (size_t)s + c] = v[c], nodes->y[3 * (size_t)s + c] = v[3 + c];
    nodes->volume[s] = v[6];
    nodes->material[s] = (int32_t)v[7];
  }
  free(received);
}

void peri_contact_ghosts_refresh(peri_contact_ghosts *g, peri_contact_nodes *nodes) {
  peri_comm_check("contact ghosts refresh");
  if (g->n_peers == 0) return;
  const double *y_owned = &nodes->y[3 * (size_t)nodes->first_owned];
  int n_req = 0;
  for (int m = 0; m < g->n_peers; ++m)
    if (g->recv_count[m] > 0)
      peri_comm_irecv(&nodes->y[3 * (size_t)g->recv_start[m]], 3 * (int64_t)g->recv_count[m], g->peer[m], g->requests, n_req++);
  for (int m = 0; m < g->n_peers; ++m) {
    const int64_t a = g->send_start[m], b = g->send_start[m + 1];
    if (b == a) continue;
    for (int64_t k = a; k < b; ++k)
      for (int c = 0; c < 3; ++c) g->buffer[3 * (size_t)k + c] = y_owned[3 * (size_t)g->send_node[k] + c];
    peri_comm_isend(&g->buffer[3 * (size_t)a], 3 * (b - a), g->peer[m], g->requests, n_req++);
  }
  peri_comm_waitall(g->requests, n_req);
}

void peri_contact_ghosts_free(peri_contact_ghosts *g, peri_contact_nodes *nodes) {
  free_plan(g);
  free(nodes->x);
  free(nodes->y);
  free(nodes->volume);
  free(nodes->material);
  memset(nodes, 0, sizeof *nodes);
}
