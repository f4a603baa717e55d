/* The OpenMP wait policy peri runs with (app/omp_wait.c). */
#ifndef PERI_APP_OMP_WAIT_H
#define PERI_APP_OMP_WAIT_H

/* Sets OMPI_MCA_mpi_yield_when_idle=1 unless set. Unless the user set OMP_WAIT_POLICY,
 * GOMP_SPINCOUNT or KMP_BLOCKTIME: sets
 * a short spin (GOMP_SPINCOUNT) and executes the program again with the same arguments (returns
 * only when that is not possible, or nothing was to be done). Call first in main. */
void peri_choose_omp_wait(char **argv);
/* One phrase for the summary: which wait policy is in force and where it came from. */
const char *peri_omp_wait_description(void);

#endif
