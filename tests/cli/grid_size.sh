#!/usr/bin/env bash
# Grid generation scans each fill shape's own bounding box, and refuses a grid larger than
# the machine's memory before making any node:
#  - two 1 cm cubes 28 m apart (1 mm spacing) have 2 x 10^3 nodes; scanning the box
#    around both (2 x 10^4 x 2 x 10^4 x 12 points) took minutes; here it must take under 5 s;
#  - a 1 m cube at 1 mm (10^9 nodes, at least 100 bytes each) is refused with exit 2 and
#    the estimate, at once and within 4 GB of address space (the scan ran out of it);
#  - discretization.max_nodes replaces the memory limit: the bound is the grid points in
#    the shapes' bounding boxes, with a margin of one or two spacings on each side;
#  - overlapping shapes give each node once (the union).
# Usage: bash tests/cli/grid_size.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# seconds COMMAND...: runs run_peri COMMAND and sets ELAPSED
seconds() {
  local start
  start=$(date +%s.%N)
  run_peri "$@"
  ELAPSED=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
}

# cubes FILE FILL...: a 3D deck at 1 mm spacing with the given fill shapes
cubes() {
  local file=$1
  shift
  {
    printf 'dimension: 3\nmaterials:\n'
    printf '  steel: {model: pmb, density: 7800, youngs_modulus: 200e9, fracture_energy: 1000}\n'
    printf 'discretization:\n  spacing: 1.0e-3\n  m: 3\n'
    for line in "$@"; do printf '  %s\n' "$line"; done
    printf 'solver: {type: explicit, steps: 10}\noutput: {every: 10, picture: false}\n'
  } >"$file"
}

deck="$TMP/far_cubes.yaml"
cubes "$deck" "fill:" \
  "  - {shape: box, min: [0, 0, 0], max: [0.01, 0.01, 0.01]}" \
  "  - {shape: box, min: [20, 20, 0], max: [20.01, 20.01, 0.01]}"
seconds check "$deck"
expect_status 0
expect_stdout_contains "nodes        2000"
awk -v t="$ELAPSED" 'BEGIN { exit !(t < 5) }' || fail "two far cubes took $ELAPSED s (bound 5 s)"
pass "two 1 cm cubes 28 m apart: 2000 nodes in $ELAPSED s"

deck="$TMP/meter.yaml"
cubes "$deck" "fill: [{shape: box, min: [0, 0, 0], max: [1, 1, 1]}]"
memory_kb=$(awk '/^MemTotal:/ { print $2 }' /proc/meminfo)
if ((memory_kb < 100000000)); then # below 100 GB: 10^9 nodes at >= 100 bytes cannot fit
  locate "1.0e-3" "$deck"
  # within 4 GB of address space, so that a generation that does start fails fast
  (
    ulimit -v 4000000
    seconds check "$deck"
    expect_status 2
    expect_stdout_empty
    expect_stderr_contains "$deck:$LOC_LINE:$LOC_COL: error: discretization: spacing 0.001 gives up to "
    expect_stderr_matches "up to 1\.0[01][0-9]e\+09 nodes"
    expect_stderr_contains "set discretization.max_nodes"
    awk -v t="$ELAPSED" 'BEGIN { exit !(t < 3) }' || fail "refusing 10^9 nodes took $ELAPSED s"
    echo "$ELAPSED" >"$TMP/elapsed"
    # `peri run` refuses it the same way, before any output
    seconds run "$deck" --output "$TMP/meter-out"
    expect_status 2
    expect_stderr_contains "$deck:$LOC_LINE:$LOC_COL: error: discretization: spacing 0.001 gives up to "
    expect_no_path "$TMP/meter-out"
    awk -v t="$ELAPSED" 'BEGIN { exit !(t < 3) }' || fail "peri run: refusing 10^9 nodes took $ELAPSED s"
  ) || exit 1
  ELAPSED=$(cat "$TMP/elapsed")
  pass "a 1 m cube at 1 mm is refused by check and run in $ELAPSED s"
else
  pass "SKIPPED: the 1 m cube would fit in this machine's $((memory_kb / 1000000)) GB"
fi

cubes "$deck" "fill: [{shape: box, min: [0, 0, 0], max: [1, 1, 1]}]" "max_nodes: 1000000"
locate "max_nodes: " "$deck"
run_peri check "$deck"
expect_status 2
expect_stderr_contains "$deck:$LOC_LINE:$((LOC_COL + 11)): error: key 'max_nodes': the fill shapes' bounding boxes hold up to "
expect_stderr_contains "more than max_nodes = 1000000"
pass "max_nodes refuses a larger grid at the key"

# 20 x 10 cells at 1 mm: (20 + 4) x (10 + 4) = 336 points in the box with its margins
with_limit() {
  sed "s/^  m: 3$/  m: 3\n  max_nodes: $1/" "$DECKS/valid_small.yaml" >"$TMP/limit.yaml"
  run_peri check "$TMP/limit.yaml"
}
with_limit 336
expect_status 0
expect_stdout_contains "nodes        200"
with_limit 335
expect_status 2
expect_stderr_contains "up to 336 grid points at spacing 0.001, more than max_nodes = 335"
pass "max_nodes counts the grid points of the bounding box"

# two rectangles overlapping on [10, 20] x [0, 10] mm: the union has 30 x 10 nodes
sed 's/^    - {shape: rectangle, min: \[0.0, 0.0\], max: \[0.020, 0.010\]}$/&\n    - {shape: rectangle, min: [0.010, 0.0], max: [0.030, 0.010]}/' \
  "$DECKS/valid_small.yaml" >"$TMP/overlap.yaml"
run_peri check "$TMP/overlap.yaml"
expect_status 0
expect_stdout_contains "nodes        300"
pass "overlapping fill shapes: each node once"
