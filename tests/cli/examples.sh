#!/usr/bin/env bash
# The example decks run and write their output: the LAMMPS examples/peri PMB problem (3D:
# .pvd series, .vtu frames, history.csv) and the quickstart (2D: also damage.png).
# The quickstart takes several seconds.
# Usage: bash tests/cli/examples.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# expect_series DIR NAME: DIR/NAME.pvd lists every DIR/NAME_*.vtu (at least two), each a
# VTK unstructured grid; prints the number of frames.
expect_series() {
  local dir=$1 name=$2 pvd vtus listed f
  pvd="$dir/$name.pvd"
  expect_nonempty_file "$pvd"
  grep -q '<VTKFile type="Collection"' "$pvd" || fail "$pvd is not a VTK collection"
  grep -q '</VTKFile>' "$pvd" || fail "$pvd is not complete"
  vtus=$(find "$dir" -maxdepth 1 -name "${name}_*.vtu" | wc -l)
  [[ $vtus -ge 2 ]] || fail "expected at least 2 .vtu files in $dir, found $vtus"
  listed=$(grep -c '<DataSet ' "$pvd")
  [[ $listed -eq $vtus ]] || fail "$pvd lists $listed frames, $dir holds $vtus .vtu files"
  for f in $(sed -nE 's/.*file="([^"]+)".*/\1/p' "$pvd"); do
    [[ "$f" != /* ]] || fail "$pvd names an absolute path $f (frames must be relative to the .pvd)"
    expect_nonempty_file "$dir/$f"
    head -c 4096 "$dir/$f" | grep -q '<VTKFile type="UnstructuredGrid"' ||
      fail "$dir/$f is not a VTK unstructured grid"
  done
  echo "$vtus"
}

# expect_history FILE STEPS: a header with time and kinetic_energy, numeric rows, the
# last one at step STEPS.
expect_history() {
  local file=$1 steps=$2 c last
  expect_nonempty_file "$file"
  for c in time step kinetic_energy; do
    [[ -n "$(csv_column "$file" "$c")" ]] || fail "$file: header has no column '$c': $(head -n 1 "$file")"
  done
  [[ $(wc -l <"$file") -ge 3 ]] || fail "$file: expected at least 2 rows"
  awk -F, 'NR > 1 { for (c = 1; c <= NF; c++) if ($c !~ /^-?[0-9.]+([eE][-+]?[0-9]+)?$/) { print "line " NR ": " $c; exit 1 } }' \
    "$file" >/dev/null || fail "$file has a value that is not a finite number"
  c=$(csv_column "$file" step)
  last=$(tail -n 1 "$file" | cut -d, -f"$c")
  [[ "$last" == "$steps" ]] || fail "$file: the last row is step $last, expected $steps"
}

# --- the LAMMPS examples/peri PMB problem (3D, 1000 steps)
deck=examples/lammps_peri_pmb.yaml
[[ -f "$deck" ]] || fail "run from the repository root ($deck not found)"
out="$TMP/pmb"
run_peri run "$deck" --quiet --output "$out"
expect_status 0
expect_stdout_empty
frames=$(expect_series "$out" lammps_peri_pmb) || exit 1
expect_history "$out/history.csv" 1000
for c in indenter_force_x indenter_force_y indenter_force_z; do
  [[ -n "$(csv_column "$out/history.csv" "$c")" ]] || fail "history.csv has no $c column (the deck has an indenter)"
done
# the indenter breaks bonds
c=$(csv_column "$out/history.csv" broken_bond_fraction)
final=$(tail -n 1 "$out/history.csv" | cut -d, -f"$c")
awk -v f="$final" 'BEGIN { exit !(f > 0) }' || fail "$deck: no bond broke (broken_bond_fraction $final)"
# a 3D run's picture is the slice through the middle (docs/output.md)
expect_nonempty_file "$out/damage.png"
[[ -z "$(find "$out" -name '*.tmp')" ]] || fail "$deck left a temporary file in $out"
pass "$deck: lammps_peri_pmb.pvd with $frames frames, history.csv to step 1000, broken bonds $final"

# --- the quickstart (2D crack branching, damage picture)
deck=examples/quickstart.yaml
out="$TMP/quickstart"
run_peri run "$deck" --quiet --output "$out"
expect_status 0
expect_stdout_empty
frames=$(expect_series "$out" quickstart) || exit 1
steps=$(sed -nE 's/.*time step .*, ([0-9]+) steps to .*/\1/p' <("$PERI" check "$deck"))
[[ -n "$steps" ]] || fail "cannot read the step count from peri check $deck"
expect_history "$out/history.csv" "$steps"
png="$out/damage.png"
expect_nonempty_file "$png"
signature=$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')
[[ "$signature" == "89504e470d0a1a0a" ]] || fail "$png has no PNG signature (got $signature)"
# IHDR first, with the width the deck asks for (picture: {width: 1200})
chunk=$(head -c 16 "$png" | tail -c 4)
[[ "$chunk" == "IHDR" ]] || fail "$png: the first chunk is '$chunk', not IHDR"
width=$((16#$(head -c 20 "$png" | tail -c 4 | od -An -tx1 | tr -d ' \n')))
[[ $width -eq 1200 ]] || fail "$png is $width pixels wide, the deck asks for 1200"
pass "$deck: quickstart.pvd with $frames frames, history.csv to step $steps, damage.png (PNG, 1200 px wide)"

# --- without --quiet the run prints the summary and where the output went (a small deck)
out="$TMP/plate"
deck="$DECKS/plate_pmb.yaml"
run_peri run "$deck" --output "$out"
expect_status 0
expect_stdout_contains "nodes        1440"
expect_stdout_matches "^  finished +200 steps"
expect_stdout_matches "^  broken bonds +[0-9]+ of [0-9]+$"
expect_stdout_contains "$out/plate_pmb.pvd"
expect_stdout_contains "$out/history.csv"
expect_series "$out" plate_pmb >/dev/null || exit 1
pass "without --quiet: the summary and the output paths are printed"

echo "PASS: $CLI_NAME"
