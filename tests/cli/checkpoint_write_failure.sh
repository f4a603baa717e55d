#!/usr/bin/env bash
# A checkpoint that cannot be written ends the run (docs/restart.md): exit status 1, a
# message naming the file, and what the run wrote before intact (history.csv up to the
# failing step, the frames, the previous checkpoint), with no temporary file left. Two
# causes: a checkpoint_file whose directory cannot be created (a file stands in its way),
# and a full disk, on a 440 KiB tmpfs that holds the first checkpoint of the 2D PMB plate
# (256 KiB) but not the second. Mounting needs root: where it is not allowed the full-disk
# case is skipped with a message.
# Usage: bash tests/cli/checkpoint_write_failure.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
skip_without_checkpoints
every=(--set output.checkpoint_every=50 --set 'output.checkpoint_file=checkpoint_{step}.h5')

# the run without trouble, for comparison
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/full" "${every[@]}"
expect_status 0

# lines of history.csv up to step S: the header, the initial row and one row per step
lines_to() { echo $(($1 + 2)); }

touch "$TMP/blocker"
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/nodir" --set output.checkpoint_every=50 \
  --set "output.checkpoint_file=$TMP/blocker/sub/c.h5"
expect_status 1
expect_stderr_contains "cannot create directory '$TMP/blocker/sub'"
cmp -s "$TMP/nodir/history.csv" <(head -n "$(lines_to 50)" "$TMP/full/history.csv") ||
  fail "history.csv is not the run's rows up to step 50"
cmp -s "$TMP/nodir/plate_pmb_000000.vtu" "$TMP/full/plate_pmb_000000.vtu" || fail "the first frame differs"
pass "a checkpoint directory that cannot be created: exit 1, history.csv and the frame up to step 50 kept"

disk="$TMP/disk"
mkdir -p "$disk"
if ! mount -t tmpfs -o size=440k tmpfs "$disk" 2>/dev/null; then
  echo "skipped: the full-disk case (mounting a tmpfs is not allowed here; it needs root)"
  echo "PASS: $CLI_NAME"
  exit 0
fi
trap 'umount "$disk" 2>/dev/null; cli_cleanup' EXIT
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$disk/o" "${every[@]}"
expect_status 1
expect_stderr_contains "cannot write checkpoint '$disk/o/checkpoint_000100.h5'"
expect_stderr_contains "No space left on device"
cmp -s "$disk/o/checkpoint_000050.h5" "$TMP/full/checkpoint_000050.h5" || fail "the checkpoint of step 50 is not intact"
cmp -s "$disk/o/history.csv" <(head -n "$(lines_to 100)" "$TMP/full/history.csv") ||
  fail "history.csv is not the run's rows up to step 100"
for f in plate_pmb_000000.vtu plate_pmb_000001.vtu; do
  cmp -s "$disk/o/$f" "$TMP/full/$f" || fail "$f is not intact"
done
[[ -z "$(find "$disk/o" -name '*.tmp')" ]] || fail "a temporary checkpoint was left behind"
pass "a full disk at the second checkpoint: exit 1, the first checkpoint, history.csv and frames intact"

# the kept checkpoint continues the run, on a disk with room
cp -r "$disk/o" "$TMP/again"
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/again" --restart "$TMP/again/checkpoint_000050.h5" "${every[@]}"
expect_status 0
cmp -s "$TMP/again/history.csv" "$TMP/full/history.csv" || fail "the restart from the kept checkpoint differs"
pass "the kept checkpoint restarts to the same history.csv"
echo "PASS: $CLI_NAME"
