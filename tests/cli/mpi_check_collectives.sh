#!/usr/bin/env bash
# The check of the sequence of collective calls (PERI_CHECK_COLLECTIVES=1, docs/parallel.md):
# a program whose rank 0 asks for a maximum while the other ranks ask for a sum
# (tests/mpi/collective_mismatch.c) must stop with exit status 1 and a message naming the
# call and site of every rank, on 2 and 3 ranks. Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_check_collectives.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init
program=$(dirname "$PERI")/mpi_collective_mismatch
[[ -x "$program" ]] || fail "$program is missing (built with peri when MPI is found)"
MPI_TIMEOUT=30

for np in 2 3; do
  RUN_CMD="PERI_CHECK_COLLECTIVES=1 mpirun -np $np mpi_collective_mismatch"
  PERI_CHECK_COLLECTIVES=1 timeout -k 10 "$MPI_TIMEOUT" mpirun --oversubscribe --mca mpi_yield_when_idle 1 \
    -np "$np" "$program" >"$RUN_STDOUT" 2>"$RUN_STDERR" </dev/null
  RUN_STATUS=$?
  expect_status 1
  expect_stderr_contains "peri: error: MPI ranks disagree on the sequence of collective calls"
  expect_stderr_contains "rank 0: peri_comm_max at tests/mpi/collective_mismatch.c:12"
  for ((r = 1; r < np; ++r)); do
    expect_stderr_contains "rank $r: peri_comm_sum_long at tests/mpi/collective_mismatch.c:14"
  done
  grep -q "no disagreement was reported" "$RUN_STDOUT" && fail "the program ran past the mismatch on $np ranks"
  pass "mismatched collectives on $np ranks: stopped with the call of every rank"
done
echo "PASS: $CLI_NAME"
