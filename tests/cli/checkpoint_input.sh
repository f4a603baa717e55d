#!/usr/bin/env bash
# Crafted and damaged checkpoints are bad input (docs/restart.md): every count, size and
# index the file holds is checked against the deck, the file's own datasets and the output
# directory before it is used, and a bad one stops `peri run --restart` with exit status 2,
# a message naming the file and the attribute or dataset, and nothing written. Copies of a
# real checkpoint of the 2D PMB plate (step 100 of 200; 101 history rows and 2 frames up to
# it) and of the heat deck with a growing crack are edited with h5py.
# Usage: bash tests/cli/checkpoint_input.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
skip_without_checkpoints
PY=""
for candidate in python3 /usr/bin/python3; do
  if command -v "$candidate" >/dev/null && "$candidate" -c 'import h5py' 2>/dev/null; then
    PY=$candidate
    break
  fi
done
if [[ -z "$PY" ]]; then
  echo "SKIP: $CLI_NAME: no python3 with h5py to craft checkpoints (Debian python3-h5py, see scripts/install-deps)"
  exit 0
fi
craft() { "$PY" "$CLI_DIR/lib/craft_checkpoint.py" "$@" || fail "cannot edit a checkpoint: craft_checkpoint.py $*"; }

every=(--set output.checkpoint_every=50 --set 'output.checkpoint_file=checkpoint_{step}.h5')
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/full" "${every[@]}"
expect_status 0
ck="$TMP/full/checkpoint_000100.h5"
expect_nonempty_file "$ck"

# refused NAME MESSAGE [--output DIR]: the restart from $TMP/NAME.h5 exits 2 with MESSAGE,
# naming the file, and writes nothing (into a fresh directory, or the copy of the run's
# output given, which must stay as it was).
refused() {
  local name=$1 message=$2 out="$TMP/out_$1"
  if [[ $# -ge 4 ]]; then out=$4; fi
  local before=""
  if [[ -d "$out" ]]; then before=$(cd "$out" && find . -type f -exec md5sum {} + | sort); fi
  run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$out" --restart "$TMP/$name.h5"
  expect_status 2
  expect_stderr_contains "$message"
  if [[ -z "$before" ]]; then
    expect_no_path "$out"
  else
    [[ "$(cd "$out" && find . -type f -exec md5sum {} + | sort)" == "$before" ]] ||
      fail "$name: the restart changed the output directory it refused to continue"
  fi
  pass "$name: exit 2, '$message'"
}

# counts far beyond anything a run writes: 2^61 once overflowed the size of the arrays the
# kept history rows and frames were read into (a heap overflow)
craft "$ck" "$TMP/rows.h5" attr /state history_rows 2305843009213693952
refused rows "checkpoint '$TMP/rows.h5': attribute /state/history_rows is 2305843009213693952, outside 0..101"
cp -r "$TMP/full" "$TMP/copy"
refused rows "attribute /state/history_rows is 2305843009213693952" --output "$TMP/copy"
craft "$ck" "$TMP/frames.h5" attr /state frames 2305843009213693952
refused frames "attribute /state/frames is 2305843009213693952, outside 0..101"
refused frames "attribute /state/frames is 2305843009213693952" --output "$TMP/copy"
craft "$ck" "$TMP/negative_rows.h5" attr /state history_rows -1
refused negative_rows "attribute /state/history_rows is -1, outside 0..101"
craft "$ck" "$TMP/negative_step.h5" attr /state step -5
refused negative_step "attribute /state/step is -5"
craft "$ck" "$TMP/dynamic_steps.h5" attr /quasi_static dynamic_steps -3
refused dynamic_steps "attribute /quasi_static/dynamic_steps is -3"

# within the range, but more rows than the history.csv of the directory holds
head -n 21 "$TMP/full/history.csv" >"$TMP/copy/history.csv"
cp "$ck" "$TMP/short.h5"
refused short "holds 20 complete rows, but the checkpoint records 101" --output "$TMP/copy"
cp "$TMP/full/history.csv" "$TMP/copy/history.csv"

# an attribute or dataset of another shape: an array where one value belongs, a dataset of
# five dimensions (its extent would not fit the two the reader expects)
craft "$ck" "$TMP/step_array.h5" attr_array /state step 1000
refused step_array "attribute 'step' is not a single value"
craft "$ck" "$TMP/rank5.h5" rank3 /nodes/u
refused rank5 "dataset 'u' has 0 values, expected 4320"
# a chunk index (it has no checksum) that says a chunk is shorter than its values, or that
# its checksum was skipped: HDF5 copied the values from past the chunk it had read
craft "$ck" "$TMP/chunk_short.h5" chunk /indenter/force 1 10
refused chunk_short "dataset 'force' is not stored as peri writes it"
craft "$ck" "$TMP/chunk_unchecked.h5" chunk /nodes/u 1 34560
refused chunk_unchecked "dataset 'u' is not stored as peri writes it"
craft "$ck" "$TMP/chunk_long.h5" chunk /nodes/v 0 40000
refused chunk_long "dataset 'v' is not stored as peri writes it"

# the heat deck's checkpoint: the growing-crack position and the coupling counts
run_peri run "$DECKS/restart_heat.yaml" --quiet --output "$TMP/heat"
expect_status 0
hk="$TMP/heat/checkpoint_000020.h5"
expect_nonempty_file "$hk"
heat_refused() {
  run_peri run "$DECKS/restart_heat.yaml" --quiet --output "$TMP/heat_$1" --restart "$TMP/$1.h5"
  expect_status 2
  expect_stderr_contains "checkpoint '$TMP/$1.h5'"
  expect_stderr_contains "$2"
  expect_no_path "$TMP/heat_$1"
  pass "heat $1: exit 2, '$2'"
}
craft "$hk" "$TMP/growing.h5" attr /thermal growing_next 4611686018427387904
heat_refused growing "attribute /thermal/growing_next does not match the deck's growing cracks"
craft "$hk" "$TMP/every.h5" attr /thermal every -1
heat_refused every "attribute /thermal/every is -1"
craft "$hk" "$TMP/substeps.h5" attr /thermal substeps -7
heat_refused substeps "attribute /thermal/substeps is -7"

# the unedited checkpoint still restarts
run_peri run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/copy" --restart "$ck" "${every[@]}"
expect_status 0
cmp -s "$TMP/full/history.csv" "$TMP/copy/history.csv" || fail "the restart from the unedited checkpoint differs"
pass "the unedited checkpoint restarts to the same history.csv"

echo "PASS: $CLI_NAME"
