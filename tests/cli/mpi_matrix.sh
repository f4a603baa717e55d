#!/usr/bin/env bash
# Every solver type on 1, 2 and 3 MPI ranks (docs/parallel.md): explicit dynamics (the
# pre-cracked PMB plate), adr, nlcg and dynamic_relaxation with and without the switch to
# dynamics (the 1D bar pulled to failure), implicit when peri is built with PETSc, and heat
# conduction (a plate with a growing crack). Each run has a time limit (a hang fails the test)
# and runs with the check of the sequence of collectives (PERI_CHECK_COLLECTIVES=1); it must
# exit 0, and history.csv on 2 and 3 ranks must be that of one process: equal to a relative
# 1e-12 (bit for bit in practice), and to 1e-9 for implicit at tolerance 1e-11 without
# breaking, whose Krylov iterates depend on the split (docs/solvers.md section 9). Two runs
# that fail (a state that is not finite, runaway growth) must exit 1 on 2 ranks with the
# message of one process. Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_matrix.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init
MPI_TIMEOUT=240   # a hang never ends; a loaded machine runs the bar's 10 load steps in 100 s and more
export PERI_CHECK_COLLECTIVES=1
MPI_RANKS="1 2 3"

bar=("$DECKS/qs_bar.yaml" --set solver.load_steps=10 --set output.fields=[displacement])
switch=(--set solver.dynamic_switch.when_broken_exceeds=4 --set solver.dynamic_switch.history_every=20)
dr=(--set solver.type=dynamic_relaxation --set solver.damping=2e5)

# matrix_case NAME ARGS...: one line of the matrix on 1, 2 and 3 ranks
matrix_case() {
  local name=$1
  shift
  mpi_same_on_ranks "$name" "$@"
  pass "$name: exit 0 and the history of one process on ranks $MPI_RANKS"
}

# (phase rows): the switch must have been taken, else the line tests nothing more
expect_dynamic_phase() {
  local col
  col=$(csv_column "$MPI_REF" phase)
  [[ -n "$col" ]] && awk -F, -v c="$col" 'NR > 1 && $c == 1 { f = 1 } END { exit !f }' "$MPI_REF" ||
    fail "$1: no dynamic phase in history.csv"
}

matrix_case explicit "$DECKS/plate_pmb.yaml" --set solver.steps=60 --set output.every=30
for solver in adr nlcg; do
  matrix_case "$solver" "${bar[@]}" --set solver.type=$solver
  matrix_case "$solver+switch" "${bar[@]}" --set solver.type=$solver "${switch[@]}"
  expect_dynamic_phase "$solver+switch"
done
matrix_case dynamic_relaxation "${bar[@]}" "${dr[@]}"
matrix_case dynamic_relaxation+switch "${bar[@]}" "${dr[@]}" "${switch[@]}"
expect_dynamic_phase dynamic_relaxation+switch
run_peri check "$DECKS/qs_bar.yaml" --set solver.type=implicit
if [[ $RUN_STATUS -eq 0 ]]; then
  # without breaking and at tolerance 1e-11 (as in mpi_empty_rank.sh): the broken bar's
  # energies are round-off, which no relative comparison can hold to the solver tolerance
  MPI_TOL=1e-9 matrix_case implicit "${bar[@]}" --set solver.type=implicit --set solver.tolerance=1e-11 \
    --set solver.breaking=false
else
  echo "skip: implicit (peri built without PETSc)"
fi
matrix_case heat "$DECKS/matrix_heat.yaml" --set solver.steps=30 --set output.every=30
# failures on 2 ranks stop every rank at the same point as one process: a quasi-static state
# that is not finite (qs_not_finite.sh) and the runaway growth of an explicit run
# (explicit_runaway.sh); exit 1 and the message of one process
failure_case() {
  local name=$1 pattern=$2
  shift 2
  run_peri "$@" --quiet --output "$TMP/$name-np1"
  expect_status 1
  local message
  message=$(grep -E "$pattern" "$RUN_STDERR" | head -n 1)
  [[ -n "$message" ]] || fail "$name: no message matching '$pattern' in one process"
  run_peri_mpi 2 "$@" --quiet --output "$TMP/$name-np2"
  expect_status 1
  expect_stderr_contains "$message"
  pass "$name on 2 ranks: exit 1 with the message of one process"
}
failure_case not-finite "diverged at load step" run "$DECKS/qs_bar_huge_load.yaml" --set solver.type=adr
failure_case runaway "diverged at step" run "$DECKS/diverge.yaml" --set solver.steps=20
echo "PASS: $CLI_NAME"
