#!/usr/bin/env bash
# The position-aware surface correction (docs/models.md 4.1) on MPI ranks: every node's
# factors come from its own family and the other end's factors of a bond from the ghost's
# coefficients, so the small 2D PMB and LPS fracture decks give the same history.csv on 1 and 2
# ranks (relative 1e-12 on every value) and the same broken bonds; and bonds break.
# Usage: bash tests/cli/mpi_position_aware.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

for model in pmb lps; do
  MPI_RANKS="1 2" mpi_same_on_ranks "pa_$model" "$DECKS/plate_$model.yaml" \
    --set discretization.surface_correction=position_aware --set solver.steps=60 --set output.picture=false
  col=$(csv_column "$MPI_REF" broken_bond_fraction)
  final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$col")
  awk -v b="$final" 'BEGIN { exit !(b > 0) }' || fail "$model: no bond broke (the comparison is weak)"
  pass "$model plate, position_aware: 1 and 2 ranks give the same history; broken bond fraction $final"
done
echo "PASS: $CLI_NAME"
