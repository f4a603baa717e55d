#!/usr/bin/env bash
# Graded grids (docs/variable_horizon.md, "Graded grids"): zones that do not tile the body
# (a side not a whole multiple of the zone's spacing, overlapping zones, a zone that is not a
# box, a lattice origin, a given node volume) exit 2 with the deck position before any work; a run writes the
# spacing and horizon fields; the example deck checks.
# Usage: bash tests/cli/graded_grid.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# a 1D bar, coarse | fine | coarse; ZONES replaces the fill list, EXTRA adds discretization keys
deck() {
  local file=$1 zones=$2 extra=$3
  cat >"$file" <<YAML
dimension: 1
materials:
  bar: {model: pmb, density: 7800, youngs_modulus: 200e9}
discretization:
  spacing: 1.0e-3
  m: 3
$extra
  fill:
$zones
solver: {type: explicit, steps: 20, breaking: false}
output: {fields: [displacement, spacing, horizon]}
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

GOOD="    - {shape: box, min: [0.0], max: [0.02], spacing: 2.0e-3}
    - {shape: box, min: [0.02], max: [0.04]}
    - {shape: box, min: [0.04], max: [0.06], spacing: 2.0e-3}"

deck "$TMP/side.yaml" "    - {shape: box, min: [0.0], max: [0.021], spacing: 2.0e-3}
    - {shape: box, min: [0.021], max: [0.04]}" ""
fails_at "$TMP/side.yaml" "{shape: box, min: [0.0], max: [0.021]" "discretization.fill item 1: its side along axis 1 is 10.5 spacings"
pass "a zone side that is not a whole number of spacings"

deck "$TMP/overlap.yaml" "    - {shape: box, min: [0.0], max: [0.02], spacing: 2.0e-3}
    - {shape: box, min: [0.01], max: [0.04]}" ""
fails_at "$TMP/overlap.yaml" "{shape: box, min: [0.01]" "discretization.fill item 2 overlaps item 1"
pass "overlapping zones"

deck "$TMP/sphere.yaml" "    - {shape: box, min: [0.0], max: [0.02], spacing: 2.0e-3}
    - {shape: sphere, center: [0.03], radius: 0.01}" ""
fails_at "$TMP/sphere.yaml" "{shape: sphere" "discretization.fill item 2: on a graded grid every zone is a box"
pass "a zone that is not a box"

deck "$TMP/origin.yaml" "$GOOD" "  origin: [0.0]"
fails_at "$TMP/origin.yaml" "origin" "discretization: a graded grid (a fill shape with its own spacing)"
pass "a lattice origin"

deck "$TMP/volume.yaml" "$GOOD" "  volume: 1.0e-9"
fails_at "$TMP/volume.yaml" "volume" "key 'volume': not on a graded grid"
pass "a given node volume"

deck "$TMP/negative.yaml" "    - {shape: box, min: [0.0], max: [0.02], spacing: -2.0e-3}" ""
fails_at "$TMP/negative.yaml" "-2.0e-3" "key 'spacing': must be positive"
pass "a negative zone spacing"

# a short run: 10 + 20 + 10 nodes, spacing and horizon fields written
deck "$TMP/run.yaml" "$GOOD" ""
run_peri run "$TMP/run.yaml" --quiet --output "$TMP/out"
expect_status 0
grep -q 'Name="spacing"' "$TMP"/out/run_*.vtu || fail "the frames have no spacing field"
grep -q 'Name="horizon"' "$TMP"/out/run_*.vtu || fail "the frames have no horizon field"
run_peri check "$TMP/run.yaml"
expect_status 0
expect_stdout_contains "40"
pass "a graded run writes the spacing and horizon fields"

run_peri check examples/graded_bar.yaml
expect_status 0
expect_stdout_contains "666"
pass "examples/graded_bar.yaml checks"
