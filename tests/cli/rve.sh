#!/usr/bin/env bash
# peri rve (docs/microstructures.md section 7): bad keys and values exit 2 with the key named,
# before any work; a small Monte-Carlo prints the moduli and writes one CSV row per realization,
# the same with one thread and with two; `picture` and `convergence` write PNG files, and an
# unwritable path is an error (exit 1: the moduli are printed first, the run keeps them).
# Usage: bash tests/cli/rve.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

run_peri rve sid=1e-6
expect_status 2
expect_stderr_contains "unknown key 'sid'"
run_peri rve kappa=soft
expect_status 2
expect_stderr_contains "kappa: expected a number, got 'soft'"
run_peri rve weight_fraction=1.2
expect_status 2
expect_stderr_contains "weight_fraction must be in [0, 1)"
run_peri rve realizations=0
expect_status 2
expect_stderr_contains "realizations: expected an integer"
run_peri rve side
expect_status 2
expect_stderr_contains "expected KEY=VALUE, got 'side'"
pass "bad keys and values exit 2 naming the key"

run_peri rve side=0.3e-6 realizations=3 csv="$TMP/one.csv" --threads 1
expect_status 0
expect_stdout_matches "^E11 +[0-9.]+ \+- [0-9.e-]+ GPa"
expect_stdout_matches "^nu21 +0\.3"
[[ $(wc -l <"$TMP/one.csv") -eq 4 ]] || fail "expected a header and 3 rows in the CSV"
run_peri rve side=0.3e-6 realizations=3 csv="$TMP/two.csv" --threads 2
expect_status 0
cmp -s "$TMP/one.csv" "$TMP/two.csv" || fail "the realizations differ between 1 and 2 threads"
pass "a Monte-Carlo of 3 realizations, the same on 1 and 2 threads"

run_peri rve side=0.3e-6 realizations=3 picture="$TMP/rve.png" convergence="$TMP/conv.png" --threads 1
expect_status 0
for f in rve.png conv.png; do
  [[ "$(head -c 8 "$TMP/$f" | od -An -tx1 | tr -d ' \n')" == 89504e470d0a1a0a ]] || fail "$f is not a PNG file"
done
run_peri rve side=0.3e-6 realizations=1 convergence="$TMP/no/such/dir/conv.png" --threads 1
expect_status 1
expect_stdout_matches "^E11 +[0-9.]+"
pass "picture and convergence PNGs; an unwritable convergence path fails after the moduli"
