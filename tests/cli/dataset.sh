#!/usr/bin/env bash
# The graph dataset (output.dataset, docs/datasets.md): bad keys are refused with exit
# status 2 at their file:line:column before any work (also on a heat-only run); the file does not depend on the
# number of threads (byte for byte); a restarted run refuses to continue a dataset.
# (The forces recomputed from the file: python.dataset; ranks: cli.dataset_mpi.)
# Usage: bash tests/cli/dataset.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
skip_without_checkpoints # (HDF5)

deck="$TMP/plate.yaml"
sed '/^output:/,$d' "$DECKS/plate_pmb.yaml" >"$deck"
lines=$(wc -l <"$deck")
printf 'output:\n  picture: false\n  dataset: {every: 0}\n' >>"$deck"
run_peri run "$deck" --output "$TMP/bad"
expect_status 2
expect_stderr_contains "plate.yaml:$((lines + 3)):"
expect_stderr_contains "key 'every': must be >= 1"
expect_no_path "$TMP/bad/plate_graph.h5"
pass "every: 0 refused at its line, nothing written"

sed -i '$d' "$deck"
printf '  dataset: {every: 10, tags: {load: [1, 2]}}\n' >>"$deck"
run_peri run "$deck" --output "$TMP/bad"
expect_status 2
expect_stderr_contains "tag 'load' must be a number or a text"
sed -i '$d' "$deck"
printf '  dataset: {evry: 10}\n' >>"$deck"
run_peri run "$deck" --output "$TMP/bad"
expect_status 2
expect_stderr_contains "did you mean 'every'"
run_peri check examples/heat_example1.yaml --set output.dataset.every=5
expect_status 2
expect_stderr_contains "a heat conduction run (solver: heat) has no bonds' mechanics"
pass "a list as a tag, a misspelt key and a heat-only run are refused"

sed -i '$d' "$deck"
printf '  dataset: {every: 40, file: graph.h5, tags: {load: 3.0e6, defect: crack}}\n  checkpoint_every: 60\n' >>"$deck"
for t in 1 2; do
  run_peri run "$deck" --quiet --threads $t --output "$TMP/t$t" --set solver.steps=120
  expect_status 0
  expect_nonempty_file "$TMP/t$t/graph.h5"
done
cmp -s "$TMP/t1/graph.h5" "$TMP/t2/graph.h5" || fail "the dataset of 1 and 2 threads differ"
pass "1 and 2 threads write the same dataset, byte for byte"

run_peri run "$deck" --quiet --output "$TMP/t1" --set solver.steps=120 --restart "$TMP/t1/plate.h5"
expect_status 1
expect_stderr_contains "a restarted run cannot continue a graph dataset"
pass "a restart refuses to continue the dataset"
echo "PASS: $CLI_NAME"
