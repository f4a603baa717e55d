#!/usr/bin/env bash
# MPI ranks do not change the result of the osb_mo model (docs/models.md 3.6): its three
# per-node coefficients of ghost nodes reach their neighbours between the two passes. The
# small 2D fracture deck run with osb_mo, elastic and with sublayers, gives the same history.csv
# on 1, 2 and 3 ranks to a relative 1e-12, and the same number of broken bonds. Skipped when
# peri was built without MPI.
# Usage: bash tests/cli/mpi_osb_mo.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

MPI_RANKS="1 2 3"
mpi_same_on_ranks osb_mo "$DECKS/plate_lps.yaml" --set materials.glass.model=osb_mo
col=$(csv_column "$MPI_REF" broken_bond_fraction)
final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$col")
awk -v b="$final" 'BEGIN { exit !(b > 0) }' || fail "osb_mo: no bond broke during the run: the comparison is weak"
pass "osb_mo plate: 1, 2, 3 ranks give the same history (tolerance $MPI_TOL); broken bond fraction $final"

mpi_same_on_ranks osb_mo_plastic "$DECKS/plate_lps.yaml" --set materials.glass.model=osb_mo \
  --set "materials.glass.plasticity={weights: [0.7, 0.3], yield_stretches: [1.0e-4, 3.0e-4]}"
col=$(csv_column "$MPI_REF" broken_bond_fraction)
final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$col")
pass "osb_mo plate with sublayers: 1, 2, 3 ranks give the same history; broken bond fraction $final"
echo "PASS: $CLI_NAME"
