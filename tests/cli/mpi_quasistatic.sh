#!/usr/bin/env bash
# The quasi-static solvers on MPI ranks (docs/parallel.md, docs/solvers.md): every reduction
# (dot products, residual norms, reactions, broken-bond counts) is summed in fixed-order
# blocks of the global node order, so the iterates, and therefore history.csv, are those of
# one process: equal to a relative 1e-12 (in practice byte for byte).
#   - the plate with a hole (LPS, plane stress), coarsened, by nlcg on 1 and 3 ranks and by
#     adr on 1 and 2, with the same maximum von Mises stress and location in the summary;
#   - the 1D bar pulled to failure (bonds break, re-solves at the same load) by nlcg on 1 to 4
#     ranks and by damped dynamic relaxation on 1 and 3;
#   - the notched beam (coarse) through its dynamic phases (solver.dynamic_switch) on 1 and 2.
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_quasistatic.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/beam.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

von_mises_line() { grep -E '^  max von Mises ' "$RUN_STDOUT"; }

plate=(--set discretization.horizon=3e-3 --set discretization.spacing=1e-3 --set output.picture=false)
for solver in nlcg adr; do
  vm_ref=""
  ranks="1 3"
  [[ $solver == adr ]] && ranks="1 2"
  for np in $ranks; do
    run_peri_mpi "$np" run examples/plate_with_hole.yaml "${plate[@]}" --set solver.type=$solver \
      --output "$TMP/plate-$solver-np$np"
    expect_status 0
    expect_nonempty_file "$TMP/plate-$solver-np$np/history.csv"
    vm=$(von_mises_line)
    [[ -n "$vm" ]] || fail "plate $solver on $np ranks: no 'max von Mises' line in the summary"
    if [[ $np -eq 1 ]]; then
      vm_ref=$vm
      continue
    fi
    expect_stdout_contains "MPI ranks    $np"
    diff_report=$(compare_histories "$TMP/plate-$solver-np1/history.csv" "$TMP/plate-$solver-np$np/history.csv" \
      "$MPI_TOL") || fail "plate $solver: history.csv on 1 and $np ranks differ: $diff_report"
    [[ "$vm" == "$vm_ref" ]] || fail "plate $solver: '$vm_ref' on 1 rank, '$vm' on $np"
  done
  pass "plate with a hole by $solver: the same history and$(echo "$vm_ref" | sed 's/^  / /') on ranks $ranks"
done

mpi_same_on_ranks bar_nlcg "$DECKS/qs_bar.yaml"
col=$(csv_column "$MPI_REF" broken_bond_fraction)
final=$(tail -n 1 "$MPI_REF" | cut -d, -f"$col")
awk -v b="$final" 'BEGIN { exit !(b > 0) }' || fail "bar nlcg: no bond broke (the comparison is weak)"
pass "bar pulled to failure by nlcg: the same history on 1, 2, 3, 4 ranks (broken fraction $final)"

MPI_RANKS="1 3" mpi_same_on_ranks bar_dr "$DECKS/qs_bar.yaml" --set solver.type=dynamic_relaxation \
  --set solver.damping=2e5 --set solver.max_iterations=200000
pass "bar by damped dynamic relaxation: the same history on 1 and 3 ranks"

beam=("${BEAM_COARSE[@]}"
  --set solver.load_steps=12 --set "boundary_conditions.2.y=-0.6e-3*t"
  --set solver.dynamic_switch.when_broken_exceeds=40 --set solver.dynamic_switch.history_every=50
  --set output.picture=false)
MPI_RANKS="1 2" mpi_same_on_ranks beam examples/notched_beam_3pb.yaml "${beam[@]}"
expect_stdout_matches "^  dynamic      [0-9]+ phases?, [0-9]+ explicit steps"
pass "notched beam through its dynamic phases: the same history on 1 and 2 ranks"
echo "PASS: $CLI_NAME"
