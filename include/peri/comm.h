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
void peri_comm_barrier(void);

/* Exact reductions over all ranks (the same result on every rank). */
long peri_comm_sum_long(long value);
int peri_comm_max_int(int value);
double peri_comm_min(double value);
double peri_comm_max(double value);
/* True on every rank when `value` is true on every rank. */
bool peri_comm_all(bool value);

/* Rank 0 receives the concatenation, in rank order, of `count` doubles from every rank
 * (counts[r] of rank r, known to all); `out` is used on rank 0 only. */
void peri_comm_gather_doubles(const double *local, int64_t count, const int64_t *counts, double *out);
/* Rank 0 receives the concatenation, in rank order, of `count` bytes from every rank
 * (counts[r] of rank r, known to all; 64-bit counts: per-bond arrays of large problems pass
 * 2^31); `out` is used on rank 0 only. */
void peri_comm_gather_bytes(const uint8_t *local, int64_t count, const int64_t *counts, uint8_t *out);
/* The same concatenation on every rank. */
void peri_comm_allgather_doubles(const double *local, int64_t count, const int64_t *counts, double *out);
/* Rank 0's `count` doubles to every rank. */
void peri_comm_broadcast_doubles(double *values, int count);

/* Non-blocking point-to-point messages of doubles for the halo exchange. */
typedef struct peri_comm_request peri_comm_request;
/* Array of n requests, freed with free(). */
peri_comm_request *peri_comm_requests(int n);
void peri_comm_isend(const double *data, int64_t count, int to, peri_comm_request *r, int k);
void peri_comm_irecv(double *data, int64_t count, int from, peri_comm_request *r, int k);
/* Waits for the first n requests. */
void peri_comm_waitall(peri_comm_request *r, int n);

#endif
