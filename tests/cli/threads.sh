#!/usr/bin/env bash
# The thread count does not change the result: a small 2D fracture run (bonds break during
# the run) gives the same history.csv with --threads 1, 2 and 3, to a relative 1e-12 on
# every value, and exactly the same broken-bond fraction. Both models: PMB and LPS.
# Usage: bash tests/cli/threads.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

TOL=1e-12

# last_value FILE COLUMN: the text of COLUMN in the last row of FILE.
last_value() {
  local c
  c=$(csv_column "$1" "$2")
  [[ -n "$c" ]] || fail "$1 has no column '$2'"
  tail -n 1 "$1" | cut -d, -f"$c"
}

for model in pmb lps; do
  deck="$DECKS/plate_$model.yaml"
  [[ -f "$deck" ]] || fail "missing fixture $deck"
  for threads in 1 2 3; do
    out="$TMP/$model-t$threads"
    run_peri run "$deck" --threads "$threads" --output "$out"
    expect_status 0
    # the run reports the thread count it used: --threads took effect
    expect_stdout_matches "^  finished .*\($threads threads\)$"
    # a uniform grid: every block reads its neighbour offsets from the lattice's table
    expect_stdout_matches "^  bond loops .*; 100\.0% of them with the lattice's offsets\)$"
    expect_nonempty_file "$out/history.csv"
  done
  ref="$TMP/$model-t1/history.csv"

  # the fixture must exercise breaking during the run, else the comparison is weak
  rows=$(($(wc -l <"$ref") - 1))
  [[ $rows -ge 100 ]] || fail "$model: expected a history row per step (>= 100 rows), got $rows"
  col=$(csv_column "$ref" broken_bond_fraction)
  [[ -n "$col" ]] || fail "$model: history.csv has no broken_bond_fraction column"
  first=$(sed -n 2p "$ref" | cut -d, -f"$col")
  final=$(last_value "$ref" broken_bond_fraction)
  awk -v a="$first" -v b="$final" 'BEGIN { exit !(b > a) }' ||
    fail "$model: no bond broke during the run (broken_bond_fraction $first -> $final)"

  for threads in 2 3; do
    other="$TMP/$model-t$threads/history.csv"
    diff_report=$(compare_histories "$ref" "$other" "$TOL") ||
      fail "$model: history.csv with --threads 1 and --threads $threads differ: $diff_report"
    got=$(last_value "$other" broken_bond_fraction)
    [[ "$got" == "$final" ]] ||
      fail "$model: final broken_bond_fraction $final (--threads 1) vs $got (--threads $threads)"
  done
  pass "$model: --threads 1, 2, 3 give the same history ($rows rows, tolerance $TOL); broken bonds $first -> $final"
done

echo "PASS: $CLI_NAME"
