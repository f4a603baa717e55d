#!/usr/bin/env bash
# Crash consistency (docs/reliability.md, docs/restart.md): a run killed with SIGKILL at an
# arbitrary moment leaves a checkpoint that is complete, and the run continued from it ends
# exactly as a run that was never interrupted.
#
# The 2D PMB fracture plate (bonds break throughout) writes one checkpoint file, replaced
# every 25 steps through FILE.tmp and a rename, with frames and a history row every step.
# A reference run without interruption keeps every checkpoint (checkpoint_{step}.h5).
# Several runs are killed with `kill -9` after random delays within the reference run's
# duration, each time:
#   - the checkpoint left behind must equal, byte for byte, the reference checkpoint of
#     its step (checkpoints hold no time stamps, so the same state gives the same bytes):
#     never half written, never a mixture of two steps;
#   - `peri run --restart` from it must succeed and give the reference history.csv
#     byte for byte (its last row included) and the reference final checkpoint.
# Usage: bash tests/cli/crash_consistency.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

DECK="$DECKS/plate_pmb.yaml"
STEPS=1500
EVERY=25
KILLS=6
common=(--quiet --threads 1 --set solver.steps=$STEPS --set output.every=100
        --set output.checkpoint_every=$EVERY)

# A build without HDF5 has no checkpoints to test (restart.sh checks its messages).
run_peri check "$DECK" --set output.checkpoint_every=$EVERY
if [[ $RUN_STATUS -ne 0 ]] && grep -q "built without HDF5" "$RUN_STDERR"; then
  pass "built without HDF5: no checkpoints, nothing to test"
  echo "PASS: $CLI_NAME"
  exit 0
fi
expect_status 0

# the reference: every checkpoint kept, and the run's duration to place the kills in
ref="$TMP/reference"
start=$(date +%s%N)
run_peri run "$DECK" "${common[@]}" --output "$ref" --set 'output.checkpoint_file=checkpoint_{step}.h5'
expect_status 0
duration_ms=$((($(date +%s%N) - start) / 1000000))
final=$(printf '%s/checkpoint_%06d.h5' "$ref" "$STEPS")
expect_nonempty_file "$final"
expect_nonempty_file "$ref/history.csv"
[[ $(($(wc -l <"$ref/history.csv") - 1)) -eq $((STEPS + 1)) ]] || fail "the reference history.csv has not one row per step"
pass "reference run: $STEPS steps in $duration_ms ms, $(ls "$ref"/checkpoint_*.h5 | wc -l) checkpoints"

# reference_step FILE: the step of the reference checkpoint equal to FILE byte for byte
# (empty when none is).
reference_step() {
  local f
  for f in "$ref"/checkpoint_*.h5; do
    if cmp -s "$1" "$f"; then
      f=${f##*_}
      echo $((10#${f%.h5}))
      return
    fi
  done
}

restarted=0
for ((trial = 1; trial <= KILLS; ++trial)); do
  dir="$TMP/killed_$trial"
  # a delay from 5% to 90% of the uninterrupted run's duration
  delay_ms=$((duration_ms * (5 + RANDOM % 86) / 100))
  "$PERI" run "$DECK" "${common[@]}" --output "$dir" --set output.checkpoint_file=restart.h5 \
    >"$TMP/killed_$trial.out" 2>&1 </dev/null &
  pid=$!
  sleep "$(printf '%d.%03d' $((delay_ms / 1000)) $((delay_ms % 1000)))"
  if kill -9 "$pid" 2>/dev/null; then
    wait "$pid" 2>/dev/null
    what="killed after $delay_ms ms"
  else
    wait "$pid" # it had finished: the last checkpoint is the final one
    what="finished before the kill at $delay_ms ms"
  fi

  if [[ ! -e "$dir/restart.h5" ]]; then
    pass "trial $trial: $what, before the first checkpoint (restart.h5 absent, nothing to check)"
    continue
  fi
  step=$(reference_step "$dir/restart.h5")
  [[ -n "$step" ]] || fail "trial $trial ($what): restart.h5 equals none of the reference checkpoints (half written?)"
  tmp_left=""
  [[ -e "$dir/restart.h5.tmp" ]] && tmp_left=", restart.h5.tmp left behind"

  run_peri run "$DECK" "${common[@]}" --output "$dir" --set output.checkpoint_file=restart.h5 \
    --restart "$dir/restart.h5"
  expect_status 0
  cmp -s "$dir/history.csv" "$ref/history.csv" ||
    fail "trial $trial: history.csv after the restart from step $step differs from the reference" \
         "(last rows: $(tail -n 1 "$dir/history.csv") | $(tail -n 1 "$ref/history.csv"))"
  [[ "$(tail -n 1 "$dir/history.csv")" == "$(tail -n 1 "$ref/history.csv")" ]] || fail "trial $trial: last rows differ"
  cmp -s "$dir/restart.h5" "$final" || fail "trial $trial: the final checkpoint after the restart differs from the reference"
  restarted=$((restarted + 1))
  pass "trial $trial: $what; the checkpoint left is the complete one of step $step$tmp_left; the restart ends as the reference"
done
[[ $restarted -ge 3 ]] || fail "only $restarted of $KILLS killed runs had written a checkpoint (the run is too fast for the delays)"
echo "PASS: $CLI_NAME"
