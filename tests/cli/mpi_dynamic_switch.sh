#!/usr/bin/env bash
# A quasi-static run that switches to explicit dynamics on 2 ranks (docs/parallel.md,
# docs/solvers.md section 4): the 3D bar of decks/qs_bar3d.yaml, LPS and PMB, pulled to
# failure by nlcg with solver.dynamic_switch and no max_broken_per_step. The time step of a
# dynamic phase is estimated after the decomposition; estimated from each rank's own nodes it
# differed between the ranks (the stiffest nodes are on one rank), the ranks counted the
# steps to arrest differently, and one rank waited in the halo exchange of the next step
# while the other summed the kinetic energy of a history row: a hang. Each run has a time
# limit (a hang fails the test), runs with the check of the sequence of collectives on
# (PERI_CHECK_COLLECTIVES=1), and must give history.csv of one process bit for bit.
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_dynamic_switch.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init
MPI_TIMEOUT=60
export PERI_CHECK_COLLECTIVES=1

for model in lps pmb; do
  MPI_RANKS="1 2" mpi_same_on_ranks "bar-$model" "$DECKS/qs_bar3d.yaml" --set materials.steel.model=$model
  expect_stdout_matches "^  dynamic      load step [0-9]+ .*arrested"
  col=$(csv_column "$MPI_REF" phase)
  [[ -n "$col" ]] || fail "bar $model: no column 'phase' in history.csv"
  awk -F, -v c="$col" 'NR > 1 && $c == 1 { found = 1 } END { exit !found }' "$MPI_REF" ||
    fail "bar $model: no row of a dynamic phase in history.csv (the switch was not reached)"
  pass "3D $model bar through its dynamic phases on 2 ranks: no hang, the history of one process"
done
echo "PASS: $CLI_NAME"
