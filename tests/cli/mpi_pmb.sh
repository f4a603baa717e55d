#!/usr/bin/env bash
# MPI ranks do not change the result (docs/parallel.md): the small 2D PMB fracture deck (a
# pre-cracked plate pulled apart; the crack grows and branches during the run) on 1, 2, 3
# and 4 ranks gives the same history.csv, to a relative 1e-12 on every value, and the same
# number of broken bonds. The same for the LAMMPS-style problem (3D, compression-dependent
# critical stretch exchanged between ranks, indenter force summed over ranks), shortened,
# and the damage picture (gathered on rank 0) is the same PNG.
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_pmb.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

mpi_same_on_ranks pmb "$DECKS/plate_pmb.yaml" --set output.picture=true
col=$(csv_column "$MPI_REF" broken_bond_fraction)
first=$(sed -n 2p "$MPI_REF" | cut -d, -f"$col")
final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$col")
awk -v a="$first" -v b="$final" 'BEGIN { exit !(b > a) }' ||
  fail "pmb: no bond broke during the run (broken_bond_fraction $first -> $final): the comparison is weak"
pass "pmb plate: 1, 2, 3, 4 ranks give the same history (tolerance $MPI_TOL); broken bonds $first -> $final"

# the picture is drawn by rank 0 from every rank's nodes: the same PNG as one process
for np in 2 3 4; do
  expect_nonempty_file "$TMP/pmb-np$np/damage.png"
  cmp -s "$TMP/pmb-np1/damage.png" "$TMP/pmb-np$np/damage.png" || fail "damage.png differs between 1 and $np ranks"
done
pass "damage.png on 2, 3 and 4 ranks is the one of a single process"

# 3D, 100 of the 1000 steps (the indenter has broken bonds by then), on 1 and 3 ranks
MPI_RANKS="1 3" mpi_same_on_ranks lammps examples/lammps_peri_pmb.yaml --set solver.steps=100 --set output.every=50
mpi_ref_final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$(csv_column "$MPI_REF" broken_bond_fraction)")
awk -v b="$mpi_ref_final" 'BEGIN { exit !(b > 0) }' || fail "lammps: no bond broke in 100 steps"
pass "LAMMPS-style 3D problem (s00/alpha critical stretch, indenter): the same history on 1 and 3 ranks"
echo "PASS: $CLI_NAME"
