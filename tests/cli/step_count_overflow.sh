#!/usr/bin/env bash
# Step counts derived from two deck numbers: end_time / time_step, and for coupled
# thermomechanics the heat sub-steps run time / thermal.time_step. A count beyond the
# largest long (2^63 - 1) must be an input error at the key (exit 2, nothing run), not a
# negative or wrapped count that runs nothing and exits 0.
# Usage: bash tests/cli/step_count_overflow.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# mechanical steps: 1 / 1e-300 = 1e300 steps
deck="$TMP/steps.yaml"
sed 's/^  steps: 20$/  end_time: 1.0\n  time_step: 1.0e-300/' "$DECKS/valid_small.yaml" >"$deck"
locate "end_time: 1.0" "$deck"
LOC_COL=$((LOC_COL + 10)) # the value
run_peri check "$deck"
expect_status 2
expect_stdout_empty
expect_stderr_contains "$deck:$LOC_LINE:$LOC_COL: error: end_time / time_step = 1e+300 steps, more than the largest count 9223372036854775807"
pass "end_time / time_step beyond 2^63 steps is refused at end_time"

run_peri run "$deck" --quiet --output "$TMP/out"
expect_status 2
expect_no_path "$TMP/out"
pass "run refuses it before any output"

# the same count just within range is accepted: 2^62 steps (check only, nothing is run)
sed 's/^  steps: 20$/  end_time: 4.611686018427388e-282\n  time_step: 1.0e-300/' \
  "$DECKS/valid_small.yaml" >"$TMP/within.yaml"
run_peri check "$TMP/within.yaml"
expect_status 0
expect_stdout_contains "4611686018427387904 steps"
pass "2^62 steps is still a valid count"

# heat sub-steps of a coupled run: about 4e-6 s / 1e-300 s
deck="$TMP/thermal.yaml"
sed -e 's/^  coupling: two_way$/  coupling: two_way\n  time_step: 1.0e-300/' -e '/checkpoint/d' \
  "$DECKS/restart_thermal_shock.yaml" >"$deck"
locate "time_step: 1.0e-300" "$deck"
LOC_COL=$((LOC_COL + 11))
run_peri check "$deck"
expect_status 2
expect_stderr_contains "$deck:$LOC_LINE:$LOC_COL: error: run time / thermal time_step = "
expect_stderr_contains "heat sub-steps, more than the largest count 9223372036854775807"
run_peri run "$deck" --quiet --output "$TMP/out"
expect_status 2
expect_no_path "$TMP/out"
pass "thermal time_step of 1e-300 s is refused at the key"

# conduction only (solver type heat): end_time / time_step counts the heat steps
deck="$TMP/heat.yaml"
sed -e 's/^solver: {type: heat, steps: 60}$/solver: {type: heat, end_time: 10, time_step: 1.0e-300}/' \
  -e '/checkpoint/d' "$DECKS/restart_heat.yaml" >"$deck"
locate "end_time: 10" "$deck"
LOC_COL=$((LOC_COL + 10))
run_peri check "$deck"
expect_status 2
expect_stderr_contains "$deck:$LOC_LINE:$LOC_COL: error: end_time / time_step = 1e+301 steps"
pass "solver type heat: 1e301 heat steps are refused at end_time"
