#!/usr/bin/env bash
# A horizon that varies (docs/variable_horizon.md): the input errors of discretization.horizon
# as an expression and of discretization.partial_stress exit 2 with the deck position before
# any work (the horizon's error names the node where it is not positive and finite); the
# example deck checks, a short explicit run writes the per-node horizon field, and the
# example's ADR solve through the partial stress and its control gives the same history.csv,
# byte for byte, on 1, 2 and 3 threads (the control's reactions were summed by atomic
# additions in the threads' order: 11,749 ADR iterations on 1 thread, 11,768 on 2).
# Usage: bash tests/cli/variable_horizon.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# a 1D bar with a horizon step; BODY replaces the marked lines
deck() {
  local file=$1 horizon=$2 extra=$3 solver=$4
  cat >"$file" <<YAML
dimension: 1
materials:
  bar: {model: pmb, density: 7800, youngs_modulus: 200e9}
discretization:
  spacing: 1.0e-3
  horizon: "$horizon"
$extra
  fill: [{shape: box, min: [0.0], max: [0.05]}]
solver: $solver
output: {fields: [displacement, horizon]}
YAML
}

fails_at() { # DECK PATTERN MESSAGE: exit 2, file:line:col of PATTERN, MESSAGE, no output
  local work
  work=$(mktemp -d "$TMP/run.XXXXXX")
  run_peri_in "$work" run "$1" --quiet --output "$work/out"
  expect_status 2
  locate "$2" "$1"
  expect_stderr_contains "$1:$LOC_LINE:$LOC_COL: error: $3"
  expect_no_path "$work/out"
}

EXPLICIT="{type: explicit, steps: 20, breaking: false}"

# the horizon is negative for x > 0.0305 (nodes at cell centres (k + 1/2) dx: the first one there is at 0.0315)
deck "$TMP/negative.yaml" "0.003 - 0.1 * (x > 0.0305)" "" "$EXPLICIT"
fails_at "$TMP/negative.yaml" '"0.003' "key 'horizon': the horizon is -0.097 at the node at (0.0315); it must be positive and finite at every node"
pass "a negative horizon names the node"

# infinite at the node at x = 0.0105
deck "$TMP/infinite.yaml" "0.003 + 1e-9 / (x - 0.0105)" "" "$EXPLICIT"
fails_at "$TMP/infinite.yaml" '"0.003' "key 'horizon': the horizon is inf at the node at (0.0105)"
pass "an infinite horizon names the node"

# partial stress with nlcg: not an energy's gradient
deck "$TMP/nlcg.yaml" "x < 0.025 ? 0.003 : 0.006" "" "{type: nlcg, end_time: 1, load_steps: 1}"
fails_at "$TMP/nlcg.yaml" '"x <' "the partial-stress force is not the gradient of an energy, so nlcg cannot minimise it"
# ... which full peridynamics allows
deck "$TMP/nlcg_none.yaml" "x < 0.025 ? 0.003 : 0.006" "  partial_stress: none" "{type: nlcg, end_time: 1, load_steps: 1}"
run_peri check "$TMP/nlcg_none.yaml"
expect_status 0
pass "nlcg: rejected with the partial stress, accepted with partial_stress: none"

# implicit: no tangent stiffness
deck "$TMP/implicit.yaml" "x < 0.025 ? 0.003 : 0.006" "  partial_stress: none" "{type: implicit, end_time: 1, load_steps: 1}"
fails_at "$TMP/implicit.yaml" '"x <' "key 'horizon': the implicit solver needs a tangent stiffness"
pass "implicit: rejected"

# partial_stress without a horizon field, and an unknown region
deck "$TMP/constant.yaml" "0.003" "  partial_stress: auto" "$EXPLICIT"
fails_at "$TMP/constant.yaml" "partial_stress" "key 'partial_stress': only with a horizon that varies"
deck "$TMP/region.yaml" "x < 0.025 ? 0.003 : 0.006" "  partial_stress: middel" "$EXPLICIT"
fails_at "$TMP/region.yaml" "middel" ""
pass "partial_stress: only with a field, and a region that exists"

# a short run writes the horizon of every node
deck "$TMP/run.yaml" "x < 0.025 ? 0.003 : 0.006" "" "$EXPLICIT"
run_peri run "$TMP/run.yaml" --quiet --output "$TMP/out"
expect_status 0
expect_nonempty_file "$TMP/out/history.csv"
grep -q 'Name="horizon"' "$TMP"/out/run_*.vtu || fail "the frames have no horizon field"
pass "a run writes the horizon field"

# the example checks
run_peri check examples/horizon_bar.yaml
expect_status 0
expect_stdout_contains "1000"
pass "examples/horizon_bar.yaml checks"

# the partial stress's reactions do not depend on the number of threads
for threads in 1 2 3; do
  run_peri run examples/horizon_bar.yaml --quiet --threads "$threads" --output "$TMP/bar$threads" \
    --set output.frames=0 --set output.picture=false
  expect_status 0
done
for threads in 2 3; do
  cmp -s "$TMP/bar1/history.csv" "$TMP/bar$threads/history.csv" ||
    fail "history.csv differs between 1 and $threads threads: $(diff "$TMP/bar1/history.csv" "$TMP/bar$threads/history.csv" | head -n 4)"
done
pass "examples/horizon_bar.yaml: the same history.csv on 1, 2 and 3 threads"
