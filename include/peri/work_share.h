/* Items 0 .. n-1 of a loop shared among the threads of an OpenMP team. Thread t owns a
 * contiguous share of about equal cost and runs it from the front in chunks; a thread whose
 * share is done takes chunks from the back of the share with the most left. Each thread so
 * works through one long run of consecutive items (the neighbour rows it reads stay in its
 * own core's cache, and it gets the same run in every pass over the nodes), and the last
 * chunks balance the load. Which thread runs an item never changes what the item computes. */
#ifndef PERI_WORK_SHARE_H
#define PERI_WORK_SHARE_H
#include <stdbool.h>
#include <stdint.h>

typedef struct peri_work_share peri_work_share;

peri_work_share *peri_work_share_new(void);
void peri_work_share_free(peri_work_share *ws);

/* Inside a parallel region, called by every thread of the team before its first
 * peri_work_share_next (a barrier: one thread sets the shares). cost_prefix[k] is the
 * cumulative cost of items 0 .. k-1 (n + 1 entries, non-decreasing). One pass per parallel
 * region and sharer: a second start in the same region could reset the shares while a
 * thread still takes chunks of the first. */
void peri_work_share_start(peri_work_share *ws, const int64_t *cost_prefix, int32_t n);

/* The calling thread's next chunk [*begin, *end); false when no item is left. */
bool peri_work_share_next(peri_work_share *ws, int32_t *begin, int32_t *end);

#endif
