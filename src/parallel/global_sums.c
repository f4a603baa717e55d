/* Global quantities of a distributed run (include/peri/decompose.h): sums in fixed-order
 * blocks of the global node order, exact counts, and gathers to rank 0 in global order. */
#include <stdlib.h>
#include <string.h>
#include "peri/comm.h"
#include "peri/decompose.h"
#include "peri/error.h"

enum { SMALL_SUM = 16 };

int64_t peri_sum_blocks_owned(const peri_sim *s) { return (s->disc.p.n_owned + PERI_SUM_BLOCK - 1) / PERI_SUM_BLOCK; }

void peri_sum_owned(const peri_sim *s, const double *terms, int ncomp, double *out) {
  const int32_t n = s->disc.p.n_owned;
  const int64_t n_blocks = peri_sum_blocks_owned(s);
  double *block = peri_calloc((size_t)(n_blocks > 0 ? n_blocks : 1) * (size_t)ncomp, sizeof(double));
#pragma omp parallel for schedule(static) if (n_blocks > 16)
  for (int64_t k = 0; k < n_blocks; ++k) {
    const int32_t a = (int32_t)(k * PERI_SUM_BLOCK), e = a + PERI_SUM_BLOCK < n ? a + PERI_SUM_BLOCK : n;
    for (int c = 0; c < ncomp; ++c) {
      double sum = 0.0;
      for (int32_t i = a; i < e; ++i) sum += terms[(size_t)ncomp * i + c];
      block[k * ncomp + c] = sum;
    }
  }
  peri_sum_blocks(s, block, ncomp, out);
  free(block);
}

void peri_sum_blocks(const peri_sim *s, const double *block, int ncomp, double *out) {
  const int64_t n_blocks = peri_sum_blocks_owned(s);
  const peri_decomposition *d = s->par.dd;
  /* (a small sum, every explicit step's, stays off the heap; the bodies' many columns take it) */
  double small[SMALL_SUM] = {0};
  double *total = ncomp <= SMALL_SUM ? small : peri_calloc((size_t)ncomp, sizeof(double));
  if (!d) {
    for (int64_t k = 0; k < n_blocks; ++k)
      for (int c = 0; c < ncomp; ++c) total[c] += block[k * ncomp + c];
  } else {
    int64_t all = 0;
    int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)d->size);
    for (int r = 0; r < d->size; ++r) {
      counts[r] = d->blocks[r] * ncomp;
      all += counts[r];
    }
    /* every rank gets all block sums and adds them in the same order */
    double *every = peri_malloc(sizeof(double) * (size_t)(all > 0 ? all : 1));
    peri_comm_allgather_doubles(block, n_blocks * ncomp, counts, every);
    for (int64_t k = 0; k < all / ncomp; ++k)
      for (int c = 0; c < ncomp; ++c) total[c] += every[k * ncomp + c];
    free(every);
    free(counts);
  }
  for (int c = 0; c < ncomp; ++c) out[c] = total[c];
  if (total != small) free(total);
}

int64_t peri_global_nodes(const peri_sim *s) { return s->par.dd ? s->par.dd->n_global : s->disc.p.n_owned; }
int64_t peri_global_bonds(const peri_sim *s) { return s->par.dd ? s->par.dd->n_bonds_global : s->disc.bonds.n_bonds; }
long peri_global_broken(const peri_sim *s) {
  const long local = peri_broken_count(&s->disc.bonds);
  return s->par.dd ? peri_comm_sum_long(local) : local;
}

void peri_gather_owned(const peri_sim *s, const double *local, int ncomp, double *out) {
  const peri_decomposition *d = s->par.dd;
  if (!d) {
    memcpy(out, local, sizeof(double) * (size_t)ncomp * (size_t)s->disc.p.n_owned);
    return;
  }
  int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)d->size);
  for (int r = 0; r < d->size; ++r) counts[r] = d->owned[r] * ncomp;
  peri_comm_gather_doubles(local, (int64_t)s->disc.p.n_owned * ncomp, counts, out);
  free(counts);
}

void peri_gather_owned_bonds(const peri_sim *s, const uint8_t *local, uint8_t *out) {
  const peri_decomposition *d = s->par.dd;
  if (!d) {
    if (s->disc.bonds.n_bonds > 0) memcpy(out, local, (size_t)s->disc.bonds.n_bonds);
    return;
  }
  /* each rank's families are one contiguous run of the global bond order, in rank order */
  int64_t *counts = peri_malloc(sizeof(int64_t) * (size_t)d->size);
  for (int r = 0; r < d->size; ++r) counts[r] = d->bond_first[r + 1] - d->bond_first[r];
  peri_comm_gather_bytes(local, s->disc.bonds.n_bonds, counts, out);
  free(counts);
}
