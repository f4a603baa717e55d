#!/usr/bin/env bash
# output.frames and the default frame interval (docs/deck.md, output): on a 20-step run,
# frames: 0 writes only the first and the last frame, frames: 4 a frame every
# ceil(20/4) = 5 steps (5 frames), and neither key a frame every 20/10 = 2 steps (11 frames).
# Usage: bash tests/cli/output_frames.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# the small deck without its 'every: 10'
deck="$TMP/small.yaml"
grep -v '^  every: 10$' "$DECKS/valid_small.yaml" > "$deck"
grep -q 'every' "$deck" && fail "fixture still sets output.every"

# frame_count SETTINGS...: runs the deck and prints the number of VTU frames written
frame_count() {
  local out="$TMP/out$#-$*"
  out=${out//[ =.]/_}
  run_peri run "$deck" "$@" --output "$out"
  expect_status 0
  ls "$out"/*.vtu 2>/dev/null | wc -l
}

n=$(frame_count --set output.frames=0)
[[ $n -eq 2 ]] || fail "frames: 0 wrote $n frames, expected 2 (the first and the last)"
n=$(frame_count --set output.frames=4)
[[ $n -eq 5 ]] || fail "frames: 4 wrote $n frames, expected 5 (steps 0, 5, 10, 15, 20)"
n=$(frame_count)
[[ $n -eq 11 ]] || fail "default wrote $n frames, expected 11 (every 2 steps)"
pass "frames: 0, frames: 4 and the default write 2, 5 and 11 frames"
