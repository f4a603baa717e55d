#!/usr/bin/env bash
# The implicit solver on MPI ranks (docs/solvers.md section 9, docs/parallel.md): a distributed
# PETSc matrix in the global (Morton) numbering, the LPS tangent rows of ghosts sent to their
# owners, GAMG or a parallel LU.
#   - the coarse plate with a hole (LPS, plane stress, CG + GAMG) on 1, 2 and 3 ranks;
#   - the 1D bar pulled to failure (PMB, bonds break between load steps) on 1 and 2 ranks,
#     with the same final broken-bond count;
#   - a 2D PMB plate turned by 0.6 rad and stretched by 20% (linear_solver direct: MUMPS or
#     SuperLU_dist on 2 ranks) on 1 and 2 ranks, where Newton stays quadratic on 2 ranks:
#     rho_{k+1} <= 10 rho_k^2 in the asymptotic range, as in tests/verification/test_implicit.c;
#   - a pre-cracked LPS plate torn apart on 2 ranks: byte-identical with 1 and 2 threads;
#   - its first Jacobian on 2 and 3 ranks equals the single-process matrix to 1e-12.
# Why 1e-6 and not the bit-for-bit agreement of the other solvers: GAMG aggregates each rank's
# rows, and PETSc's reductions depend on the split, so the Krylov and Newton iterates differ
# between rank counts in round-off. Each run still stops at a relative residual below the
# solver tolerance (1e-8 for these decks), and the solutions then differ by about the
# condition number times that tolerance in the stiff directions; measured: below the 10
# printed digits (plate with a hole, but for its zero y reactions, 1e-10 N against 50 N),
# 2e-10 of the reactions (cracked LPS plate), 5e-10 (bar). 1e-6 bounds that with room and still
# catches any wrong term, which shows at 1e-3 or more. Values are compared relative to the
# largest magnitude of their kind over the run (the reactions, the displacements, ...): a
# reaction that symmetry makes zero is round-off, ~1e-12 of the others, on any rank count.
# Skipped when peri was built without MPI or PETSc.
# Usage: bash tests/cli/mpi_implicit.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

TOL=1e-6
matrix_report=""

# same_on_ranks NAME RANKS DECK [ARGS...]: runs DECK on each rank count of RANKS (1 first);
# history.csv must agree with the 1-rank run to TOL (compare_scaled) and the broken-bond count
# must be the same, and so must the number of Newton iterations: a tangent term lost between
# ranks leaves the converged history as it is (the residual decides it) but costs Newton
# iterations (the plate: 6 instead of 2 without the rows of ghosts). Sets REF (the 1-rank
# history) and BROKEN (its broken-bond line). After each run, calls the function named by
# AFTER_RUN (if set) with the rank count.
same_on_ranks() {
  local name=$1 ranks=$2 deck=$3
  shift 3
  local np out report newton newton_ref=""
  for np in $ranks; do
    out="$TMP/$name-np$np"
    run_peri_mpi "$np" run "$deck" --output "$out" "$@"
    expect_status 0
    expect_nonempty_file "$out/history.csv"
    expect_stdout_contains "solver       implicit"
    [[ -n "${AFTER_RUN:-}" ]] && "$AFTER_RUN" "$np"
    newton=$(grep -E '^  finished ' "$RUN_STDOUT" | grep -oE '[0-9]+ iterations')
    [[ -n "$newton" ]] || fail "$name on $np ranks: no iteration count in the summary"
    if [[ $np -eq 1 ]]; then
      REF="$out/history.csv"
      BROKEN=$(broken_line)
      newton_ref=$newton
      continue
    fi
    [[ "$newton" == "$newton_ref" ]] || fail "$name: $newton_ref (Newton) on 1 rank, $newton on $np"
    expect_stdout_contains "MPI ranks    $np"
    report=$(compare_scaled "$REF" "$out/history.csv" "$TOL") ||
      fail "$name: history.csv on 1 and $np ranks differ: $report"
    [[ "$(broken_line)" == "$BROKEN" ]] || fail "$name: '$BROKEN' on 1 rank, '$(broken_line)' on $np"
  done
}

run_peri check "$DECKS/qs_bar.yaml" --set solver.type=implicit
if [[ "$RUN_STATUS" == 2 ]] && grep -qF "built without PETSc" "$RUN_STDERR"; then
  echo "SKIP: $CLI_NAME: peri was built without PETSc"
  exit 0
fi

# (1) LPS: the plate with a hole, coarse; the summary's maximum von Mises stress (4 digits)
von_mises_value() { grep -E '^  max von Mises ' "$RUN_STDOUT" | sed -E 's/.*: ([^ ]+) Pa.*/\1/'; }
plate=(--set discretization.horizon=3e-3 --set discretization.spacing=1e-3 --set solver.type=implicit
       --set output.picture=false --set 'output.fields=[von_mises]')
vm_ref=""
same_von_mises() {
  local vm
  vm=$(von_mises_value)
  [[ -n "$vm" ]] || fail "plate on $1 ranks: no 'max von Mises' value in the summary"
  [[ -z "$vm_ref" ]] && vm_ref=$vm
  # printed to 4 digits: values that agree to 1e-6 print alike, or one unit apart at a rounding edge
  awk -v a="$vm" -v b="$vm_ref" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1.5e-4 * b) }' ||
    fail "plate: max von Mises $vm_ref Pa on 1 rank, $vm Pa on $1"
}
AFTER_RUN=same_von_mises same_on_ranks plate "1 2 3" examples/plate_with_hole.yaml "${plate[@]}"
pass "LPS plate with a hole by implicit on 1, 2, 3 ranks: history.csv within $TOL, max von Mises $vm_ref Pa"

# (2) PMB through fracture: the bar of qs_bar.yaml
same_on_ranks bar "1 2" "$DECKS/qs_bar.yaml" --set solver.type=implicit
col=$(csv_column "$REF" broken_bond_fraction)
final=$(tail -n 1 "$REF" | cut -d, -f"$col")
awk -v b="$final" 'BEGIN { exit !(b > 0) }' || fail "bar: no bond broke (the comparison is weak)"
pass "PMB bar pulled to failure by implicit on 1 and 2 ranks: history.csv within $TOL," \
  "$(echo "$BROKEN" | sed 's/^  *//')"

# (3) thread invariance on ranks: the LPS rows (of owned nodes and of ghosts) are computed in
# parallel, each summed in a fixed order and added once, so a pre-cracked LPS plate torn apart
# in load steps (tests/cli/decks/implicit_crack.yaml) gives the same history.csv, byte for byte,
# with 1 and 2 threads per rank
for threads in 1 2; do
  run_peri_mpi 2 run "$DECKS/implicit_crack.yaml" --threads "$threads" --output "$TMP/crack$threads"
  expect_status 0
done
broken=$(broken_line | sed 's/^  *//')
[[ "$broken" =~ ^broken\ bonds\ [1-9] ]] || fail "the cracked plate did not break ($broken)"
cmp -s "$TMP/crack1/history.csv" "$TMP/crack2/history.csv" ||
  fail "2 ranks: history.csv differs between 1 and 2 threads:" \
    "$(diff "$TMP/crack1/history.csv" "$TMP/crack2/history.csv" | head -4)"
pass "cracked LPS plate on 2 ranks: the same history.csv with 1 and 2 threads per rank ($broken)"

# (4) the distributed matrix itself: the first Jacobian of the cracked plate (LPS, at the same
# state on any rank count) printed by PETSc (-ksp_view_mat, 17 digits, global numbering) on 2
# and 3 ranks equals the single-process one to 1e-12 of its largest entry. Only the order of
# the sums differs (measured 2e-14); a term lost or counted twice between ranks shows at 1e-3.
first_matrix_difference() { # FILE_A FILE_B: "entries_a entries_b max|a-b|/max|a|" of the first matrices
  awk '
    FNR == 1 { file++; inside = 0 }
    /^zzz = \[/ { if (!seen[file]++) inside = 1; next }
    /^\];/ { inside = 0; next }
    inside && NF == 3 {
      key = $1 " " $2
      if (file == 1) { a[key] = $3 + 0; v = $3 < 0 ? -$3 : $3; if (v > amax) amax = v; na++ }
      else { b[key] = $3 + 0; nb++ }
    }
    END {
      for (k in a) { d = a[k] - (k in b ? b[k] : 0); if (d < 0) d = -d; if (d > dmax) dmax = d }
      for (k in b) if (!(k in a)) { d = b[k] < 0 ? -b[k] : b[k]; if (d > dmax) dmax = d }
      printf "%d %d %.3g\n", na, nb, (amax > 0 ? dmax / amax : 1)
    }' "$1" "$2"
}
one_step=(--set solver.load_steps=1 --set solver.end_time=0.25 --set solver.breaking=false)
for np in 1 2 3; do
  run_peri_mpi "$np" run "$DECKS/implicit_crack.yaml" "${one_step[@]}" --output "$TMP/matrix$np" \
    --petsc-options "-ksp_view_mat ascii:$TMP/matrix$np.m:ascii_matlab"
  expect_status 0
  expect_nonempty_file "$TMP/matrix$np.m"
  [[ $np -eq 1 ]] && continue
  read -r na nb diff < <(first_matrix_difference "$TMP/matrix1.m" "$TMP/matrix$np.m")
  [[ "$na" -gt 1000 && "$na" == "$nb" ]] || fail "matrix on $np ranks: $nb entries, $na in one process"
  awk -v d="$diff" 'BEGIN { exit !(d <= 1e-12) }' ||
    fail "matrix on $np ranks differs from the single-process one by $diff of its largest entry"
  matrix_report+=" $np ranks: $diff;"
done
pass "the first Jacobian ($na entries) on 2 and 3 ranks equals the single-process one:$matrix_report"

# (5) 2D PMB, large rotation, parallel LU; Newton's relative residuals of the last solve
cat >"$TMP/turn.yaml" <<'DECK'
dimension: 2
plane: stress
materials:
  m: {model: pmb, density: 1000, youngs_modulus: 1e9}
discretization: {spacing: 1e-3, m: 3, fill: [{shape: rectangle, min: [0, 0], max: [0.03, 0.01]}]}
regions:
  held: {shape: rectangle, min: [-1, -1], max: [0.003, 1]}
  turned: {shape: rectangle, min: [0.027, -1], max: [1, 1]}
boundary_conditions:
  - {type: displacement, region: held, x: 0, y: 0}
  - {type: displacement, region: turned,
     x: "cos(0.6*t)*(1 + 0.2*t)*x - sin(0.6*t)*(y - 0.005) - x",
     y: "sin(0.6*t)*(1 + 0.2*t)*x + cos(0.6*t)*(y - 0.005) + 0.005 - y"}
solver: {type: implicit, load_steps: 2, linear_solver: direct, tolerance: 1e-12, breaking: false}
output: {picture: false}
DECK
export PERI_QS_DEBUG=1 # rank 0 prints "implicit K: relative residual R ..." per Newton iteration
same_on_ranks turn "1 2" "$TMP/turn.yaml"
unset PERI_QS_DEBUG
read -r pairs worst < <(awk '
  /^implicit [0-9]+: relative residual/ { k = $2 + 0; if (k == 0) n = 0; rho[n++] = $5 + 0 }
  END {
    p = 0; w = 0
    for (i = 0; i + 1 < n; i++)
      if (rho[i] < 0.1 && rho[i + 1] > 1e-13) { p++; r = rho[i + 1] / (rho[i] * rho[i]); if (r > w) w = r }
    print p, w
  }' "$RUN_STDERR")
[[ "${pairs:-0}" -ge 2 ]] || fail "turned plate on 2 ranks: ${pairs:-0} Newton iterations in the asymptotic range"
awk -v w="$worst" 'BEGIN { exit !(w < 10) }' ||
  fail "turned plate on 2 ranks: rho_{k+1} / rho_k^2 reached $worst: Newton is not quadratic"
pass "2D PMB plate turned by 0.6 rad with a parallel LU on 1 and 2 ranks: history.csv within $TOL;" \
  "Newton quadratic on 2 ranks ($pairs asymptotic steps, max rho_{k+1}/rho_k^2 = $worst)"
echo "PASS: $CLI_NAME"
