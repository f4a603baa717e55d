#!/usr/bin/env bash
# The implicit solver from the command line (docs/solvers.md, docs/deck.md §14):
#  - bad implicit keys exit 2 before any work, naming file:line:col and what is wrong;
#  - a bar pulled to failure runs with type implicit, and its peak force is E A s0 (2 MN)
#    within 2%, as with nlcg (tests/cli/quasistatic.sh);
#  - --petsc-options reaches PETSc (-snes_monitor prints the Newton residuals) and an option
#    PETSc did not use is reported;
#  - a pre-cracked LPS plate torn apart in load steps gives a byte-identical history.csv
#    with 1 and 2 threads (the tangent rows are computed in parallel).
# In a build without PETSc, type implicit itself is the positioned error.
# Usage: bash tests/cli/implicit.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# deck SOLVER_LINE: the bar of tests/cli/decks/qs_bar.yaml with the given solver mapping.
deck() {
  local path
  path=$(mktemp "$TMP/deck.XXXXXX") && mv "$path" "$path.yaml" && path="$path.yaml"
  sed "s|^solver: .*|solver: $1|" "$DECKS/qs_bar.yaml" >"$path"
  echo "$path"
}

# fails_at DECK PATTERN MESSAGE: `peri check` exits 2, prints nothing on stdout and names
# DECK at the position of PATTERN with MESSAGE.
fails_at() {
  run_peri check "$1"
  expect_status 2
  expect_stdout_empty
  locate "$2" "$1"
  expect_stderr_contains "$1:$LOC_LINE:$LOC_COL: error: $3"
}

valid=$(deck "{type: implicit, load_steps: 40}")
run_peri check "$valid"
if [[ "$RUN_STATUS" == 2 ]] && grep -qF "built without PETSc" "$RUN_STDERR"; then
  fails_at "$valid" "implicit" "solver type 'implicit': this peri was built without PETSc"
  pass "without PETSc: type implicit is a positioned input error"
  d=$(deck "{type: nlcg, linear_solver: cg}")
  fails_at "$d" "linear_solver" "key 'linear_solver': only for solver type implicit"
  pass "implicit keys are rejected for other solvers"
  exit 0
fi
expect_status 0
expect_stdout_contains "solver       implicit (quasi-static)"

# (a) a misspelt choice, with a suggestion
d=$(deck "{type: implicit, linear_solver: cgg}")
fails_at "$d" "cgg" "key 'linear_solver': unknown value 'cgg'; did you mean 'cg'?"
pass "misspelt linear_solver"

# (b) implicit keys under another solver type
d=$(deck "{type: nlcg, linear_solver: gmres}")
fails_at "$d" "linear_solver" "key 'linear_solver': only for solver type implicit"
d=$(deck "{type: explicit, steps: 10, petsc_options: \"-ksp_rtol 1e-9\"}")
fails_at "$d" "petsc_options" "key 'petsc_options': only for solver type implicit"
pass "implicit keys rejected for nlcg and explicit"

# (c) a preconditioner with the direct solver
d=$(deck "{type: implicit, linear_solver: direct, petsc_preconditioner: gamg}")
fails_at "$d" "gamg" "key 'petsc_preconditioner': linear_solver direct is an LU factorization"
pass "preconditioner with linear_solver direct"

# (d) both tolerances, and one out of range
d=$(deck "{type: implicit, tolerance: 1e-8, newton_tolerance: 1e-10}")
fails_at "$d" "newton_tolerance" "key 'newton_tolerance': give either 'tolerance' or 'newton_tolerance'"
d=$(deck "{type: implicit, newton_tolerance: 2}")
fails_at "$d" "2}" "key 'newton_tolerance': must be in (0, 1)"
pass "newton_tolerance"

# (e) PETSc options that are not options
d=$(deck "{type: implicit, petsc_options: \"ksp_rtol 1e-10\"}")
fails_at "$d" "\"ksp_rtol" "key 'petsc_options': expected PETSc options"
pass "petsc_options must start with an option"

# the bar to failure: peak reaction E A s0 = 2 MN within 2%, then zero
run_peri run "$valid" --quiet --output "$TMP/bar"
expect_status 0
expect_file "$TMP/bar/history.csv"
col=$(csv_column "$TMP/bar/history.csv" reaction_pulled_x)
[[ -n "$col" ]] || fail "history.csv has no reaction_pulled_x column"
read -r peak last < <(awk -F, -v c="$col" 'NR > 1 { v = $c + 0; if (v > m) m = v; l = v } END { print m, l }' \
  "$TMP/bar/history.csv")
awk -v p="$peak" -v l="$last" 'BEGIN { exit !(p > 0.98 * 2e6 && p < 1.02 * 2e6 && l * l < 1) }' ||
  fail "implicit bar: peak reaction $peak N (expected 2e6 within 2%), final $last N (expected 0)"
pass "bar to failure with implicit: peak $peak N, final $last N"

# --petsc-options reaches PETSc; an unused option is reported
run_peri run "$valid" --quiet --output "$TMP/mon" --set solver.load_steps=2 \
  --petsc-options "-snes_monitor -snes_monitr"
expect_status 0
expect_stdout_contains "SNES Function norm"
expect_stderr_contains "PETSc option -snes_monitr was not used"
pass "--petsc-options: monitor printed, unused option reported"

# thread invariance through fracture
for threads in 1 2; do
  run_peri run "$DECKS/implicit_crack.yaml" --quiet --threads "$threads" --output "$TMP/crack$threads"
  expect_status 0
done
cmp -s "$TMP/crack1/history.csv" "$TMP/crack2/history.csv" ||
  fail "history.csv differs between 1 and 2 threads: $(diff "$TMP/crack1/history.csv" "$TMP/crack2/history.csv" | head -4)"
broken=$(awk -F, 'NR == 1 { for (k = 1; k <= NF; ++k) if ($k == "broken_bond_fraction") c = k } END { print $c }' \
  "$TMP/crack2/history.csv")
awk -v b="$broken" 'BEGIN { exit !(b > 0.2) }' || fail "the plate did not crack (broken fraction $broken)"
pass "fracture with implicit: the same history.csv with 1 and 2 threads (broken fraction $broken)"
