#!/usr/bin/env bash
# Local nodes (horizon 0; docs/variable_horizon.md "A vanishing horizon: the local model"):
# what is rejected exits 2 with the deck position before any work (partial_stress: none, which
# would leave the local nodes without a force; nlcg, since the coupled force is not an energy's
# gradient; implicit, which needs a tangent; a precrack into the coupling region of the local
# nodes; a local_stencil shorter than the spacing), adr and dynamic_relaxation are accepted, and
# the example deck runs.
# Usage: bash tests/cli/local_coupling.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# a 2D plate, PD for |x| < 5 mm, local elsewhere; EXTRA lines in discretization, TAIL after it
deck() {
  local file=$1 extra=$2 solver=$3 tail=$4
  cat >"$file" <<YAML
dimension: 2
plane: stress
materials:
  plate: {model: pmb, density: 2700, youngs_modulus: 70e9}
discretization:
  spacing: 1.0e-3
  thickness: 1.0e-3
  horizon: "abs(x) < 0.005 ? 0.003 : 0"
$extra
  fill: [{shape: box, min: [-0.02, -0.01], max: [0.02, 0.01]}]
$tail
solver: $solver
output: {picture: false}
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

EXPLICIT="{type: explicit, steps: 5, breaking: false}"

deck "$TMP/none.yaml" "  partial_stress: none" "$EXPLICIT" ""
fails_at "$TMP/none.yaml" "none" "key 'partial_stress': none leaves the local nodes (horizon 0) without a force"
pass "partial_stress: none with local nodes is rejected"

deck "$TMP/nlcg.yaml" "" "{type: nlcg, end_time: 1, load_steps: 1}" ""
fails_at "$TMP/nlcg.yaml" '"abs' "key 'horizon': local nodes (horizon 0) run with solver.type explicit, adr or dynamic_relaxation"
pass "nlcg with local nodes is rejected"

# a crack from the PD band into the local region at x = 6 mm
deck "$TMP/crack.yaml" "" "$EXPLICIT" "precracks: [{from: [0.0, 0.0], to: [0.012, 0.0]}]"
fails_at "$TMP/crack.yaml" "[{from: [0.0, 0.0]" "key 'precracks': a crack cuts a bond of the node"
# ... while one inside the full-PD band is accepted
deck "$TMP/crack_pd.yaml" "" "$EXPLICIT" "precracks: [{from: [-0.0005, 0.0], to: [0.0005, 0.0]}]"
run_peri check "$TMP/crack_pd.yaml"
expect_status 0
pass "a precrack into the local nodes' coupling region is rejected, one in the PD band accepted"

deck "$TMP/stencil.yaml" "  local_stencil: 0.5e-3" "$EXPLICIT" ""
fails_at "$TMP/stencil.yaml" "0.5e-3" "key 'local_stencil': must be a length of at least the spacing"
pass "local_stencil shorter than the spacing is rejected"

# implicit is rejected (no tangent stiffness); adr and dynamic_relaxation are accepted
deck "$TMP/implicit.yaml" "" "{type: implicit, end_time: 1, load_steps: 1}" ""
fails_at "$TMP/implicit.yaml" '"abs' "key 'horizon': the implicit solver needs a tangent stiffness"
pass "implicit with local nodes is rejected"
for solver in "{type: adr, end_time: 1, load_steps: 1}" "{type: dynamic_relaxation, end_time: 1, load_steps: 1, damping: 1e5}"; do
  deck "$TMP/qs.yaml" "" "$solver" ""
  run_peri check "$TMP/qs.yaml"
  expect_status 0
done
pass "adr and dynamic_relaxation with local nodes are accepted"

# the example, a short part of it: runs and writes the horizon field
run_peri run examples/local_bar.yaml --quiet --output "$TMP/bar" --set solver.end_time=5e-6
expect_status 0
expect_nonempty_file "$TMP/bar/history.csv"
grep -q 'Name="horizon"' "$TMP"/bar/local_bar_*.vtu || fail "the frames have no horizon field"
pass "examples/local_bar.yaml runs"
