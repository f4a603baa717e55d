#!/usr/bin/env bash
# Sublayer plasticity on MPI ranks (docs/plasticity.md, docs/parallel.md): the pre-cracked
# plate with two sublayers, PMB and LPS, gives the same history (mean yield index, broken
# bonds, energies) on 1, 2, 3 and 4 ranks; each rank keeps the plastic state of its own
# families.
# Usage: bash tests/cli/mpi_plasticity.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

layers='plasticity: {weights: [0.9, 0.1], yield_stretches: [5.0e-5, 2.0e-4]}'
mpi_same_on_ranks plastic_pmb "$DECKS/plate_pmb.yaml" \
  --set "materials.glass={model: pmb, density: 2440, youngs_modulus: 72.0e9, fracture_energy: 3.8, $layers}"
col=$(csv_column "$MPI_REF" mean_yield_index)
[[ -n "$col" ]] || fail "history.csv has no mean_yield_index"
final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$col")
awk -v p="$final" 'BEGIN { exit !(p > 0.1) }' || fail "the plate barely yields (mean yield index $final)"
pass "plastic pmb plate: 1 to 4 ranks give the same history (mean yield index $final)"

mpi_same_on_ranks plastic_lps "$DECKS/plate_lps.yaml" \
  --set "materials.glass={model: lps, density: 2440, youngs_modulus: 72.0e9, poisson_ratio: 0.22, fracture_energy: 3.8, $layers}"
pass "plastic lps plate: 1 to 4 ranks give the same history"

echo "PASS: $CLI_NAME"
