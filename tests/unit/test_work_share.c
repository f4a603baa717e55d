/* Sharing a loop's items among threads (include/peri/work_share.h): every item exactly once,
 * each thread's own share contiguous and in order, shares split by cost. */
#include <criterion/criterion.h>
#include <omp.h>
#include <stdlib.h>
#include "peri/work_share.h"

enum { MAX_ITEMS = 5000, MAX_THREADS = 4 };

/* cost prefixes: every item 1; all the cost in item 0; item k costs k (a ramp) */
static void fill_prefix(int64_t *prefix, int32_t n, int kind) {
  prefix[0] = 0;
  for (int32_t k = 0; k < n; ++k) prefix[k + 1] = prefix[k] + (kind == 0 ? 1 : kind == 1 ? (k == 0 ? 1000 : 0) : k);
}

/* Runs one pass on `threads` threads; visits[k] counts the times item k was handed out. */
static void run_pass(peri_work_share *ws, const int64_t *prefix, int32_t n, int threads, int *visits) {
  for (int32_t k = 0; k < n; ++k) visits[k] = 0;
#pragma omp parallel num_threads(threads)
  {
    peri_work_share_start(ws, prefix, n);
    int32_t begin, end;
    while (peri_work_share_next(ws, &begin, &end)) {
      cr_expect(0 <= begin && begin < end && end <= n, "chunk [%d, %d) of %d items", begin, end, n);
      for (int32_t k = begin; k < end; ++k) {
#pragma omp atomic
        ++visits[k];
      }
    }
  }
}

Test(work_share, every_item_exactly_once) {
  static int64_t prefix[MAX_ITEMS + 1];
  static int visits[MAX_ITEMS];
  const int32_t sizes[] = {0, 1, 7, 100, 1000, MAX_ITEMS};
  peri_work_share *ws = peri_work_share_new();
  /* the same sharer over passes of different sizes and team sizes (its slots grow) */
  for (int threads = 1; threads <= MAX_THREADS; ++threads)
    for (int kind = 0; kind < 3; ++kind)
      for (size_t s = 0; s < sizeof sizes / sizeof *sizes; ++s) {
        const int32_t n = sizes[s];
        fill_prefix(prefix, n, kind);
        run_pass(ws, prefix, n, threads, visits);
        for (int32_t k = 0; k < n; ++k)
          cr_assert_eq(visits[k], 1, "item %d of %d handed out %d times (%d threads, costs %d)", k, n, visits[k],
                       threads, kind);
      }
  peri_work_share_free(ws);
}

Test(work_share, one_thread_runs_items_in_order) {
  static int64_t prefix[1001];
  fill_prefix(prefix, 1000, 2);
  peri_work_share *ws = peri_work_share_new();
  int32_t expected = 0, begin, end;
#pragma omp parallel num_threads(1)
  {
    peri_work_share_start(ws, prefix, 1000);
    while (peri_work_share_next(ws, &begin, &end)) {
      cr_assert_eq(begin, expected, "chunk starts at %d, expected %d", begin, expected);
      expected = end;
    }
  }
  cr_assert_eq(expected, 1000);
  peri_work_share_free(ws);
}

/* The first item each of `threads` threads gets (first[t]), before any thread can steal:
 * each takes one chunk, then all wait, then the rest of the pass is drained. */
static void first_chunks(const int64_t *prefix, int32_t n, int threads, int32_t *first) {
  peri_work_share *ws = peri_work_share_new();
#pragma omp parallel num_threads(threads)
  {
    peri_work_share_start(ws, prefix, n);
    int32_t begin, end;
    cr_expect(peri_work_share_next(ws, &begin, &end));
    first[omp_get_thread_num()] = begin;
#pragma omp barrier
    while (peri_work_share_next(ws, &begin, &end)) {
    }
  }
  peri_work_share_free(ws);
}

/* Before any stealing a thread's first chunk is the front of its own share, and the shares
 * split the cost evenly: with equal costs, thread t of T starts at t n / T. */
Test(work_share, first_chunks_start_the_equal_cost_shares) {
  enum { N = 4000, T = 4 };
  static int64_t prefix[N + 1];
  fill_prefix(prefix, N, 0);
  int32_t first[T];
  first_chunks(prefix, N, T, first);
  for (int t = 0; t < T; ++t) cr_assert_eq(first[t], t * N / T, "thread %d starts at %d", t, first[t]);
}

/* With costs on a ramp (item k costs k) the two shares of two threads hold half the cost
 * each: the second starts at the k with k (k - 1) / 2 >= n (n - 1) / 4, about n / sqrt 2. */
Test(work_share, shares_split_by_cost) {
  enum { N = 1000 };
  static int64_t prefix[N + 1];
  fill_prefix(prefix, N, 2);
  int32_t first[2];
  first_chunks(prefix, N, 2, first);
  int32_t k = 0;
  while ((int64_t)k * (k - 1) / 2 < (int64_t)N * (N - 1) / 4) ++k;
  cr_assert_eq(first[0], 0);
  cr_assert_eq(first[1], k, "second share starts at %d, expected %d (about %.0f)", first[1], k, N / 1.41421356);
}
