#!/usr/bin/env bash
# MPI ranks do not change heat conduction (docs/parallel.md): Bobaru & Duangpanya 2012
# Example 5 (two cracks growing across the plate, prescribed temperatures on two edges) on a
# coarse grid for 0.4 s on 1, 2, 3 and 4 ranks, and the thermal-shock example (heat coupled
# both ways with the PMB mechanics, breaking; coarse) for 4 microseconds on 1 and 3 ranks: history.csv
# (total heat, temperature range, mean temperatures and heat inflow of the regions, broken
# bonds) agrees to a relative 1e-12. Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_heat.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

mpi_same_on_ranks heat examples/heat_example5.yaml --set solver.end_time=0.4 \
  --set discretization.spacing=0.05 --set discretization.horizon=0.325
col=$(csv_column "$MPI_REF" broken_bond_fraction)
first=$(sed -n 2p "$MPI_REF" | cut -d, -f"$col")
final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$col")
awk -v a="$first" -v b="$final" 'BEGIN { exit !(b > a) }' ||
  fail "heat: the growing cracks cut no bond during the run ($first -> $final)"
pass "heat conduction with growing cracks: the same history on 1 to 4 ranks (cut fraction $first -> $final)"

MPI_RANKS="1 3" mpi_same_on_ranks thermal_shock examples/thermal_shock.yaml --set solver.end_time=4.0e-6 \
  --set discretization.spacing=2.0e-4 --set output.frames=2
pass "thermal shock (two-way coupling, coarse): the same history on 1 and 3 ranks"
echo "PASS: $CLI_NAME"
