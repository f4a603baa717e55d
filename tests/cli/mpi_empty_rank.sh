#!/usr/bin/env bash
# Distributed runs where ranks hold no nodes (docs/parallel.md): a 100-node bar split over
# 4 ranks (ranks own whole blocks of 64 nodes, so two ranks get none) runs, gives the
# history of the single-process run, and its .pvtu frames list only the pieces written.
# The quasi-static solvers refuse several ranks with a clear message (exit status 2).
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_empty_rank.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

bar=(--set 'discretization.fill=[{shape: interval, min: [0], max: [0.1]}]'
     --set 'boundary_conditions.0.x=1e-6*exp(-((x-0.05)/0.01)^2)' --set output.frames=3)
run_peri_mpi 1 run examples/wave_in_bar.yaml --output "$TMP/np1" "${bar[@]}"
expect_status 0
expect_stdout_contains "nodes        100"
run_peri_mpi 4 run examples/wave_in_bar.yaml --output "$TMP/np4" "${bar[@]}"
expect_status 0
expect_stdout_contains "MPI ranks    4"
diff_report=$(compare_histories "$TMP/np1/history.csv" "$TMP/np4/history.csv" "$MPI_TOL") ||
  fail "bar: history.csv on 1 and 4 ranks differ: $diff_report"
pieces=$(ls "$TMP/np4"/wave_in_bar_000000_*.vtu | wc -l)
[[ $pieces -ge 1 && $pieces -lt 4 ]] || fail "bar: expected fewer pieces than ranks (empty ranks), got $pieces"
listed=$(grep -c '<Piece Source=' "$TMP/np4/wave_in_bar_000000.pvtu")
[[ $listed -eq $pieces ]] || fail "bar: the .pvtu lists $listed pieces, $pieces were written"
grep -q 'wave_in_bar_000000.pvtu' "$TMP/np4/wave_in_bar.pvd" || fail "bar: the .pvd does not list the .pvtu frames"
pass "100-node bar on 4 ranks ($pieces with nodes): the history of one process; the frames list $pieces pieces"

run_peri_mpi 2 run "$DECKS/qs_bar.yaml" --set solver.type=implicit --output "$TMP/qs"
expect_status 2
expect_stderr_contains "the implicit solver runs in one process"
expect_stdout_empty
expect_no_path "$TMP/qs"
pass "an implicit deck on 2 ranks stops with exit status 2 and says why, before any output"
echo "PASS: $CLI_NAME"
