#!/usr/bin/env bash
# The PD-FEM coupling on MPI ranks (docs/coupling.md, "On MPI ranks"): each rank assembles the
# rows of its owned nodes (the bonds of its PD nodes, the elements that contain its FEM nodes,
# whose corners come as ghosts) into the distributed PETSc matrix.
#   - the point-supported plate of Table 2.1 (load-controlled, MUMPS) on 1, 2 and 3 ranks: the
#     reactions, net_force_y and the e_r columns equal to 1e-8 (relative), and on 2 ranks the
#     support reactions sum to Table 2.1's 10.1425 within 1%, as on 1 rank (tests/cli/coupling.sh);
#     the same with GMRES + GAMG on 2 ranks against MUMPS on 1 (at tolerance 1e-12);
#   - that plate all FEM and all PD (bond-based and LPS) on 2 ranks: models in balance, so the
#     support reactions sum to the load 10 (1e-9 relative); the LPS coupled plate on 1 and 2
#     ranks (its kept rows reach 2 horizons) to 1e-8;
#   - imposed fields, where nothing is solved and every row sums as in one process: the 1D
#     cubic curve (Tables 2.11, 2.12) and Case II of §2.6.2 (exact partial volumes, Table 2.16
#     e_ry = 5.00e-4) on 1, 2 and 3 ranks, history.csv equal to 1e-12;
#   - the Gmsh plate (elements larger than a horizon, nodes off the PD grid) in uniform tension
#     on 2 ranks: the right edge's reaction E eps H h = 120 N to 1e-9; its explicit dynamics
#     on 1, 2, 3 ranks: history.csv equal to 1e-12;
#   - crack growth with switching (the coarse three-point bending beam) on 1 and 2 ranks: the
#     same node types and damage at every node, the same broken bonds, history.csv to 1e-8;
#   - a crack that reaches the coarse part of a graded mesh stops the run on 2 ranks (exit 1) with
#     the message of 1 rank, naming the same node;
#   - explicit coupled dynamics (the pulse through FEM | PD | FEM, the bar pulled apart with
#     switching) on 1, 2, 3 ranks: history.csv equal to 1e-12; the first break at t* = 176.34 s.
# The out_of_balance_x of the plate is a ratio of two round-off sums (the x forces of a plate
# loaded in y): it is compared through its numerator, net_force_x, at round-off of the reactions.
# Skipped when peri was built without MPI or PETSc.
# Usage: bash tests/cli/mpi_coupling.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

plate=examples/coupling_plate_point_load.yaml
run_peri check "$plate"
if [[ "$RUN_STATUS" == 2 ]] && grep -qF "built without PETSc" "$RUN_STDERR"; then
  echo "SKIP: $CLI_NAME: peri was built without PETSc"
  exit 0
fi
expect_status 0

# value FILE COLUMN: the last row's value of COLUMN
value() {
  local col
  col=$(csv_column "$1" "$2")
  [[ -n "$col" ]] || fail "$1 has no column $2"
  tail -n 1 "$1" | cut -d, -f"$col"
}
# near GOT WANT RELTOL: |GOT - WANT| <= RELTOL |WANT|
near() { awk -v g="$1" -v w="$2" -v t="$3" 'BEGIN { d = g - w; if (d < 0) d = -d; exit !(d <= t * (w < 0 ? -w : w)) }'; }
support_sum() { awk -v a="$(value "$1" reaction_left_y)" -v b="$(value "$1" reaction_right_y)" 'BEGIN { printf "%.12g", a + b }'; }

# same_values REF OUT NAME: the support sum and the coupling columns of OUT equal REF's to 1e-8;
# net_force_x at round-off of the reactions (1e-12 of the load 10)
same_values() {
  local col a b
  a=$(support_sum "$1") b=$(support_sum "$2")
  near "$b" "$a" 1e-8 || fail "$3: support reactions sum to $a on 1 rank, $b here"
  for col in net_force_y out_of_balance_y out_of_balance; do
    a=$(value "$1" $col) b=$(value "$2" $col)
    near "$b" "$a" 1e-8 || fail "$3: $col $a on 1 rank, $b here"
  done
  b=$(value "$2" net_force_x)
  awk -v x="$b" 'BEGIN { exit !(x < 1e-11 && x > -1e-11) }' || fail "$3: net_force_x $b, not at round-off"
}

# (1) Table 2.1, load-controlled, MUMPS (linear_solver direct)
for np in 1 2 3; do
  run_peri_mpi "$np" run "$plate" --output "$TMP/plate-np$np" --set output.picture=false
  expect_status 0
  hist="$TMP/plate-np$np/history.csv"
  expect_nonempty_file "$hist"
  [[ $np -eq 1 ]] && continue
  expect_stdout_contains "MPI ranks    $np"
  same_values "$TMP/plate-np1/history.csv" "$hist" "plate on $np ranks"
  sum=$(support_sum "$hist")
  near "$sum" 10.1425 0.01 || fail "plate on $np ranks: support reactions sum to $sum, Table 2.1 10.1425 within 1%"
done
pass "Table 2.1 plate on 1, 2, 3 ranks (MUMPS): reactions and e_r equal to 1e-8; on 2 and 3 ranks the" \
  "supports carry $sum (Table 2.1: 10.1425, within 1%), e_ry $(value "$hist" out_of_balance_y)"

run_peri_mpi 2 run "$plate" --output "$TMP/gmres-np2" --set output.picture=false --set solver.linear_solver=gmres \
  --set solver.petsc_preconditioner=gamg --set solver.tolerance=1e-12
expect_status 0
same_values "$TMP/plate-np1/history.csv" "$TMP/gmres-np2/history.csv" "plate by GMRES on 2 ranks"
pass "Table 2.1 plate by GMRES + GAMG on 2 ranks: the values of MUMPS on 1 rank to 1e-8 ($(support_sum "$TMP/gmres-np2/history.csv"))"

# (2) models in balance: every reaction sums to the load; LPS rows on ranks
lps=(--set materials.plate.model=lps --set materials.plate.poisson_ratio=0.3)
for variant in "fem:--set coupling.pd_region=nowhere" "pd:--set coupling.pd_region=all" \
  "lps_pd:--set coupling.pd_region=all ${lps[*]}"; do
  name=${variant%%:*}
  read -r -a args <<<"${variant#*:}"
  run_peri_mpi 2 run "$plate" --output "$TMP/$name" --set output.picture=false "${args[@]}"
  expect_status 0
  sum=$(support_sum "$TMP/$name/history.csv")
  near "$sum" 10 1e-9 || fail "$name plate on 2 ranks: the supports carry $sum, not the load 10"
done
for np in 1 2; do
  run_peri_mpi "$np" run "$plate" --output "$TMP/lps-np$np" --set output.picture=false "${lps[@]}"
  expect_status 0
done
same_values "$TMP/lps-np1/history.csv" "$TMP/lps-np2/history.csv" "LPS coupled plate on 2 ranks"
pass "all-FEM, all-PD and all-PD LPS plates on 2 ranks carry the load 10 (1e-9); the LPS coupled plate" \
  "on 1 and 2 ranks agrees to 1e-8 ($(support_sum "$TMP/lps-np2/history.csv"))"

# (3) imposed fields: F = K u row by row, nothing solved
same_history() { # NAME DECK [ARGS...]: 1, 2, 3 ranks, history.csv equal to 1e-12
  local np name=$1 deck=$2
  shift 2
  for np in 1 2 3; do
    run_peri_mpi "$np" run "$deck" --output "$TMP/$name-np$np" --set output.picture=false "$@"
    expect_status 0
    [[ $np -eq 1 ]] && continue
    report=$(compare_histories "$TMP/$name-np1/history.csv" "$TMP/$name-np$np/history.csv" 1e-12) ||
      fail "$name: history.csv on 1 and $np ranks differ: $report"
  done
}
same_history bar examples/coupling_bar_cubic.yaml
net=$(value "$TMP/bar-np2/history.csv" net_force_x) ratio=$(value "$TMP/bar-np2/history.csv" out_of_balance)
near "$net" -2.31e-7 0.0025 || fail "1D bar on 2 ranks: net_force_x $net, Table 2.12 -2.31e-7"
near "$ratio" 5.78e-4 0.001 || fail "1D bar on 2 ranks: out_of_balance $ratio, Table 2.11 5.78e-4"
same_history case2 examples/coupling_plate_case2.yaml
ery=$(value "$TMP/case2-np2/history.csv" out_of_balance_y)
near "$ery" 5.00e-4 0.001 || fail "Case II on 2 ranks: out_of_balance_y $ery, Table 2.16 5.00e-4"
pass "imposed fields on 1, 2, 3 ranks: the same history.csv (1e-12); on 2 ranks the 1D bar's net force $net" \
  "(Table 2.12: -2.31e-7), e_r $ratio (Table 2.11: 5.78e-4), Case II e_ry $ery (Table 2.16: 5.00e-4)"

# (4) the Gmsh plate: elements wider than a horizon, their corners brought as ghosts
gmsh=examples/coupling_gmsh_plate.yaml
run_peri check "$gmsh"
if [[ "$RUN_STATUS" == 2 ]]; then
  echo "skip: $gmsh (no Gmsh reader in this build)"
else
  run_peri_mpi 2 run "$gmsh" --output "$TMP/gmsh" --set output.picture=false
  expect_status 0
  rx=$(value "$TMP/gmsh/history.csv" reaction_right_x)
  near "$rx" 120 1e-9 || fail "Gmsh plate on 2 ranks: reaction $rx, E eps H h = 120"
  pass "Gmsh plate in uniform tension on 2 ranks: reaction $rx N (E eps H h = 120 N, 1e-9)"
  same_history gmsh_dynamics "$gmsh" --set 'solver={type: explicit, end_time: 2}'
  pass "Gmsh plate, explicit dynamics (830 steps): the same history.csv on 1, 2, 3 ranks"
fi

# (5) crack growth with switching: the coarse three-point bending beam of
# tests/verification/test_coupling_3pb.c (dx = 0.25 m, 2,560 nodes, 21 load steps to 8.4 mm,
# scheme 2) on 1 and 2 ranks. The crack grows from the notch and FEM nodes switch to PD as it
# goes; the node types and the damage of every node at the end (the switched nodes and the crack
# path), read from the frames by node_id, must be the same, and so must history.csv (1e-8 of
# the largest value of each kind: the linear solves differ in round-off) and the broken bonds.
coarse_3pb=(--set discretization.spacing=0.25 --set 'regions.left_support.max=[0.25, 0.25]'
  --set 'regions.right_support.min=[19.75, 0]' --set 'regions.right_support.max=[20, 0.25]'
  --set 'regions.load.min=[9.74, 7.75]' --set 'regions.load.max=[10.26, 8.1]' --set solver.load_steps=21
  --set 'boundary_conditions.2.y=-8.4e-3*t' --set output.picture=false --set output.frames=1
  --set 'output.fields=[node_type, damage]' --set output.compress=false)
# node_states DIR: "node_id node_type damage" of every node in the last frame's pieces, by node_id
node_states() {
  python3 - "$1" <<'PY'
import base64, glob, re, struct, sys
frames = sorted(glob.glob(sys.argv[1] + "/*_0000[0-9][0-9]*.vtu"))
last = max(re.search(r"_(\d{6})(_\d+)?\.vtu$", f).group(1) for f in frames)
rows = {}
for f in frames:
    if re.search(r"_(\d{6})(_\d+)?\.vtu$", f).group(1) != last:
        continue
    arrays = {}
    for kind, name, data in re.findall(r'<DataArray type="(\w+)" Name="(\w+)"[^>]*format="binary">\s*(\S+)\s*</DataArray>', open(f).read()):
        raw = base64.b64decode(data)[8:]  # after the UInt64 byte count
        code = {"Int32": "i", "Float64": "d"}.get(kind)
        if code:
            arrays[name] = struct.unpack("<%d%s" % (len(raw) // struct.calcsize(code), code), raw)
    for k, node in enumerate(arrays["node_id"]):
        rows[node] = "%d %d %r" % (node, arrays["node_type"][k], arrays["damage"][k])
print("\n".join(rows[k] for k in sorted(rows)))
PY
}
for np in 1 2; do
  run_peri_mpi "$np" run examples/coupling_three_point_bending.yaml --output "$TMP/3pb-np$np" "${coarse_3pb[@]}"
  expect_status 0
  node_states "$TMP/3pb-np$np" >"$TMP/3pb-np$np.nodes" || fail "3PB on $np ranks: the frames cannot be read"
  [[ $np -eq 1 ]] && broken_ref=$(broken_line)
done
[[ $(wc -l <"$TMP/3pb-np1.nodes") -eq 2560 ]] || fail "3PB: $(wc -l <"$TMP/3pb-np1.nodes") nodes in the frames, not 2560"
cmp -s "$TMP/3pb-np1.nodes" "$TMP/3pb-np2.nodes" ||
  fail "3PB: node types or damage differ on 1 and 2 ranks: $(diff "$TMP/3pb-np1.nodes" "$TMP/3pb-np2.nodes" | head -4)"
[[ "$(broken_line)" == "$broken_ref" ]] || fail "3PB: '$broken_ref' on 1 rank, '$(broken_line)' on 2"
# without out_of_balance_x: once the beam has broken its x forces are the solves' residuals
# (0.07 N, the tolerance 1e-8 times the peak reaction 1.4 MN), whose ratio has no digits to compare
without_column "$TMP/3pb-np1/history.csv" out_of_balance_x >"$TMP/3pb-np1.csv"
without_column "$TMP/3pb-np2/history.csv" out_of_balance_x >"$TMP/3pb-np2.csv"
report=$(compare_scaled "$TMP/3pb-np1.csv" "$TMP/3pb-np2.csv" 1e-8) ||
  fail "3PB: history.csv on 1 and 2 ranks differ: $report"
pd=$(value "$TMP/3pb-np2/history.csv" pd_nodes)
cracked=$(awk '$3 >= 0.3' "$TMP/3pb-np2.nodes" | wc -l)
[[ $pd -gt 200 && $cracked -gt 20 ]] || fail "3PB: $pd PD nodes, $cracked nodes with damage >= 0.3: the crack did not grow"
pass "3PB crack growth with switching on 1 and 2 ranks: the same $pd PD nodes (100 at the start) and damage" \
  "of every node ($cracked nodes with damage >= 0.3), $(echo "$broken_ref" | sed 's/^  *//'), history.csv to 1e-8"

# a crack that reaches the coarse part of a graded mesh (tests/cli/coupling.sh): the run stops
# with exit 1 on 2 ranks too, naming the same node (its global number and position) as on 1
graded_stop=(--set 'coupling.graded_mesh={levels: 3, fine: [{shape: rectangle, min: [6, -1], max: [14, 5]},
  {shape: rectangle, min: [-1, -1], max: [1.5, 1.5]}, {shape: rectangle, min: [18.5, -1], max: [21, 1.5]}]}')
for np in 1 2; do
  run_peri_mpi "$np" run examples/coupling_three_point_bending.yaml --output "$TMP/stop-np$np" "${coarse_3pb[@]}" \
    "${graded_stop[@]}"
  expect_status 1
  expect_stderr_contains "should become a PD node, but its horizon reaches the coarse part of the graded mesh"
  grep -F "should become a PD node" "$RUN_STDERR" >"$TMP/stop-np$np.message"
done
cmp -s "$TMP/stop-np1.message" "$TMP/stop-np2.message" ||
  fail "graded stop: '$(cat "$TMP/stop-np1.message")' on 1 rank, '$(cat "$TMP/stop-np2.message")' on 2"
pass "a crack reaching a graded mesh's coarse part stops the run on 2 ranks with the message of 1 rank"

# (6) explicit coupled dynamics: velocity-Verlet with f = K u of the owned rows, the same sums as
# in one process, so history.csv is the same to 1e-12 (in practice byte for byte) on 1, 2, 3 ranks
same_history wave examples/coupling_bar_wave.yaml
same_history pull examples/coupling_bar_switching.yaml
# the bar pulled apart (docs/coupling.md, "Switching during explicit dynamics"): the two fronts
# meet at x = 150, where the strain 2 (v0/c) tanh^2((t - 150)/tau) reaches s0 = 1.5 v0/c at
# t* = 150 + tau artanh(sqrt(0.75)) = 176.34 s; the rows are 1 s apart
first=$(awk -F, -v c="$(csv_column "$TMP/pull-np2/history.csv" broken_bond_fraction)" \
  'NR > 1 && $c > 0 { print $1; exit }' "$TMP/pull-np2/history.csv")
awk -v t="$first" 'BEGIN { exit !(t != "" && t >= 176.34 && t <= 176.34 + 1.5) }' ||
  fail "bar pulled apart on 2 ranks: first broken bond in the row at t = ${first:-never}, t* = 176.34 s"
pd=$(value "$TMP/pull-np2/history.csv" pd_nodes)
[[ $pd -gt 9 ]] || fail "bar pulled apart on 2 ranks: $pd PD nodes at the end, no switch from the 9 at the start"
pass "explicit coupled dynamics on 1, 2, 3 ranks (the pulse through FEM | PD | FEM, the bar pulled apart):" \
  "the same history.csv; on 2 ranks the first break in the row at t = $first s (t* = 176.34 s), PD nodes 9 -> $pd"
echo "PASS: $CLI_NAME"
