#!/usr/bin/env bash
# The thread count does not change a quasi-static fracture run: the notched beam in
# three-point bending (examples/notched_beam_3pb.yaml, coarsened to dx = 2.5 mm) solved with
# nlcg and with adr gives a byte-identical history.csv with --threads 1 and --threads 2. The
# run breaks bonds at load steps and passes through dynamic phases (solver.dynamic_switch),
# so the load stepping, the re-solves, the cut-back logic and the explicit phases are all
# covered.
# Usage: bash tests/cli/qs_threads.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/beam.bash"
cli_init "$@"

deck=$BEAM_DECK
coarse=("${BEAM_COARSE[@]}"
  --set solver.load_steps=16 --set "boundary_conditions.2.y=-0.8e-3*t"
  --set "solver.dynamic_switch={when_broken_exceeds: 40, damping: 2.0e4}")

for solver in nlcg adr; do
  for threads in 1 2; do
    out="$TMP/$solver-t$threads"
    run_peri run "$deck" "${coarse[@]}" --set solver.type=$solver --threads "$threads" --output "$out"
    expect_status 0
    expect_stdout_matches "^  finished +16 load steps .*\($threads threads\)$"
    expect_nonempty_file "$out/history.csv"
  done
  ref="$TMP/$solver-t1/history.csv"

  # the fixture must break bonds during the load steps and switch to dynamics, else the
  # comparison is weak
  b=$(csv_column "$ref" broken_bond_fraction)
  ph=$(csv_column "$ref" phase)
  [[ -n "$b" && -n "$ph" ]] || fail "$solver: history.csv lacks broken_bond_fraction or phase: $(head -n 1 "$ref")"
  first=$(sed -n 2p "$ref" | cut -d, -f"$b")
  final=$(tail -n 1 "$ref" | cut -d, -f"$b")
  awk -v a="$first" -v b="$final" 'BEGIN { exit !(b > a) }' ||
    fail "$solver: no bond broke during the run (broken_bond_fraction $first -> $final)"
  dynamic_rows=$(awk -F, -v c="$ph" 'NR > 1 && $c == 1' "$ref" | wc -l)
  [[ $dynamic_rows -ge 1 ]] || fail "$solver: no dynamic phase (no row with phase 1)"

  cmp -s "$ref" "$TMP/$solver-t2/history.csv" ||
    fail "$solver: history.csv differs between --threads 1 and --threads 2: $(diff "$ref" "$TMP/$solver-t2/history.csv" | head -n 4)"
  pass "$solver: --threads 1 and 2 give byte-identical histories ($(($(wc -l <"$ref") - 1)) rows, $dynamic_rows in dynamic phases); broken bonds $first -> $final"
done

echo "PASS: $CLI_NAME"
