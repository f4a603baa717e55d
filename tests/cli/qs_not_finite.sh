#!/usr/bin/env bash
# Quasi-static solves whose state is not finite (docs/solvers.md section 2): a body force of
# 1e200 t on the 1D bar (decks/qs_bar_huge_load.yaml) and a traction of 1e200 t on the plate
# with a hole drive the displacements, forces and residual to infinity or NaN. No solver may
# report such a state as converged (adr and dynamic_relaxation did, and the run exited 0 with
# inf and NaN in history.csv): the load step is cut back, and when the max_cutbacks (6)
# halvings are used up the run exits 1 naming the load step, with history.csv kept. Every
# quasi-static solver is checked (implicit when peri is built with PETSc).
# Usage: bash tests/cli/qs_not_finite.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

solvers="adr dynamic_relaxation nlcg"
run_peri check "$DECKS/qs_bar_huge_load.yaml" --set solver.type=implicit
[[ $RUN_STATUS -eq 0 ]] && solvers="$solvers implicit"

# expect_diverged NAME OUT: exit 1, the message, the cut-backs used up, history.csv with its
# first row (t = 0) and no row of a load step, and no inf or NaN reported as a result.
expect_diverged() {
  local name=$1 out=$2
  expect_status 1
  expect_stderr_matches "error: $name: the solution diverged at load step 1 \(t = [0-9.e-]+, the increment halved 6 times\)"
  expect_stderr_contains "not finite"
  expect_stdout_contains "6 cut-backs"
  expect_nonempty_file "$out/history.csv"
  [[ $(wc -l <"$out/history.csv") -eq 2 ]] || fail "$name: history.csv should hold the header and the row at t = 0"
  grep -qiE 'nan|inf' "$out/history.csv" && fail "$name: history.csv holds a value that is not finite"
  return 0
}

for solver in $solvers; do
  extra=()
  [[ $solver == dynamic_relaxation ]] && extra=(--set solver.damping=2e5)
  out="$TMP/bar-$solver"
  run_peri run "$DECKS/qs_bar_huge_load.yaml" --set solver.type=$solver "${extra[@]}" --output "$out"
  expect_diverged "$solver" "$out"
  pass "$solver, body force 1e200 t: exit 1 after 6 cut-backs, history.csv kept"
done

out="$TMP/plate-adr"
run_peri run examples/plate_with_hole.yaml --set discretization.horizon=3e-3 --set discretization.spacing=1e-3 \
  --set output.picture=false --set solver.type=adr --set "boundary_conditions.1.x=1e200*t" --output "$out"
expect_diverged adr "$out"
pass "adr, traction 1e200 t on the plate with a hole: exit 1 after 6 cut-backs, history.csv kept"
echo "PASS: $CLI_NAME"
