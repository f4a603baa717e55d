#!/usr/bin/env bash
# Damage is irreversible: in the history of a fracture run (a row every step) the column
# broken_bond_fraction never decreases, stays in [0, 1], and ends above zero and above
# its starting value (the pre-crack) because the crack grows.
# Usage: bash tests/cli/damage_monotone.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

for model in pmb lps; do
  deck="$DECKS/plate_$model.yaml"
  [[ -f "$deck" ]] || fail "missing fixture $deck"
  grep -qE '^ +history_every: 1$' "$deck" || fail "fixture $deck must have history_every: 1"
  steps=$(sed -nE 's/^ +steps: ([0-9]+)$/\1/p' "$deck")
  [[ -n "$steps" ]] || fail "fixture $deck has no 'steps: N'"

  out="$TMP/$model"
  run_peri run "$deck" --quiet --output "$out"
  expect_status 0
  expect_stdout_empty
  history="$out/history.csv"
  expect_nonempty_file "$history"

  col=$(csv_column "$history" broken_bond_fraction)
  [[ -n "$col" ]] || fail "$model: history.csv has no broken_bond_fraction column"
  step_col=$(csv_column "$history" step)
  [[ -n "$step_col" ]] || fail "$model: history.csv has no step column"

  report=$(awk -F, -v c="$col" -v s="$step_col" -v steps="$steps" '
    NR == 1 { next }
    {
      v = $c + 0
      if ($c == "" || v < 0 || v > 1) { printf "line %d: broken_bond_fraction %s is not in [0, 1]\n", NR, $c; bad = 1; exit }
      if ($s + 0 != NR - 2) { printf "line %d: step %s, expected %d (history_every: 1)\n", NR, $s, NR - 2; bad = 1; exit }
      if (NR > 2 && v < prev) { printf "line %d (step %s): broken_bond_fraction decreased from %s to %s\n", NR, $s, prev_text, $c; bad = 1; exit }
      if (NR == 2) first = v
      prev = v; prev_text = $c; last = v; last_step = $s + 0; rows++
    }
    END {
      if (bad) exit 1
      if (rows != steps + 1) { printf "%d rows, expected %d (steps 0..%d)\n", rows, steps + 1, steps; exit 1 }
      if (!(last > 0)) { printf "final broken_bond_fraction %g is not > 0\n", last; exit 1 }
      if (!(last > first)) { printf "no bond broke during the run (%g at step 0, %g at the end)\n", first, last; exit 1 }
      printf "%g at step 0 -> %g at step %d", first, last, last_step
    }' "$history") || fail "$model: $report"
  pass "$model: broken_bond_fraction never decreases over $steps steps: $report"
done

echo "PASS: $CLI_NAME"
