#!/usr/bin/env bash
# MPI ranks do not change the per-phase stress (docs/microstructures.md): the cooled Bi2212
# filament from an image (tests/cli/decks/filament_cooling.yaml, LPS with thermal strain, two
# materials) on 1 and 3 ranks gives the same history.csv, its columns max_von_mises_MAT,
# max_von_mises_at_MAT_x, _y and mean_stress_MAT included (relative MPI_TOL). The stress of a
# node next to another rank's nodes takes their halves of the bonds from the coefficients the
# force pass exchanges. Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_phase_stress.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init
cp "$DECKS/filament_cooling.yaml" "$TMP/"
python3 scripts/microstructure longitudinal "$TMP/filament.png" --width 120 --height 60 --filament-width 0.4 \
  --waviness 0.02 --seed 1 || fail "scripts/microstructure longitudinal"
MPI_RANKS="1 3" mpi_same_on_ranks phase_stress "$TMP/filament_cooling.yaml" --threads 1
[[ -n "$(csv_column "$MPI_REF" mean_stress_bi2212)" ]] || fail "history.csv has no mean_stress_bi2212 column"
pass "cooled filament: 1 and 3 ranks give the same history, per-phase stress columns included (tolerance $MPI_TOL)"
echo "PASS: $CLI_NAME"
