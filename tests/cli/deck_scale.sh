#!/usr/bin/env bash
# Deck checks scale as n log n: a deck with 100,000 regions and 5,000 boundary conditions
# naming them is checked in seconds. Comparing each key of a mapping with every earlier
# one (the duplicate-key check) and scanning the region list for each condition took 47 s
# for 100,000 regions alone on the development machine; the bound below is generous for
# n log n (about 2 s there) and fails the quadratic checks. A duplicate among the 100,000
# keys is still found, at its second occurrence.
# Usage: bash tests/cli/deck_scale.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

REGIONS=100000
CONDITIONS=5000
BOUND_SECONDS=20

# write_deck FILE [DUPLICATE]: the deck; with DUPLICATE, region_DUPLICATE is given twice,
# the second time as the last region
write_deck() {
  {
    printf 'dimension: 2\nplane: stress\nmaterials:\n'
    printf '  glass: {model: pmb, density: 2440, youngs_modulus: 72.0e9, fracture_energy: 3.8}\n'
    printf 'discretization:\n  spacing: 1.0e-3\n  m: 3\n'
    printf '  fill: [{shape: rectangle, min: [0.0, 0.0], max: [0.004, 0.002]}]\nregions:\n'
    awk -v n=$REGIONS -v dup="${2:-}" 'BEGIN {
      for (i = 0; i < n; i++) printf "  region_%d: {shape: rectangle, min: [-1, -1], max: [1, 1]}\n", i
      if (dup != "") printf "  region_%d: {shape: rectangle, min: [-1, -1], max: [1, 1]}\n", dup
    }'
    printf 'boundary_conditions:\n'
    # spread over the names (7919 is prime, so the indices are distinct)
    awk -v n=$REGIONS -v k=$CONDITIONS 'BEGIN {
      for (i = 0; i < k; i++) printf "  - {type: velocity, region: region_%d, y: 0}\n", (i * 7919) % n
    }'
    printf 'solver:\n  type: explicit\n  steps: 20\noutput:\n  every: 10\n  picture: false\n'
  } >"$1"
}

deck="$TMP/many_regions.yaml"
write_deck "$deck"
start=$(date +%s.%N)
run_peri check "$deck"
elapsed=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
expect_status 0
expect_stdout_contains "nodes        8"
awk -v t="$elapsed" -v b=$BOUND_SECONDS 'BEGIN { exit !(t < b) }' ||
  fail "checking $REGIONS regions took $elapsed s (bound $BOUND_SECONDS s)"
pass "$REGIONS regions and $CONDITIONS conditions checked in $elapsed s"

deck="$TMP/duplicate.yaml"
write_deck "$deck" 4242
first=$(grep -n '^  region_4242:' "$deck" | head -n 1 | cut -d: -f1)
second=$(grep -n '^  region_4242:' "$deck" | tail -n 1 | cut -d: -f1)
run_peri check "$deck"
expect_status 2
expect_stderr_contains "$deck:$second:3: error: duplicate key 'region_4242' (first given at line $first, column 3)"
pass "a duplicate among $REGIONS keys is reported at its second occurrence"
