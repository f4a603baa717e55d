#!/usr/bin/env bash
# A horizon that varies on MPI ranks (docs/variable_horizon.md, "Limits"; docs/parallel.md):
# full peridynamics (discretization.partial_stress: none) runs distributed. PMB's one-pass force
# reads each bond's constants (both ends' states summed in the bond's entry), sliced with the
# bonds; LPS and the LAMMPS breaking order compute the other end's state of each bond from the
# ghost's horizon, constant, dilatation and P (exchanged) by the operations that node's own rank
# uses. Every sum runs in the order of one process, so history.csv is the same on any number of
# ranks to a relative 1e-12, with the same broken bonds (1 and 2 or 3 ranks here):
#  - examples/graded_notched_beam.yaml (a graded grid, dx 1 and 3 mm, PMB, nlcg to failure: the
#    crack, re-solves and cut-backs), and its first 3 load steps with the lps model;
#  - examples/horizon_pulse.yaml with partial_stress: none (explicit, delta 3 dx and 6 dx), with
#    PMB in the LAMMPS breaking order and with LPS;
# and a coupling region (the partial stress, the pulse's default), whose reactions would scatter
# to other ranks' nodes, is refused with exit 2 before any work.
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_variable_horizon.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

# (the beam's nlcg takes 46,740 iterations, each with global sums: 2 ranks, so that the ranks do
# not share a core with each other when ctest runs tests side by side)
export MPI_RANKS="1 2"
mpi_same_on_ranks graded_beam examples/graded_notched_beam.yaml --set output.frames=0 --set output.picture=false
[[ "$MPI_BROKEN" =~ broken\ bonds\ ([0-9]+) && ${BASH_REMATCH[1]} -gt 0 ]] ||
  fail "graded beam: no bond broke ('$MPI_BROKEN'): the crack was to run on every rank count"
pass "graded notched beam (PMB, nlcg to failure): 1 and 2 ranks give the same history and broken bonds"

lps_beam=(--set materials.pmma.model=lps --set materials.pmma.poisson_ratio=0.3 --set solver.load_steps=3
  --set solver.end_time=0.03 --set output.frames=0 --set output.picture=false)
export MPI_RANKS="1 3"
mpi_same_on_ranks lps_beam examples/graded_notched_beam.yaml "${lps_beam[@]}"
pass "graded notched beam with the lps model (3 load steps): 1 and 3 ranks give the same history"

export MPI_RANKS="1 3"
mpi_same_on_ranks pulse examples/horizon_pulse.yaml --set discretization.partial_stress=none
pass "pulse across a horizon step (PMB, explicit, full peridynamics): 1 and 3 ranks give the same history"
mpi_same_on_ranks pulse_after examples/horizon_pulse.yaml --set discretization.partial_stress=none \
  --set solver.breaking_order=after_force
pass "the pulse in the LAMMPS breaking order (each end's state computed on the bond's side): 1 and 3 ranks agree"
mpi_same_on_ranks pulse_lps examples/horizon_pulse.yaml --set discretization.partial_stress=none \
  --set materials.steel.model=lps --set materials.steel.poisson_ratio=0.3
pass "the pulse with the lps model: 1 and 3 ranks give the same history"

run_peri_mpi 2 check examples/horizon_pulse.yaml
expect_status 2
expect_stderr_contains "on MPI ranks (2 here) a horizon that varies runs as full peridynamics"
expect_stderr_contains "a coupling region"
pass "a coupling region (the partial stress) on 2 ranks: exit 2 naming why"
