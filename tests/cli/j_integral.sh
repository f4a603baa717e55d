#!/usr/bin/env bash
# The j_integral columns from the command line (docs/plasticity.md §6, docs/deck.md §22):
#  - a pre-cracked plate that grows its crack (tests/cli/decks/plate_pmb.yaml, plastic glass)
#    has the columns j_integral_1, _2, crack_extension; J is positive once loaded and the crack
#    extension grows from 0 to at least two spacings; output.plot draws the J-R curve;
#  - the thread count does not change the columns (history.csv bitwise, 1 and 3 threads);
#  - bad j_integral input: file:line:column, exit 2 (a 3D deck, a ring with inner >= outer, a
#    zero direction, a key that does not exist).
# Usage: bash tests/cli/j_integral.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

plate="$DECKS/plate_pmb.yaml"
plastic_glass='materials.glass={model: pmb, density: 2440, youngs_modulus: 72.0e9, fracture_energy: 3.8, plasticity: {weights: [0.9, 0.1], yield_stretches: [5.0e-5, 2.0e-4]}}'
j='j_integral={tip: [0.030, 0.012], contours: [[0.004, 0.007], [0.007, 0.010]]}'
for threads in 1 3; do
  run_peri run "$plate" --quiet --threads "$threads" --output "$TMP/plate$threads" --set "$plastic_glass" --set "$j" \
    --set 'output.plot={x: crack_extension, y: j_integral_2}' --set solver.steps=300 --set output.history_every=20
  expect_status 0
done
hist="$TMP/plate1/history.csv"
for c in j_integral_1 j_integral_2 crack_extension; do
  [[ -n "$(csv_column "$hist" "$c")" ]] || fail "history.csv has no column $c"
done
cj=$(csv_column "$hist" j_integral_2)
ca=$(csv_column "$hist" crack_extension)
awk -F, -v cj="$cj" -v ca="$ca" '
  NR == 2 && ($ca != 0 || $cj != 0) { print "  the initial state has J = " $cj ", extension " $ca; bad = 1 }
  NR > 2 { last_j = $cj; last_a = $ca; if ($ca < prev_a) { print "  the crack extension fell at row " NR; bad = 1 } prev_a = $ca }
  END {
    printf "  last row: J = %g J/m^2, crack extension %g m\n", last_j, last_a
    if (!(last_j > 0) || !(last_a >= 0.002)) bad = 1
    exit bad
  }' "$hist" || fail "J and the crack extension do not grow"
expect_nonempty_file "$TMP/plate1/j_integral_2_vs_crack_extension.png"
cmp -s "$hist" "$TMP/plate3/history.csv" || fail "history.csv differs between 1 and 3 threads"
pass "J and crack extension columns, the J-R plot, 1 and 3 threads bitwise equal"

# --- bad input: file:line:column, exit 2
run_peri check "$DECKS/qs_bar3d.yaml" --set 'j_integral={tip: [0, 0], contours: [[0.002, 0.004]]}'
expect_status 2
expect_stderr_contains "error: j_integral: only for dimension 2"
run_peri check "$plate" --set 'j_integral={tip: [0.03, 0.012], contours: [[0.004, 0.002]]}'
expect_status 2
expect_stderr_contains "--set:1:44: error: j_integral.contours: need 0 < inner < outer, got [0.004, 0.002]"
run_peri check "$plate" --set 'j_integral={tip: [0.03, 0.012], direction: [0, 0], contours: [[0.002, 0.004]]}'
expect_status 2
expect_stderr_contains "error: j_integral.direction: must be a nonzero vector"
run_peri check "$plate" --set 'j_integral={tip: [0.03, 0.012], contour: [[0.002, 0.004]]}'
expect_status 2
expect_stderr_contains "unknown key 'contour' in j_integral; did you mean 'contours'?"
pass "bad j_integral input: file:line:column, exit 2"

echo "PASS: $CLI_NAME"
