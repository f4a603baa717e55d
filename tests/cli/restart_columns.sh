#!/usr/bin/env bash
# A restart never loses history rows (docs/restart.md): when the restarted deck writes
# other history.csv columns than the run it continues (here a region added, which adds its
# reaction columns, or one removed), `peri run --restart` into that run's directory is
# refused with exit status 2, a message naming the columns added or removed, and the
# directory left as it was. Into a new directory the same restart runs, and the original
# rows stay where they were.
# Usage: bash tests/cli/restart_columns.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
skip_without_checkpoints
every=(--set output.checkpoint_every=50 --set 'output.checkpoint_file=checkpoint_{step}.h5')
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/run" "${every[@]}" --set solver.steps=100
expect_status 0
ck="$TMP/run/checkpoint_000050.h5"
expect_nonempty_file "$ck"
snapshot() { (cd "$TMP/run" && find . -type f -exec md5sum {} + | sort); }
before=$(snapshot)

# the plate writes 18 columns: time, step, 4 energies, the broken-bond fraction, the mean
# damage, momentum x and y, and the x and y reactions of its 4 regions; with one region more
# (a probe strip: reaction_probe_x, reaction_probe_y), 20 ...
sed 's/^regions:$/regions:\n  probe: {shape: rectangle, min: [0.040, 0.0], max: [0.050, 0.024]}/' \
  "$DECKS/plate_pmb.yaml" >"$TMP/plate_pmb.yaml"
grep -q "probe:" "$TMP/plate_pmb.yaml" || fail "the region was not added to the deck"
run_peri run "$TMP/plate_pmb.yaml" --quiet --output "$TMP/run" --restart "$ck" "${every[@]}"
expect_status 2
expect_stderr_contains "history.csv' has 18 columns and this deck's run writes 20: the deck adds the columns 'reaction_probe_x', 'reaction_probe_y'"
[[ "$(snapshot)" == "$before" ]] || fail "the refused restart changed the run's directory"
pass "a region added: exit 2, the added columns named, the directory unchanged"

# ... and one fewer (bottom_no_fail gone: its reaction columns)
sed '/^  bottom_no_fail:/d' "$DECKS/plate_pmb.yaml" >"$TMP/fewer.yaml"
run_peri run "$TMP/fewer.yaml" --quiet --output "$TMP/run" --restart "$ck" "${every[@]}"
expect_status 2
expect_stderr_contains "the deck no longer has the columns 'reaction_bottom_no_fail_x', 'reaction_bottom_no_fail_y'"
[[ "$(snapshot)" == "$before" ]] || fail "the refused restart changed the run's directory"
pass "a region removed: exit 2, the removed columns named"

# into a new directory the restart runs with the new columns, from the checkpoint's step
run_peri run "$TMP/plate_pmb.yaml" --quiet --output "$TMP/new" --restart "$ck" "${every[@]}"
expect_status 0
expect_stderr_contains "history.csv starts again at the checkpoint"
[[ "$(head -n 1 "$TMP/new/history.csv")" == *reaction_probe_x,reaction_probe_y* ]] ||
  fail "the new history.csv lacks the probe's columns"
[[ "$(sed -n 2p "$TMP/new/history.csv" | cut -d, -f"$(csv_column "$TMP/new/history.csv" step)")" == "51" ]] ||
  fail "the new history.csv does not start after the checkpoint's step 50"
[[ "$(snapshot)" == "$before" ]] || fail "the restart into a new directory changed the original one"
pass "into a new directory: the new columns from step 51, the original rows untouched"
echo "PASS: $CLI_NAME"
