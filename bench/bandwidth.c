/* Memory bandwidth of this machine for the roofline estimate of docs/performance.md: the
 * STREAM triad a = b + s c over arrays far larger than the caches, best of 10 passes,
 * counting 24 bytes per element (two loads and a store; write-allocate traffic not counted,
 * as in STREAM). Usage: bandwidth [threads]. */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv) {
  if (argc > 1) omp_set_num_threads(atoi(argv[1]));
  const size_t n = (size_t)1 << 25; /* 3 x 256 MiB */
  double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
  if (!a || !b || !c) return 1;
#pragma omp parallel for schedule(static)
  for (size_t i = 0; i < n; ++i) a[i] = 0.0, b[i] = 1.0, c[i] = 2.0;
  double best = 1e30;
  for (int pass = 0; pass < 10; ++pass) {
    const double t0 = omp_get_wtime();
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; ++i) a[i] = b[i] + 3.0 * c[i];
    const double t = omp_get_wtime() - t0;
    if (t < best) best = t;
  }
  printf("%.1f GB/s (triad, %d threads, check %g)\n", 24.0 * (double)n / best / 1e9, omp_get_max_threads(), a[n / 2]);
  free(a);
  free(b);
  free(c);
  return 0;
}
