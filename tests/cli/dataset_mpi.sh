#!/usr/bin/env bash
# On MPI ranks the graph dataset (docs/datasets.md) is gathered on rank 0 in the global node
# and bond order: the pre-cracked plate, whose crack grows from step ~100, gives the same
# file on 1 and 3 ranks, byte for byte, to step 120. Skipped when peri was built without MPI.
# Usage: bash tests/cli/dataset_mpi.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init
skip_without_checkpoints

for np in 1 3; do
  run_peri_mpi $np run "$DECKS/plate_pmb.yaml" --quiet --output "$TMP/np$np" --set output.picture=false --set solver.steps=120 \
    --set output.dataset.every=60 --set output.dataset.file=graph.h5
  expect_status 0
  expect_nonempty_file "$TMP/np$np/graph.h5"
done
for np in 3; do
  cmp -s "$TMP/np1/graph.h5" "$TMP/np$np/graph.h5" || fail "the dataset on $np ranks differs from 1 rank's"
done
pass "1 and 3 ranks write the same dataset, byte for byte"
echo "PASS: $CLI_NAME"
