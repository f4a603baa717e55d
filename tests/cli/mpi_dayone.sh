#!/usr/bin/env bash
# The three day-one decks (examples/dayone_*.yaml) run to completion with default settings
# on 1 and 2 MPI ranks (skipped without MPI), and do what their headers say:
#  - the 3D pre-cracked bar pulled quasi-statically fails: the reaction on the pulled end
#    falls below 5% of its peak by the last load step, and no dynamic-switch tuning is
#    needed; its history on 2 ranks is that of 1 rank (docs/parallel.md: the quasi-static
#    solvers' sums are in a fixed order);
#  - the centre-cracked plate in dynamic tension: bonds break beyond the pre-cut ones;
#  - the sphere hitting the plate: a non-zero indenter force and broken bonds.
# Usage: bash tests/cli/mpi_dayone.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

# column HISTORY NAME: the values of column NAME, one a line
column() {
  local k
  k=$(csv_column "$1" "$2")
  [[ -n "$k" ]] || fail "$1: no column $2"
  tail -n +2 "$1" | cut -d, -f"$k"
}

for np in 1 2; do
  out="$TMP/bar-np$np"
  run_peri_mpi "$np" run examples/dayone_bar3d.yaml --output "$out" --set output.fields=[damage]
  expect_status 0
  column "$out/history.csv" reaction_pulled_x | awk '{ if ($1 > peak) peak = $1; last = $1 }
    END { if (!(peak > 0) || !(last < 0.05 * peak)) { print "peak " peak ", last " last; exit 1 } }' ||
    fail "bar on $np ranks: the reaction should fall below 5% of its peak (the bar fails)"
  if [[ $np -eq 2 ]]; then
    diff_report=$(compare_histories "$TMP/bar-np1/history.csv" "$out/history.csv" "$MPI_TOL") ||
      fail "bar: history.csv on 1 and 2 ranks differ: $diff_report"
  fi

  out="$TMP/plate-np$np"
  run_peri_mpi "$np" run examples/dayone_plate2d_dynamic.yaml --output "$out" --set output.picture=false \
    --set output.fields=[damage]
  expect_status 0
  column "$out/history.csv" broken_bond_fraction | awk 'NR == 1 { first = $1 } { last = $1 }
    END { if (!(last > 2 * first)) { print "first " first ", last " last; exit 1 } }' ||
    fail "plate on $np ranks: the crack should grow (broken bond fraction at least doubles)"

  out="$TMP/sphere-np$np"
  run_peri_mpi "$np" run examples/dayone_sphere_impact.yaml --output "$out" --set output.fields=[damage]
  expect_status 0
  column "$out/history.csv" indenter_force_z | awk '{ if ($1 > peak) peak = $1 } END { exit !(peak > 0) }' ||
    fail "sphere on $np ranks: no force on the indenter"
  column "$out/history.csv" broken_bond_fraction | tail -n 1 | awk '{ exit !($1 > 0) }' ||
    fail "sphere on $np ranks: no broken bond"
  pass "the three day-one decks on $np rank(s): the bar fails, the plate's crack grows, the sphere breaks bonds"
done
echo "PASS: $CLI_NAME"
