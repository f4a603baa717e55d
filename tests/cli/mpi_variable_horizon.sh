#!/usr/bin/env bash
# A horizon that varies on MPI ranks (docs/variable_horizon.md, "Limits"; docs/parallel.md):
# full peridynamics with PMB (discretization.partial_stress: none) runs distributed: each bond
# keeps both ends' constants, sliced with the bonds, and each rank its nodes' and ghosts'
# horizons and critical-stretch factors, so every sum runs in the order of one process and
# history.csv is the same on 1, 2 and 3 ranks to a relative 1e-12, with the same broken bonds:
#  - examples/graded_notched_beam.yaml (a graded grid, dx 1 and 3 mm, PMB, nlcg to failure: the
#    crack, re-solves and cut-backs);
#  - examples/horizon_pulse.yaml with partial_stress: none (explicit, delta 3 dx and 6 dx);
# and what needs the reverse bonds of other ranks is refused with exit 2 before any work: a
# coupling region (the partial stress, the pulse's default) and the lps model.
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_variable_horizon.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

export MPI_RANKS="1 2 3"
mpi_same_on_ranks graded_beam examples/graded_notched_beam.yaml --set output.frames=0 --set output.picture=false
[[ "$MPI_BROKEN" =~ broken\ bonds\ ([0-9]+) && ${BASH_REMATCH[1]} -gt 0 ]] ||
  fail "graded beam: no bond broke ('$MPI_BROKEN'): the crack was to run on every rank count"
pass "graded notched beam (PMB, nlcg to failure): 1, 2 and 3 ranks give the same history and broken bonds"

export MPI_RANKS="1 3"
mpi_same_on_ranks pulse examples/horizon_pulse.yaml --set discretization.partial_stress=none
pass "pulse across a horizon step (PMB, explicit, full peridynamics): 1 and 3 ranks give the same history"

run_peri_mpi 2 check examples/horizon_pulse.yaml
expect_status 2
expect_stderr_contains "on MPI ranks (2 here) a horizon that varies runs as full peridynamics"
expect_stderr_contains "a coupling region"
pass "a coupling region (the partial stress) on 2 ranks: exit 2 naming why"

run_peri_mpi 2 check examples/graded_notched_beam.yaml --set materials.pmma.model=lps \
  --set materials.pmma.poisson_ratio=0.3
expect_status 2
expect_stderr_contains "this deck has the lps model"
pass "the lps model with a horizon that varies on 2 ranks: exit 2 naming why"
