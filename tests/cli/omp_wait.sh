#!/usr/bin/env bash
# The OpenMP wait policy peri chooses (app/omp_wait.c, docs/parallel.md): with none of
# OMP_WAIT_POLICY, GOMP_SPINCOUNT and KMP_BLOCKTIME set, peri executes itself again with
# GOMP_SPINCOUNT=3000 and its summary says so (the line names the value only when the second
# start happened: it reads the mark the first start left); a policy the user set is kept and
# named as the user's.
# Usage: bash tests/cli/omp_wait.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
deck=tests/cli/decks/plate_pmb.yaml
clean=(env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT -u KMP_BLOCKTIME -u PERI_OMP_WAIT_CHOSEN)

"${clean[@]}" "$PERI" check "$deck" >"$TMP/default.out" 2>&1 || fail "peri check failed without a wait policy set"
grep -q '^  threads .*short spin, then sleep (GOMP_SPINCOUNT=3000' "$TMP/default.out" ||
  fail "without a policy set, the summary does not report the short spin: $(grep threads "$TMP/default.out")"
pass "no policy set: peri starts again with GOMP_SPINCOUNT=3000"

"${clean[@]}" OMP_WAIT_POLICY=passive "$PERI" check "$deck" >"$TMP/passive.out" 2>&1 || fail "peri check failed"
grep -q '^  threads .*passive wait (OMP_WAIT_POLICY)' "$TMP/passive.out" ||
  fail "OMP_WAIT_POLICY=passive is not reported as the user's: $(grep threads "$TMP/passive.out")"
pass "OMP_WAIT_POLICY=passive kept"

"${clean[@]}" GOMP_SPINCOUNT=100 "$PERI" check "$deck" >"$TMP/spin.out" 2>&1 || fail "peri check failed"
grep -q '^  threads .*wait from GOMP_SPINCOUNT' "$TMP/spin.out" ||
  fail "GOMP_SPINCOUNT=100 is not reported as the user's: $(grep threads "$TMP/spin.out")"
pass "GOMP_SPINCOUNT kept"

"${clean[@]}" "$PERI" run "$deck" --output "$TMP/run" --set solver.steps=20 >"$TMP/run.out" 2>&1 ||
  fail "peri run failed after starting again"
grep -q '^  finished     20 steps' "$TMP/run.out" || fail "the run started again did not finish its 20 steps"
pass "a run started again finishes"
echo "PASS: $CLI_NAME"
