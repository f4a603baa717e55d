#!/usr/bin/env bash
# MPI ranks do not change the result of the LPS model (docs/parallel.md): the dilatation of
# ghost nodes reaches their neighbours between the two passes of the model. The small 2D LPS
# fracture deck on 1, 2, 3 and 4 ranks gives the same history.csv, to a relative 1e-12 on
# every value, and the same number of broken bonds. Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_lps.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

mpi_same_on_ranks lps "$DECKS/plate_lps.yaml"
col=$(csv_column "$MPI_REF" broken_bond_fraction)
first=$(sed -n 2p "$MPI_REF" | cut -d, -f"$col")
final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$col")
awk -v a="$first" -v b="$final" 'BEGIN { exit !(b > a) }' ||
  fail "lps: no bond broke during the run (broken_bond_fraction $first -> $final): the comparison is weak"
pass "lps plate: 1, 2, 3, 4 ranks give the same history (tolerance $MPI_TOL); broken bonds $first -> $final"
echo "PASS: $CLI_NAME"
