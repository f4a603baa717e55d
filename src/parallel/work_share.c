/* Contiguous shares with stealing from the back (include/peri/work_share.h). */
#include "peri/work_share.h"
#include <omp.h>
#include <stdatomic.h>
#include <stdlib.h>
#include "peri/error.h"

/* a share [front, back) packed in one word (front low, back high), so that the owner taking
 * from the front and a thief taking from the back agree through one compare-and-swap */
typedef struct {
  _Atomic uint64_t range;
  char pad[64 - sizeof(uint64_t)]; /* one cache line per thread: no false sharing */
} share_slot;

struct peri_work_share {
  void *memory;     /* slot, aligned to a cache line within it */
  share_slot *slot;
  int capacity, threads;
  int32_t chunk;
};

/* chunks: at most MAX_CHUNK items, and at least CHUNKS_PER_SHARE per share, so that the
 * last chunk of a pass is a small part of a thread's work */
enum { MAX_CHUNK = 64, CHUNKS_PER_SHARE = 32 };

static uint64_t pack(uint32_t front, uint32_t back) { return (uint64_t)back << 32 | front; }
static uint32_t front_of(uint64_t r) { return (uint32_t)r; }
static uint32_t back_of(uint64_t r) { return (uint32_t)(r >> 32); }

peri_work_share *peri_work_share_new(void) { return peri_calloc(1, sizeof(peri_work_share)); }

void peri_work_share_free(peri_work_share *ws) {
  if (!ws) return;
  free(ws->memory);
  free(ws);
}

/* first item k with cost_prefix[k] >= target */
static int32_t first_at_cost(const int64_t *cost_prefix, int32_t n, int64_t target) {
  int32_t lo = 0, hi = n;
  while (lo < hi) {
    const int32_t mid = lo + (hi - lo) / 2;
    if (cost_prefix[mid] < target) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

void peri_work_share_start(peri_work_share *ws, const int64_t *cost_prefix, int32_t n) {
#pragma omp single
  {
    const int threads = omp_get_num_threads();
    if (threads > ws->capacity) {
      free(ws->memory);
      ws->memory = peri_malloc(sizeof(share_slot) * ((size_t)threads + 1));
      ws->slot = (share_slot *)(((uintptr_t)ws->memory + 63) & ~(uintptr_t)63);
      ws->capacity = threads;
    }
    ws->threads = threads;
    const int64_t total = cost_prefix[n] - cost_prefix[0];
    int32_t begin = 0;
    for (int t = 0; t < threads; ++t) {
      const int32_t end =
          t + 1 == threads ? n : first_at_cost(cost_prefix, n, cost_prefix[0] + total * (t + 1) / threads);
      atomic_init(&ws->slot[t].range, pack((uint32_t)begin, (uint32_t)(end > begin ? end : begin)));
      begin = end > begin ? end : begin;
    }
    const int32_t per_share = n / (threads * CHUNKS_PER_SHARE);
    ws->chunk = per_share < 1 ? 1 : per_share > MAX_CHUNK ? MAX_CHUNK : per_share;
  } /* implied barrier: every thread sees the shares */
}

bool peri_work_share_next(peri_work_share *ws, int32_t *begin, int32_t *end) {
  const uint32_t chunk = (uint32_t)ws->chunk;
  _Atomic uint64_t *own = &ws->slot[omp_get_thread_num()].range;
  uint64_t r = atomic_load(own);
  while (front_of(r) < back_of(r)) { /* own share, from the front */
    const uint32_t f = front_of(r), b = back_of(r), taken = b - f > chunk ? f + chunk : b;
    if (atomic_compare_exchange_weak(own, &r, pack(taken, b))) {
      *begin = (int32_t)f;
      *end = (int32_t)taken;
      return true;
    }
  }
  for (;;) { /* the back of the share with the most left */
    int victim = -1;
    uint32_t most = 0;
    for (int t = 0; t < ws->threads; ++t) {
      const uint64_t v = atomic_load(&ws->slot[t].range);
      if (back_of(v) > front_of(v) && back_of(v) - front_of(v) > most) {
        most = back_of(v) - front_of(v);
        victim = t;
      }
    }
    if (victim < 0) return false;
    _Atomic uint64_t *share = &ws->slot[victim].range;
    uint64_t v = atomic_load(share);
    while (front_of(v) < back_of(v)) {
      const uint32_t f = front_of(v), b = back_of(v), taken = b - f > chunk ? b - chunk : f;
      if (atomic_compare_exchange_weak(share, &v, pack(f, taken))) {
        *begin = (int32_t)taken;
        *end = (int32_t)b;
        return true;
      }
    }
  }
}
