/* A program whose ranks take different branches on purpose, for tests/cli/mpi_check_collectives.sh:
 * after one agreed reduction, rank 0 asks for a maximum while the other ranks ask for a sum.
 * With PERI_CHECK_COLLECTIVES=1 the check must stop it with a message naming both calls;
 * without the check the two reductions would be matched by MPI and return mixed values. */
#include <stdio.h>
#include "peri/comm.h"

int main(int argc, char **argv) {
  peri_comm_init(&argc, &argv);
  const long ranks = peri_comm_sum_long(1); /* the same call on every rank */
  if (peri_comm_rank() == 0)
    (void)peri_comm_max(1.0);
  else
    (void)peri_comm_sum_long(1);
  if (peri_comm_rank() == 0) printf("ranks %ld: no disagreement was reported\n", ranks);
  peri_comm_finalize();
  return 0;
}
