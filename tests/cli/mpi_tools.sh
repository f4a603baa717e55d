#!/usr/bin/env bash
# Rigid tools on several MPI ranks (docs/contact.md "Rigid tools"): the force on a tool is
# summed per block of nodes in node order, whatever rank owns the block, and the load
# control's offset follows from that sum, so 1 and 2 ranks give the same history.csv to a
# relative 1e-12: a plane slid with Coulomb friction (explicit) and a flat punch under load
# control (explicit, its own damped equation), and the punch under load control in the
# quasi-static solvers (adr and nlcg, two load steps): the depth search reads the same summed
# contact force on every rank, so it takes the same offsets and the histories agree too.
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_tools.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

export MPI_RANKS="1 2"
mpi_same_on_ranks sliding tests/cli/decks/tool_sliding_plane.yaml
pass "plane slid with friction (explicit): 1 and 2 ranks give the same history"
mpi_same_on_ranks load_control tests/cli/decks/tool_load_control.yaml
pass "punch under load control (explicit): 1 and 2 ranks give the same history"
for solver in adr nlcg; do
  sed -e "s/type: explicit, end_time: 4.0e-4, damping: 4.0e4,/type: $solver, load_steps: 2,/" \
    tests/cli/decks/tool_load_control.yaml > "$TMP/load_control_$solver.yaml"
  mpi_same_on_ranks "load_control_$solver" "$TMP/load_control_$solver.yaml"
  pass "punch under load control ($solver, 2 load steps): 1 and 2 ranks give the same history"
done
