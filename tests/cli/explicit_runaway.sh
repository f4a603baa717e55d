#!/usr/bin/env bash
# Runaway growth of an explicit run (docs/solvers.md section 10): the plate of
# decks/diverge.yaml, with a time step 3 and 100 times its stable estimate, stopped after 20
# steps. Before the check the 100-times run reached a kinetic energy of about 1e134 J with
# finite values and exited 0. The kinetic energy of a correct run cannot exceed the initial
# energy plus the work of the loads (here: the initial kinetic energy, about 8.6e-9 J, and no
# loads) by more than the discretization error; the run must exit 1 naming the step and the
# time step, within the first 10 steps, and keep history.csv (finite values) up to the step before.
# The same check stops a damped run and a quasi-static run whose dynamic phase is unstable.
# Usage: bash tests/cli/explicit_runaway.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

for dt in 5.0e-7 1.7e-5; do
  out="$TMP/dt-$dt"
  run_peri run "$DECKS/diverge.yaml" --quiet --output "$out" --set solver.steps=20 --set solver.time_step=$dt
  expect_status 1
  expect_stderr_matches "error: the solution diverged at step [0-9]+ \(t = [0-9.e-]+\): the kinetic energy [0-9.e+-]+ J exceeds 1000 times the energy put into the body"
  expect_stderr_contains "reduce solver.time_step"
  failed_at=$(sed -nE 's/.*diverged at step ([0-9]+).*/\1/p' "$RUN_STDERR" | head -n 1)
  [[ $failed_at -ge 1 && $failed_at -le 10 ]] || fail "dt $dt: expected the divergence within 10 steps, got step $failed_at"
  history="$out/history.csv"
  expect_nonempty_file "$history"
  [[ $(($(wc -l <"$history") - 1)) -eq $failed_at ]] ||
    fail "dt $dt: history.csv should keep steps 0..$((failed_at - 1)) ($(wc -l <"$history") lines)"
  grep -qiE 'nan|inf' "$history" && fail "dt $dt: history.csv holds a value that is not finite"
  pass "time step $dt: exit 1 at step $failed_at, history.csv kept"
done

# damped (solver.damping) runs and the dynamic phases of a quasi-static run use the same
# integrator and check: damping only removes energy, so the bound holds for them too
out="$TMP/damped"
run_peri run "$DECKS/diverge.yaml" --quiet --output "$out" --set solver.steps=20 --set solver.time_step=1.7e-5 \
  --set solver.damping=1e4
expect_status 1
expect_stderr_matches "error: the solution diverged at step [0-9]+ \(t = [0-9.e-]+\): the kinetic energy [0-9.e+-]+ J exceeds 1000 times"
pass "damped explicit run with 100 times the stable step: exit 1"
out="$TMP/qs-dynamic"
run_peri run "$DECKS/qs_bar3d.yaml" --quiet --output "$out" --set solver.dynamic_switch.time_step=1e-5
expect_status 1
expect_stderr_matches "error: the solution diverged at step [0-9]+ \(t = [0-9.e-]+\): the kinetic energy [0-9.e+-]+ J exceeds 1000 times"
expect_nonempty_file "$out/history.csv"
pass "quasi-static run whose dynamic phase takes about 60 times the stable step: exit 1, history.csv kept"

# the stable time step of the same deck runs to its end
run_peri run "$DECKS/diverge.yaml" --quiet --output "$TMP/stable" --set solver.steps=200 --set solver.time_step=1.7e-7
expect_status 0
pass "the stable time step runs its 200 steps"
echo "PASS: $CLI_NAME"
