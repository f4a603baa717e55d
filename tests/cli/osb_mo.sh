#!/usr/bin/env bash
# The Madenci-Oterkus model from a deck (docs/models.md 3.6): its input errors exit 2 with
# file:line:col before any work; a fracture run gives the same history with --threads 1 and
# 2 (bonds break during it); the quasi-static solvers adr and nlcg reach the same static
# solution of a plate pulled at one end (the reaction to 1e-4).
# Usage: bash tests/cli/osb_mo.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# a small plate held at its left edge and pulled at its right edge, quasi-statically
plate="$TMP/plate.yaml"
cat >"$plate" <<'DECK'
dimension: 2
plane: stress
materials:
  steel: {model: osb_mo, density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
discretization:
  spacing: 1.0e-3
  m: 3
  thickness: 1.0e-3
  fill: [{shape: rectangle, min: [0, 0], max: [0.020, 0.010]}]
regions:
  left:  {shape: rectangle, min: [-1, -1], max: [0.0031, 1]}
  right: {shape: rectangle, min: [0.0169, -1], max: [1, 1]}
boundary_conditions:
  - {type: displacement, region: left, x: 0, y: 0}
  - {type: displacement, region: right, x: "2.0e-6*t", y: 0}
solver: {type: nlcg, load_steps: 2, end_time: 1, tolerance: 1.0e-9, breaking: false}
output: {picture: false, every: 1000}
DECK

# expect_error DECK PATTERN MESSAGE: peri check and run exit 2 with DECK:line:col of
# PATTERN and MESSAGE, nothing on stdout, no output directory
expect_error() {
  local deck=$1 pattern=$2 message=$3
  for command in check run; do
    if [[ $command == run ]]; then run_peri run "$deck" --quiet --output "$TMP/never"; else run_peri check "$deck"; fi
    expect_status 2
    expect_stdout_empty
    expect_no_path "$TMP/never"
    locate "$pattern" "$deck"
    expect_stderr_contains "$deck:$LOC_LINE:$LOC_COL: error: $message"
  done
}

sed 's/  m: 3/  m: 3\n  influence: inverse/' "$plate" >"$TMP/influence.yaml"
expect_error "$TMP/influence.yaml" "influence:" "key 'influence': the osb_mo model has its own influence function"
pass "an influence function with osb_mo: exit 2 at the key"

sed 's/  m: 3/  m: 3\n  surface_correction: energy/' "$plate" >"$TMP/correction.yaml"
expect_error "$TMP/correction.yaml" "surface_correction:" "key 'surface_correction': not available with the osb_mo model"
pass "surface_correction with osb_mo: exit 2 at the key"

sed 's/type: nlcg/type: implicit/' "$plate" >"$TMP/implicit.yaml"
expect_error "$TMP/implicit.yaml" "implicit" "solver.type implicit: the osb_mo model has no tangent stiffness"
pass "the implicit solver with osb_mo: exit 2 at solver.type"

sed 's/poisson_ratio: 0.3}/poisson_ratio: 0.3, critical_stretch: {s00: 0.01, alpha: 0.25}}/' "$plate" >"$TMP/lammps.yaml"
for command in check run; do
  if [[ $command == run ]]; then run_peri run "$TMP/lammps.yaml" --quiet --output "$TMP/never"; else run_peri check "$TMP/lammps.yaml"; fi
  expect_status 2
  expect_stderr_matches "lammps.yaml:[0-9]+:[0-9]+: error: materials.steel: the \{s00, alpha\} critical stretch is not available with the osb_mo model"
done
pass "the {s00, alpha} critical stretch with osb_mo: exit 2"

# the same static solution by nlcg (the model's energy) and adr (its forces only)
for solver in nlcg adr; do
  run_peri run "$plate" --quiet --set solver.type=$solver --output "$TMP/$solver"
  expect_status 0
  expect_nonempty_file "$TMP/$solver/history.csv"
done
col=$(csv_column "$TMP/nlcg/history.csv" reaction_right_x)
[[ -n "$col" ]] || fail "history.csv has no reaction_right_x column"
a=$(tail -n 1 "$TMP/nlcg/history.csv" | cut -d, -f"$col")
b=$(tail -n 1 "$TMP/adr/history.csv" | cut -d, -f"$col")
awk -v a="$a" -v b="$b" 'BEGIN { d = a - b; if (d < 0) d = -d; s = a < 0 ? -a : a; exit !(s > 0 && d <= 1e-4 * s) }' ||
  fail "reaction at the pulled edge: nlcg $a, adr $b (relative 1e-4 expected)"
pass "nlcg and adr: the same reaction at the pulled edge ($a, $b N)"

# threads: the LPS fracture fixture run with osb_mo
for threads in 1 2; do
  run_peri run "$DECKS/plate_lps.yaml" --set materials.glass.model=osb_mo --threads "$threads" --output "$TMP/t$threads"
  expect_status 0
done
ref="$TMP/t1/history.csv"
col=$(csv_column "$ref" broken_bond_fraction)
final=$(tail -n 1 "$ref" | cut -d, -f"$col")
awk -v b="$final" 'BEGIN { exit !(b > 0) }' || fail "no bond broke during the fracture run"
diff_report=$(compare_histories "$ref" "$TMP/t2/history.csv" 1e-12) ||
  fail "history.csv with --threads 1 and 2 differ: $diff_report"
pass "fracture run: --threads 1 and 2 give the same history (broken bond fraction $final)"

echo "PASS: $CLI_NAME"
