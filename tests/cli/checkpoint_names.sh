#!/usr/bin/env bash
# output.checkpoint_file may not name a file the run writes or reads (docs/restart.md):
# history.csv, the .pvd, a frame, the picture, the plot, the deck or its node file. Such a
# name is refused when the deck is read, with exit status 2, the file:line:column of the
# key and nothing written; paths are compared resolved ("..", symbolic links), and "{step}"
# stands for any step number.
# Usage: bash tests/cli/checkpoint_names.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
skip_without_checkpoints

# the plate deck with the checkpoint keys in its output section, at known lines
deck="$TMP/decks/plate.yaml"
mkdir -p "$TMP/decks"
sed '/^output:/,$d' "$DECKS/plate_pmb.yaml" >"$deck"
lines=$(wc -l <"$deck")
cat >>"$deck" <<YAML
output:
  directory: "$TMP/out"
  every: 100
  picture: true
  plot: {x: time, y: kinetic_energy}
  checkpoint_every: 50
  checkpoint_file: "CHECKPOINT"
YAML
key_line=$((lines + 7))

# refused NAME WHAT: checkpoint_file NAME is refused as overwriting WHAT, at the key.
refused() {
  sed "s|CHECKPOINT|$1|" "$deck" >"$TMP/decks/case.yaml"
  run_peri run "$TMP/decks/case.yaml" --quiet
  expect_status 2
  expect_stderr_contains "case.yaml:$key_line:3: error: key 'checkpoint_file': '$1' would overwrite $2"
  expect_no_path "$TMP/out"
  pass "checkpoint_file '$1': refused as $2"
}
refused "history.csv" "the run's history.csv"
refused "case.pvd" "the run's .pvd"
refused "case_000002.vtu" "a frame of the run"
refused "case_{step}.vtu" "a frame of the run"
refused "case_{step}.pvtu" "a frame of the run"
refused "damage.png" "the run's picture"
refused "kinetic_energy_vs_time.png" "the run's plot"
refused "./sub/../history.csv" "the run's history.csv"
refused "$TMP/decks/case.yaml" "the deck"
refused "../decks/case.yaml" "the deck"
# through a symbolic link to the output directory
mkdir -p "$TMP/real"
ln -s "$TMP/real" "$TMP/link"
sed -i "s|directory: \"$TMP/out\"|directory: \"$TMP/real\"|" "$deck"
sed "s|CHECKPOINT|$TMP/link/history.csv|" "$deck" >"$TMP/decks/case.yaml"
run_peri check "$TMP/decks/case.yaml"
expect_status 2
expect_stderr_contains "would overwrite the run's history.csv ($TMP/real/history.csv)"
pass "an absolute name through a link to the output directory: refused"

# names of their own are accepted, and the run writes them
sed -i "s|directory: \"$TMP/real\"|directory: \"$TMP/out\"|" "$deck"
for name in "checkpoint_{step}.h5" "history_{step}.csv.h5" "case.h5" "checkpoints/case_{step}.vtu.h5"; do
  sed "s|CHECKPOINT|$name|" "$deck" >"$TMP/decks/case.yaml"
  run_peri check "$TMP/decks/case.yaml"
  expect_status 0
done
sed "s|CHECKPOINT|checkpoints/c_{step}.h5|" "$deck" >"$TMP/decks/case.yaml"
run_peri run "$TMP/decks/case.yaml" --quiet
expect_status 0
expect_nonempty_file "$TMP/out/checkpoints/c_000200.h5"
pass "names of their own are accepted"
echo "PASS: $CLI_NAME"
