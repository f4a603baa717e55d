#!/usr/bin/env bash
# A failure during the run exits 1 with a message and keeps what was written before it:
# a diverging run (time step 100 times the stable estimate, initial velocity) keeps its
# history.csv and a valid .pvd listing the frames written before the failure. An output
# directory that cannot be created is a run failure too (status 1, not 2).
# Usage: bash tests/cli/midrun_failure.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck="$DECKS/diverge.yaml"
[[ -f "$deck" ]] || fail "missing fixture $deck"
steps=$(sed -nE 's/^ +steps: ([0-9]+)$/\1/p' "$deck")
[[ -n "$steps" ]] || fail "fixture $deck has no 'steps: N'"

# the deck itself is valid: check accepts it, with a warning about the time step
run_peri check "$deck"
expect_status 0
expect_stderr_contains "exceeds the stable estimate"
pass "check accepts the diverging deck and warns about the time step"

out="$TMP/out"
run_peri run "$deck" --quiet --output "$out"
expect_status 1
expect_stdout_empty
expect_stderr_contains "diverged"
expect_stderr_matches "diverged at step [0-9]+"
failed_at=$(sed -nE 's/.*diverged at step ([0-9]+).*/\1/p' "$RUN_STDERR" | head -n 1)
[[ $failed_at -gt 1 && $failed_at -lt $steps ]] ||
  fail "expected the divergence after a few steps and before step $steps, got step $failed_at"
pass "the diverging run exits 1 with 'diverged at step $failed_at'"

# history.csv: the header and one row per step before the failing one, in order
history="$out/history.csv"
expect_nonempty_file "$history"
[[ -n "$(csv_column "$history" time)" && -n "$(csv_column "$history" kinetic_energy)" ]] ||
  fail "$history: header without time and kinetic_energy: $(head -n 1 "$history")"
step_col=$(csv_column "$history" step)
report=$(awk -F, -v s="$step_col" -v last="$((failed_at - 1))" '
  NR == 1 { next }
  { if ($s + 0 != NR - 2) { printf "line %d is step %s, expected %d\n", NR, $s, NR - 2; bad = 1; exit } n = $s + 0 }
  END {
    if (bad) exit 1
    if (n != last) { printf "the last row is step %d, expected %d (the step before the failure)\n", n, last; exit 1 }
  }' "$history") || fail "$history: $report"
tail -c 1 "$history" | od -An -c | grep -q '\\n' || fail "$history does not end with a complete line"
pass "history.csv keeps steps 0..$((failed_at - 1)), written before the failure"

# the .pvd is complete and lists the frames on disk (one per step before the failure)
pvd="$out/diverge.pvd"
expect_nonempty_file "$pvd"
grep -q '</VTKFile>' "$pvd" || fail "$pvd is not complete"
listed=$(grep -c '<DataSet ' "$pvd")
[[ $listed -eq $failed_at ]] || fail "$pvd lists $listed frames, expected $failed_at (steps 0..$((failed_at - 1)))"
for f in $(sed -nE 's/.*file="([^"]+)".*/\1/p' "$pvd"); do
  expect_nonempty_file "$out/$f"
  tail -c 64 "$out/$f" | grep -q '</VTKFile>' || fail "$out/$f is truncated"
done
[[ -z "$(find "$out" -name '*.tmp')" ]] || fail "a temporary file was left in $out"
pass "$pvd is complete and lists the $listed frames on disk"

# an output directory that cannot be created: a run failure (1), reported before any step
blocker="$TMP/not_a_directory"
echo "a file in the way" >"$blocker"
run_peri run "$DECKS/valid_small.yaml" --quiet --output "$blocker/out"
expect_status 1
expect_stderr_contains "cannot create directory"
expect_stderr_contains "$blocker"
[[ "$(cat "$blocker")" == "a file in the way" ]] || fail "the file in the way was changed"
pass "an output path under a regular file: status 1, 'cannot create directory'"

echo "PASS: $CLI_NAME"
