#!/usr/bin/env bash
# The thread count does not change the result: a small 2D fracture run (bonds break during
# the run) gives the same history.csv with --threads 1, 2 and 3, to a relative 1e-12 on
# every value, and exactly the same broken-bond fraction. Both models: PMB and LPS.
# Usage: bash tests/cli/threads.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

TOL=1e-12

# compare_histories A B: same header, same number of rows, every value equal to a
# relative TOL (|a - b| <= TOL * max(|a|, |b|); equal text is equal). Prints the first
# difference and returns 1 on a mismatch.
compare_histories() {
  awk -F, -v tol="$TOL" -v fa="$1" -v fb="$2" '
    function abs(v) { return v < 0 ? -v : v }
    NR == FNR { row[FNR] = $0; rows_a = FNR; next }
    {
      rows_b = FNR
      if (!(FNR in row)) { printf "%s has more lines than %s\n", fb, fa; bad = 1; exit }
      if (FNR == 1) {
        if ($0 != row[1]) { printf "headers differ:\n  %s\n  %s\n", row[1], $0; bad = 1; exit }
        ncol = split($0, names, ",")
        next
      }
      n = split(row[FNR], a, ",")
      if (n != NF || n != ncol) { printf "row %d: %d and %d columns (header: %d)\n", FNR, n, NF, ncol; bad = 1; exit }
      for (c = 1; c <= n; c++) {
        if (a[c] == $c) continue
        x = a[c] + 0; y = $c + 0
        scale = abs(x) > abs(y) ? abs(x) : abs(y)
        if (abs(x - y) > tol * scale) {
          printf "row %d, column %s: %s vs %s (relative difference %.3g > %g)\n",
                 FNR, names[c], a[c], $c, abs(x - y) / scale, tol
          bad = 1; exit
        }
      }
    }
    END {
      if (bad) exit 1
      if (rows_a != rows_b) { printf "%s has %d lines, %s has %d\n", fa, rows_a, fb, rows_b; exit 1 }
    }' "$1" "$2"
}

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
    diff_report=$(compare_histories "$ref" "$other") ||
      fail "$model: history.csv with --threads 1 and --threads $threads differ: $diff_report"
    got=$(last_value "$other" broken_bond_fraction)
    [[ "$got" == "$final" ]] ||
      fail "$model: final broken_bond_fraction $final (--threads 1) vs $got (--threads $threads)"
  done
  pass "$model: --threads 1, 2, 3 give the same history ($rows rows, tolerance $TOL); broken bonds $first -> $final"
done

echo "PASS: $CLI_NAME"
