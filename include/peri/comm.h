/* The thin message-passing layer: every MPI call of peri goes through these functions, which
 * fall back to a single process when peri is built without MPI (PERI_HAVE_MPI undefined).
 * Reductions that must not depend on the process count are exact (integers, min, max) or
 * combine values in a fixed order on rank 0 (see peri_sum_owned in decompose.h). */
#ifndef PERI_COMM_H
#define PERI_COMM_H
#include <stdbool.h>
#include <stdint.h>

/* Starts MPI (when built with it). Ranks other than 0 send stdout and stderr to /dev/null
 * so that messages are printed once (every rank reads the same deck and reports the same
 * errors). Call once at the start of main. */
void peri_comm_init(int *argc, char ***argv);
/* Ends MPI. */
void peri_comm_finalize(void);
/* Stops every rank with `status` (after a failure that not all ranks saw). */
void peri_comm_abort(int status);

int peri_comm_rank(void);
int peri_comm_size(void);

/* Every collective call names its call site (file:line), so that the check of the sequence
 * of collectives (PERI_CHECK_COLLECTIVES=1, docs/parallel.md) can say where each rank is. */
#define PERI_COMM_STR_(x) #x
#define PERI_COMM_STR(x) PERI_COMM_STR_(x)
#define PERI_COMM_SITE __FILE__ ":" PERI_COMM_STR(__LINE__)

/* With PERI_CHECK_COLLECTIVES set (and not 0) in the environment, every collective call
 * (the functions below, the halo exchange and the end of MPI) first checks that all ranks
 * are at the same call of the same site, and stops every rank with a message naming where
 * each one is when they are not: a run whose ranks took different branches stops there
 * instead of hanging or mixing unrelated values. Off by default (one small message per
 * collective). `call` names the operation. */
void peri_comm_check_at(const char *call, const char *site);
#define peri_comm_check(call) peri_comm_check_at((call), PERI_COMM_SITE)

void peri_comm_barrier_at(const char *site);
#define peri_comm_barrier() peri_comm_barrier_at(PERI_COMM_SITE)

/* Exact reductions over all ranks (the same result on every rank). */
long peri_comm_sum_long_at(long value, const char *site);
int peri_comm_max_int_at(int value, const char *site);
double peri_comm_min_at(double value, const char *site);
double peri_comm_max_at(double value, const char *site);
#define peri_comm_sum_long(value) peri_comm_sum_long_at((value), PERI_COMM_SITE)
#define peri_comm_max_int(value) peri_comm_max_int_at((value), PERI_COMM_SITE)
#define peri_comm_min(value) peri_comm_min_at((value), PERI_COMM_SITE)
#define peri_comm_max(value) peri_comm_max_at((value), PERI_COMM_SITE)
/* True on every rank when `value` is true on every rank. */
bool peri_comm_all_at(bool value, const char *site);
#define peri_comm_all(value) peri_comm_all_at((value), PERI_COMM_SITE)

/* Rank 0 receives the concatenation, in rank order, of `count` doubles from every rank
 * (counts[r] of rank r, known to all); `out` is used on rank 0 only. */
void peri_comm_gather_doubles_at(const double *local, int64_t count, const int64_t *counts, double *out,
                                 const char *site);
#define peri_comm_gather_doubles(local, count, counts, out) \
  peri_comm_gather_doubles_at((local), (count), (counts), (out), PERI_COMM_SITE)
/* Rank 0 receives the concatenation, in rank order, of `count` bytes from every rank
 * (counts[r] of rank r, known to all; 64-bit counts: per-bond arrays of large problems pass
 * 2^31); `out` is used on rank 0 only. */
void peri_comm_gather_bytes_at(const uint8_t *local, int64_t count, const int64_t *counts, uint8_t *out,
                               const char *site);
#define peri_comm_gather_bytes(local, count, counts, out) \
  peri_comm_gather_bytes_at((local), (count), (counts), (out), PERI_COMM_SITE)
/* The same concatenation on every rank. */
void peri_comm_allgather_doubles_at(const double *local, int64_t count, const int64_t *counts, double *out,
                                    const char *site);
#define peri_comm_allgather_doubles(local, count, counts, out) \
  peri_comm_allgather_doubles_at((local), (count), (counts), (out), PERI_COMM_SITE)
/* Rank 0's `count` doubles to every rank. */
void peri_comm_broadcast_doubles_at(double *values, int count, const char *site);
#define peri_comm_broadcast_doubles(values, count) peri_comm_broadcast_doubles_at((values), (count), PERI_COMM_SITE)

/* Non-blocking point-to-point messages of doubles for the halo exchange. */
typedef struct peri_comm_request peri_comm_request;
/* Array of n requests, freed with free(). */
peri_comm_request *peri_comm_requests(int n);
void peri_comm_isend(const double *data, int64_t count, int to, peri_comm_request *r, int k);
void peri_comm_irecv(double *data, int64_t count, int from, peri_comm_request *r, int k);
/* Waits for the first n requests. */
void peri_comm_waitall(peri_comm_request *r, int n);

#endif
