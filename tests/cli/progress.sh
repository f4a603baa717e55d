#!/usr/bin/env bash
# Progress lines when stderr is not a terminal (a batch job's log; src/run/progress.c):
#  - an explicit run with --progress=0.01 prints "progress: step N/M (P%)  t = ... s  elapsed ...
#    R steps/s  eta ..." lines, whose step counts rise and stay within the run's 400 steps;
#  - a quasi-static run with the dynamic switch (tests/cli/decks/qs_bar3d.yaml) prints load
#    step, pseudo-time, rate, ETA, the solve's iteration and residual, broken bonds and the
#    phase, both static and dynamic, and its broken-bond count ends at the run's total less
#    the pre-cut ones (the summary's "broken bonds N of M", none pre-cut here);
#  - without --progress a run shorter than the 10 s default prints no line, --quiet and
#    --progress=0 print none, and a malformed interval is an error (exit 2) before any work.
# Usage: bash tests/cli/progress.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
D=tests/cli/decks

run_peri run "$D/plate_pmb.yaml" --progress=0.01 --output "$TMP/explicit" --set solver.steps=400
expect_status 0
grep -q '^progress: ' "$RUN_STDERR" || fail "no progress line on a non-terminal stderr with --progress=0.05"
line_re='^progress: step [0-9]+/400 \([0-9]+%\)  t = [0-9.e+-]+ s  elapsed [0-9.]+ (s|min)[^ ]*  [0-9.e+]+ steps/s  eta ([0-9.]+ (s|min)|\?)'
bad=$(grep '^progress: ' "$RUN_STDERR" | grep -Ev "$line_re" | head -n 1)
[[ -z "$bad" ]] || fail "explicit progress line without the expected fields: $bad"
steps=$(sed -nE 's/^progress: step ([0-9]+)\/400.*/\1/p' "$RUN_STDERR")
sort -n -c <<<"$steps" || fail "the step counts of the progress lines do not rise: $steps"
(($(wc -l <<<"$steps") >= 2)) || fail "expected at least two progress lines at 0.01 s intervals"
grep -q $'\r' "$RUN_STDERR" && fail "a non-terminal stderr got the live line's carriage returns"
pass "explicit: $(grep -c '^progress: ' "$RUN_STDERR") lines with step, time, rate and ETA"

run_peri run "$D/qs_bar3d.yaml" --progress=0.05 --output "$TMP/qs"
expect_status 0
qs_re='^progress: load step [0-9]+/4(  t = [0-9.e+-]+ of 1|, dynamic phase: [0-9]+ explicit steps in all, [0-9.e+-]+ s of dynamics)  elapsed [^ ]+ [^ ]+  [0-9.e+-]+ load steps/s  eta [^ ]+( [^ ]+)?  solve [0-9]+: iteration [0-9]+, residual [0-9.e+-]+ \(tolerance 1e-08\)  broken bonds [0-9]+  cut-backs [0-9]+  phase (static|dynamic)$'
bad=$(grep '^progress: ' "$RUN_STDERR" | grep -Ev "$qs_re" | head -n 1)
[[ -z "$bad" ]] || fail "quasi-static progress line without the expected fields: $bad"
grep -q 'phase static$' "$RUN_STDERR" || fail "no progress line during a static solve"
grep -q 'phase dynamic$' "$RUN_STDERR" || fail "no progress line during the dynamic phase"
grep -Eq 'iteration [1-9][0-9]*, residual' "$RUN_STDERR" || fail "no iteration count in the solve's progress"
last=$(sed -nE 's/.*broken bonds ([0-9]+) .*/\1/p' "$RUN_STDERR" | tail -n 1)
total=$(sed -nE 's/^  broken bonds ([0-9]+) of.*/\1/p' "$RUN_STDOUT")
[[ -n "$last" && -n "$total" && $last -le $total && $last -gt 0 ]] ||
  fail "broken bonds in the progress lines ($last) should be positive and at most the run's total ($total)"
pass "quasi-static: load step, residual, iterations, broken bonds ($last of $total) and both phases"

run_peri run "$D/plate_pmb.yaml" --output "$TMP/default" --set solver.steps=20
expect_status 0
grep -q '^progress: ' "$RUN_STDERR" && fail "a run shorter than the 10 s default printed a progress line"
for opts in "--quiet --progress=0.05" "--progress=0"; do
  # shellcheck disable=SC2086
  run_peri run "$D/plate_pmb.yaml" $opts --output "$TMP/off" --set solver.steps=200
  expect_status 0
  grep -q '^progress: ' "$RUN_STDERR" && fail "$opts printed a progress line"
done
pass "no lines by default in a short run, with --quiet, or with --progress=0"

for bad_value in abc -1 ""; do
  run_peri run "$D/plate_pmb.yaml" "--progress=$bad_value" --output "$TMP/bad"
  expect_status 2
  expect_stderr_contains "option --progress: expected seconds between lines"
  expect_no_path "$TMP/bad"
done
pass "a malformed --progress interval is refused with exit 2"
echo "PASS: $CLI_NAME"
