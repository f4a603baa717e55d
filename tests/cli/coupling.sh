#!/usr/bin/env bash
# The PD-FEM coupling from the command line (docs/coupling.md):
#  - the 1D example imposes the cubic curve of Table 2.9 across the right interface: its
#    history.csv has net_force_x = -2.31e-7 (Table 2.12) and out_of_balance = 5.78e-4 (Table
#    2.11) to the printed 3 digits, and the frames carry the node_type field;
#  - the point-supported plate (Table 2.1): the support reactions sum to 10.1425 within 1%;
#  - bad input exits 2 before any work, naming the deck position and what is wrong: an
#    unknown pd_region, an FEM node that belongs to no element, linear_solver cg, a solver
#    other than implicit or explicit, breaking in explicit dynamics with a state-based PD side, a bond-based key
#    with a state-based material, bonds that may break,
#    a node off the lattice of the elements; a graded mesh (coupling.graded_mesh) whose coarse
#    part lies within a horizon of a PD node (naming the node), with an FEM node in no element,
#    whose fine zone holds no cell, or in 1D;
#  - a crack run on a graded mesh whose fine zone stops below the crack's path: the switching
#    reaches the coarse part, the run stops with exit 1 naming the node, and keeps the
#    history.csv of the load steps before.
# In a build without PETSc the coupling needs the implicit solver, itself a positioned error.
# Usage: bash tests/cli/coupling.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

bar=examples/coupling_bar_cubic.yaml
run_peri check "$bar"
if [[ "$RUN_STATUS" == 2 ]] && grep -qF "built without PETSc" "$RUN_STDERR"; then
  pass "without PETSc: the coupling decks are rejected at solver type implicit"
  exit 0
fi
expect_status 0

# value FILE COLUMN: the last row's value of COLUMN in a CSV file
value() {
  local col
  col=$(csv_column "$1" "$2")
  [[ -n "$col" ]] || fail "$1 has no column $2"
  tail -n 1 "$1" | cut -d, -f"$col"
}

# near GOT WANT TOL: |GOT - WANT| <= TOL
near() { awk -v g="$1" -v w="$2" -v t="$3" 'BEGIN { d = g - w; if (d < 0) d = -d; exit !(d <= t) }'; }

run_peri_in "$TMP" run "$(pwd)/$bar" -q
expect_status 0
hist="$TMP/output/coupling_bar_cubic/history.csv"
expect_nonempty_file "$hist"
net=$(value "$hist" net_force_x)
ratio=$(value "$hist" out_of_balance)
near "$net" -2.31e-7 0.005e-7 || fail "net_force_x $net, Table 2.12 -2.31e-7"
near "$ratio" 5.78e-4 0.005e-4 || fail "out_of_balance $ratio, Table 2.11 5.78e-4"
grep -q 'Name="node_type"' "$TMP/output/coupling_bar_cubic/coupling_bar_cubic_000001.vtu" ||
  fail "the frame has no node_type field"
pass "1D cubic curve over the interface: net force $net, e_r $ratio (Tables 2.11, 2.12)"
# coupling.tractions: the nonlocal plus the local traction at the right interface balances the
# reactions (eq. 2.108, Table 2.12's 2.31e-7); at the left interface the field is linear: they cancel
right=$(awk -v a="$(value "$hist" nonlocal_traction_right_x)" -v b="$(value "$hist" local_traction_right_x)" 'BEGIN { printf "%.10g", a + b }')
left=$(awk -v a="$(value "$hist" nonlocal_traction_left_x)" -v b="$(value "$hist" local_traction_left_x)" 'BEGIN { printf "%.10g", a + b }')
# (history.csv prints 10 digits: each traction, 1.5e-4, to half a unit of 1e-13)
near "$right" "$(awk -v n="$net" 'BEGIN { printf "%.12g", -n }')" 1.1e-13 || fail "tau + t at the right interface $right, -net force ${net#-}"
near "$right" 2.31e-7 0.005e-7 || fail "tau + t at the right interface $right, Table 2.12 2.31e-7"
near "$left" 0 1e-15 || fail "tau + t at the left interface $left, 0 for a linear field"
pass "interface tractions: tau + t = $right at the right interface (Table 2.12 2.31e-7), $left at the left"

plate=examples/coupling_plate_point_load.yaml
run_peri_in "$TMP" run "$(pwd)/$plate" -q
expect_status 0
hist="$TMP/output/coupling_plate_point_load/history.csv"
sum=$(awk -v a="$(value "$hist" reaction_left_y)" -v b="$(value "$hist" reaction_right_y)" 'BEGIN { printf "%.9g", a + b }')
near "$sum" 10.1425 0.101425 || fail "sum of the support reactions $sum, Table 2.1 10.1425 within 1%"
expect_nonempty_file "$TMP/output/coupling_plate_point_load/node_type.png"
pass "point-supported plate: reactions sum to $sum (Table 2.1: 10.1425)"

# deck NAME SED...: a copy of the plate with sed edits
deck() {
  local path="$TMP/$1.yaml"
  shift
  sed "$@" "$plate" >"$path"
  echo "$path"
}

# fails_at DECK PATTERN MESSAGE: `peri check` exits 2, prints nothing on stdout and names DECK
# at the position of PATTERN with MESSAGE.
fails_at() {
  run_peri check "$1"
  expect_status 2
  expect_stdout_empty
  locate "$2" "$1"
  expect_stderr_contains "$1:$LOC_LINE:$LOC_COL: error: $3"
}

d=$(deck typo -e 's/pd_region: pd}/pd_region: pdd}/')
fails_at "$d" "pdd" "unknown region 'pdd'; did you mean 'pd'?"
pass "an unknown pd_region is a positioned error"

d=$(deck lonely -e 's/fill: \[{shape: rectangle, min: \[-12.5, -17.5\], max: \[12.5, 17.5\]}\]/fill: [{shape: rectangle, min: [-12.5, -17.5], max: [12.5, 17.5]}, {shape: rectangle, min: [13.5, 20.5], max: [14.5, 21.5]}]/')
fails_at "$d" "{pd_region" "coupling: FEM node"
expect_stderr_contains "belongs to no element"
pass "an FEM node outside every element is a positioned error"

d=$(deck cg -e 's/solver: {type: implicit, load_steps: 1}/solver: {type: implicit, load_steps: 1, linear_solver: cg}/')
fails_at "$d" "cg}" "key 'linear_solver': the coupled stiffness is not symmetric"
pass "CG is refused for the non-symmetric coupled stiffness"

d=$(deck explicit -e 's/solver: {type: implicit, load_steps: 1}/solver: {type: nlcg, load_steps: 1}/')
fails_at "$d" "{type: nlcg" "coupling: needs solver type implicit"
pass "a solver other than implicit is a positioned error"

d=$(deck explicit_lps_breaking -e 's/model: pmb, density: 1,/model: lps, poisson_ratio: 0.3, density: 1,/' \
      -e 's/solver: {type: implicit, load_steps: 1}/solver: {type: explicit, steps: 10, breaking: true}/')
fails_at "$d" "true}" "key 'breaking': crack growth with switching needs the bond-based PD side"
pass "crack growth in the coupled explicit dynamics with a state-based PD side is a positioned error"

d=$(deck lps -e 's/model: pmb, density: 1,/model: lps, poisson_ratio: 0.3, density: 1,/' -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, gamma: 0.98}/')
fails_at "$d" "gamma" "key 'gamma': only for the bond-based PD side"
pass "gamma with a state-based material is a positioned error"

d=$(deck radius -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, switch_radius: 1}/')
fails_at "$d" "switch_radius" "key 'switch_radius': only with solver.breaking: true"
pass "switch_radius without breaking is a positioned error"

d=$(deck negative -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, switch_radius: -1}/' \
      -e 's/solver: {type: implicit, load_steps: 1}/solver: {type: implicit, load_steps: 1, breaking: true}/')
fails_at "$d" "switch_radius" "key 'switch_radius': expected a number of horizons >= 0, got -1"
pass "a negative switch_radius is a positioned error"

d=$(deck lps_breaking -e 's/model: pmb, density: 1,/model: lps, poisson_ratio: 0.3, density: 1,/' \
      -e 's/solver: {type: implicit, load_steps: 1}/solver: {type: implicit, load_steps: 1, breaking: true}/')
fails_at "$d" "true}" "key 'breaking': crack growth with switching needs the bond-based PD side"
pass "crack growth with a state-based PD side is a positioned error"

d=$(deck exact_breaking -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, partial_volume: exact}/' \
      -e 's/solver: {type: implicit, load_steps: 1}/solver: {type: implicit, load_steps: 1, breaking: true}/')
fails_at "$d" "exact}" "key 'partial_volume': exact families are not bonds and cannot break"
pass "crack growth with exact partial volumes is a positioned error"

# a node off the lattice of the elements (a node file whose 9th node is 0.3 dx off)
for x in 0 1 2 3 4 5 6 7 8.3 9 10 11 12; do echo "$x 1 1"; done >"$TMP/off.txt"
cat >"$TMP/off.yaml" <<'DECK'
dimension: 1
materials: {bar: {model: pmb, density: 1, youngs_modulus: 1}}
discretization: {spacing: 1, m: 3, node_file: off.txt}
regions: {pd: {shape: interval, min: [3.5], max: [6.5]}}
coupling: {pd_region: pd}
solver: {type: implicit, load_steps: 1}
DECK
fails_at "$TMP/off.yaml" "{pd_region" "coupling: node 8 at (8.3, 0, 0) is not on the lattice of spacing 1"
pass "a node off the lattice of the elements is a positioned error"

d=$(deck graded_tight -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, graded_mesh: {fine: {shape: rectangle, min: [-6, -6], max: [6, 6]}}}/')
fails_at "$d" "{pd_region" "coupling: PD node"
expect_stderr_contains "lies within a horizon of the graded mesh's coarse part"
pass "a PD node next to the coarse part of a graded mesh is a positioned error naming the node"

d=$(deck graded_empty -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, graded_mesh: {fine: {shape: rectangle, min: [40, 40], max: [50, 50]}}}/')
fails_at "$d" "graded_mesh" "coupling.graded_mesh: the fine zone holds no lattice cell"
pass "a graded mesh whose fine zone holds no cell is a positioned error"

d=$(deck graded_lonely -e 's/fill: \[{shape: rectangle, min: \[-12.5, -17.5\], max: \[12.5, 17.5\]}\]/fill: [{shape: rectangle, min: [-12.5, -17.5], max: [12.5, 17.5]}, {shape: rectangle, min: [13.5, 20.5], max: [14.5, 21.5]}]/' \
      -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, graded_mesh: {fine: {shape: rectangle, min: [-12.5, -17.5], max: [12.5, 17.5]}}}/')
fails_at "$d" "{pd_region" "coupling: FEM node"
expect_stderr_contains "belongs to no element of the graded mesh"
pass "an FEM node outside every element of a graded mesh is a positioned error"

sed -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, graded_mesh: {fine: {shape: interval, min: [0], max: [5]}}}/' \
  "$TMP/off.yaml" >"$TMP/graded_1d.yaml"
fails_at "$TMP/graded_1d.yaml" "graded_mesh" "key 'graded_mesh': 2D only"
pass "a graded mesh in 1D is a positioned error"

beam=examples/coupling_three_point_bending.yaml
run_peri_in "$TMP" run "$(pwd)/$beam" -q --set discretization.spacing=0.25 \
  --set "regions.left_support.max=[0.25, 0.25]" --set "regions.right_support.min=[19.75, 0]" \
  --set "regions.right_support.max=[20, 0.25]" --set "regions.load.min=[9.74, 7.75]" \
  --set "regions.load.max=[10.26, 8.1]" --set solver.load_steps=21 --set "boundary_conditions.2.y=-8.4e-3*t" \
  --set output.frames=2 --set output.picture=false \
  --set "coupling.graded_mesh={levels: 3, fine: [{shape: rectangle, min: [6, -1], max: [14, 5]},
    {shape: rectangle, min: [-1, -1], max: [1.5, 1.5]}, {shape: rectangle, min: [18.5, -1], max: [21, 1.5]}]}"
expect_status 1
expect_stderr_contains "should become a PD node, but its horizon reaches the coarse part of the graded mesh"
hist="$TMP/output/coupling_three_point_bending/history.csv"
expect_nonempty_file "$hist"
(( $(wc -l <"$hist") > 3 )) || fail "the run that stopped kept no load step in $hist"
pass "a crack that reaches the coarse part of a graded mesh stops the run, naming the node, and keeps its output"

# coupling.balance_regions (e_r of eqs. 2.114, 2.116 over chosen reactions): the column, its value
# from the history's reactions, and its input errors
d=$(deck balance -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, balance_regions: [left, right, middle]}/')
run_peri_in "$TMP" run "$d" -q --output "$TMP/balance"
expect_status 0
hist="$TMP/balance/history.csv"
got=$(value "$hist" out_of_balance_reactions_y)
want=$(awk -v a="$(value "$hist" reaction_left_y)" -v b="$(value "$hist" reaction_right_y)" \
  -v c="$(value "$hist" reaction_middle_y)" 'BEGIN { s = a + b + c; m = (a < 0 ? -a : a) + (b < 0 ? -b : b) + (c < 0 ? -c : c);
  printf "%.12g", (s < 0 ? -s : s) / m }')
near "$got" "$want" 1e-9 || fail "out_of_balance_reactions_y $got, from the reactions $want"
pass "out_of_balance_reactions_y is |sum| / sum of |.| of the listed regions' reactions ($got)"
d=$(deck balance_one -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, balance_regions: [left]}/')
fails_at "$d" "[left]" "key 'balance_regions': expected a list of at least two region names"
d=$(deck balance_unknown -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, balance_regions: [left, rigth]}/')
fails_at "$d" "rigth]" "unknown region 'rigth'; did you mean 'right'?"
d=$(deck balance_all -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, balance_regions: [left, all]}/')
fails_at "$d" "all]" "key 'balance_regions': region 'all' sums every nodal force"
d=$(deck balance_twice -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, balance_regions: [left, left]}/')
fails_at "$d" "left]}" "key 'balance_regions': region 'left' is listed twice"
pass "balance_regions: one region, an unknown one, all and a repeated one are positioned errors"
d=$(deck traction_off -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, tractions: {top: {at: [0, 5.2], normal: +y}}}/')
fails_at "$d" "[0, 5.2]" "coupling.tractions.top: no node at (0, 4.7): 'at' must lie on a line of nodes, half a spacing"
d=$(deck traction_axis -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, tractions: {top: {at: [0, 5.5], normal: +z}}}/')
fails_at "$d" "+z}" "key 'normal': +z is not an axis of a 2D deck"
d=$(deck traction_key -e 's/coupling: {pd_region: pd}/coupling: {pd_region: pd, tractions: {top: {at: [0, 5.5], normal: +y, side: 1}}}/')
fails_at "$d" "side" "unknown key 'side'"
pass "tractions: a point off the midway of two nodes, a normal off the deck's axes and an unknown key are positioned errors"

# the Brokenshire deck's inclined notch: a rectangle needs perpendicular, non-zero edges
torsion=examples/coupling_brokenshire_torsion.yaml
sed 's/edge2: \[0, 0, 0.03\]/edge2: [0, 0.01, 0.03]/' "$torsion" >"$TMP/skew.yaml"
fails_at "$TMP/skew.yaml" "{corner" "precracks: edge1 and edge2 must be perpendicular"
sed 's/edge2: \[0, 0, 0.03\]/edge2: [0, 0, 0]/' "$torsion" >"$TMP/flat.yaml"
fails_at "$TMP/flat.yaml" "{corner" "precracks: edge2 has zero length"
pass "a pre-crack with skew or zero edges is a positioned error"
