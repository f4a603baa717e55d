/* OpenMP wait policy chosen by peri (docs/parallel.md, "Threads on a busy machine").
 *
 * libgomp's default lets an idle thread spin for about 300,000 iterations (a fraction of a
 * millisecond) before it sleeps. On a machine where other processes hold the cores, the
 * spinning threads steal the time the working ones need and every step waits for a thread
 * that has no core: runs were 4 to 37 times slower than with short waits (docs/parallel.md,
 * bench/dayone). Sleeping at once (OMP_WAIT_POLICY=passive) cures that but costs 1.1 to 1.9
 * times on an idle machine, where a quasi-static solve's short parallel loops pay a thread's
 * wake-up each time. A short spin of SHORT_SPIN iterations (a few microseconds) before
 * sleeping was as fast as libgomp's default on an idle machine and as passive waiting on a
 * busy one (docs/parallel.md). The runtime reads its environment when it is loaded, before
 * main, so peri sets GOMP_SPINCOUNT and executes itself again, once; a user's
 * OMP_WAIT_POLICY, GOMP_SPINCOUNT or KMP_BLOCKTIME (LLVM's libomp) is left alone. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "omp_wait.h"

/* Marks the process started again by peri_choose_omp_wait (and reports the choice). */
#define MARK "PERI_OMP_WAIT_CHOSEN"
/* libgomp spin iterations before a waiting thread sleeps (its default: 300,000) */
#define SHORT_SPIN "3000"

void peri_choose_omp_wait(char **argv) {
  /* MPI ranks waiting in Open MPI give their core away too (read at MPI_Init, so no exec is
   * needed); a value given with `mpirun --mca mpi_yield_when_idle 0` arrives set and stays */
  setenv("OMPI_MCA_mpi_yield_when_idle", "1", 0);
  if (getenv("OMP_WAIT_POLICY") || getenv("GOMP_SPINCOUNT") || getenv("KMP_BLOCKTIME") || getenv(MARK)) return;
  if (setenv("GOMP_SPINCOUNT", SHORT_SPIN, 1) != 0 || setenv(MARK, SHORT_SPIN, 1) != 0) return;
  execv("/proc/self/exe", argv);
  /* no /proc (or exec refused): go on with the runtime's default, which only costs speed */
  unsetenv("GOMP_SPINCOUNT");
  unsetenv(MARK);
}

const char *peri_omp_wait_description(void) {
  const char *mark = getenv(MARK), *policy = getenv("OMP_WAIT_POLICY"), *spin = getenv("GOMP_SPINCOUNT");
  if (mark && spin && !strcmp(spin, mark) && !policy)
    return "short spin, then sleep (GOMP_SPINCOUNT=" SHORT_SPIN "; OMP_WAIT_POLICY=active or passive to change)";
  if (getenv("GOMP_SPINCOUNT")) return "wait from GOMP_SPINCOUNT";
  if (policy) return !strcmp(policy, "active") || !strcmp(policy, "ACTIVE") ? "active wait (OMP_WAIT_POLICY)"
                                                                            : "passive wait (OMP_WAIT_POLICY)";
  if (getenv("KMP_BLOCKTIME")) return "wait from KMP_BLOCKTIME";
  return "the OpenMP runtime's default wait";
}
