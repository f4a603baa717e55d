#!/usr/bin/env bash
# The FEM part of a PD-FEM coupling on a Gmsh mesh (coupling.mesh; docs/coupling.md "Gmsh meshes"):
#  - examples/coupling_gmsh_plate.yaml (a 16 x 12 plate, a structured grid of quadrangles on the
#    PD grid around a PD block, Gmsh's unstructured quadrangles off the grid outside) in uniform
#    tension u_x(16) = 0.016: the model's nodes are exactly the mesh's (the grid's nodes that the
#    mesh covers are left out), every node has the analytic displacement u = (1e-3 x, -1e-3 y / 3)
#    (plane stress, nu = 1/3) to 1e-9 of the largest, and the right edge's reaction is
#    E eps H h = 120 N to 1e-9 (the linear patch test);
#  - the linear field u = a + Hx imposed on every node: out_of_balance (e_r) below 1e-13; a
#    quadratic one above 1e-6 (the check can fail); the same with 2-node bars (1D) and 8-node
#    hexahedra (3D) that the Gmsh library meshes from a .geo;
#  - a geometry that crashes Gmsh 4.8 while meshing, and one Gmsh cannot parse: exit 2 naming
#    the file (the geometry is meshed in a child process);
#  - bad meshes exit 2 before any work, naming the file and the entity: a missing file, a file
#    Gmsh cannot parse, an element naming a node the file does not define, an inverted element
#    (clockwise corners: det J < 0), a degenerate one (collinear corners), an element type peri
#    has no element for (a 6-node triangle), a node in no element, a PD zone whose horizon
#    reaches the mesh's nodes off the PD grid (naming the PD node and the mesh's element or
#    node), a mesh made for another spacing, a grid node outside the mesh that is not PD.
# Usage: bash tests/cli/coupling_gmsh.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

plate=examples/coupling_gmsh_plate.yaml
run_peri check "$plate"
if [[ "$RUN_STATUS" == 2 ]] && grep -qE "built without PETSc|built without the Gmsh library|reads no Gmsh" "$RUN_STDERR"; then
  pass "without PETSc or Gmsh: the deck is rejected before any work"
  exit 0
fi
expect_status 0

PY=""
for candidate in /usr/bin/python3 python3; do
  if command -v "$candidate" >/dev/null && "$candidate" -c 'import numpy' 2>/dev/null; then
    PY=$candidate
    break
  fi
done

# value FILE COLUMN: the last row's value of COLUMN in a CSV file
value() {
  local col
  col=$(csv_column "$1" "$2")
  [[ -n "$col" ]] || fail "$1 has no column $2"
  tail -n 1 "$1" | cut -d, -f"$col"
}
# near GOT WANT TOL: |GOT - WANT| <= TOL
near() { awk -v g="$1" -v w="$2" -v t="$3" 'BEGIN { d = g - w; if (d < 0) d = -d; exit !(d <= t) }'; }

cp examples/coupling_gmsh_plate.yaml examples/coupling_gmsh_plate.msh "$TMP/"
sed -i 's/fields: \[displacement, force, node_type\]/fields: [displacement, node_type]/' \
  "$TMP/coupling_gmsh_plate.yaml"
run_peri_in "$TMP" run coupling_gmsh_plate.yaml -q
expect_status 0
out="$TMP/output/coupling_gmsh_plate"
hist="$out/history.csv"
reaction=$(value "$hist" reaction_right_x)
near "$reaction" 120 1.2e-7 || fail "reaction of the right edge $reaction, E eps H h = 120"
pd=$(value "$hist" pd_nodes)
[[ "$pd" == 35 ]] || fail "$pd PD nodes, the block [6.5, 9.5] x [5, 7] holds 7 x 5"
# the mesh's node count: the second number after \$Nodes (Gmsh 4.1)
mesh_nodes=$(awk '/^\$Nodes/ { getline; print $2; exit }' examples/coupling_gmsh_plate.msh)
if [[ -n "$PY" ]]; then
  "$PY" - "$CLI_DIR/lib" "$out" "$mesh_nodes" <<'PYEOF' || fail "the displacement is not the uniform strain"
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
from check_outputs import read_frame, read_pvd
frames = read_pvd(sys.argv[2], "coupling_gmsh_plate")
a, _ = read_frame(sys.argv[2], frames[-1][1])
x, u = a["reference_position"], a["displacement"]
exact = np.c_[1e-3 * x[:, 0], -1e-3 * x[:, 1] / 3]
err = np.abs(u[:, :2] - exact).max()
print("nodes %d (mesh %s), PD %d, largest error %.3g of 0.016" % (len(x), sys.argv[3], a["node_type"].sum(), err))
sys.exit(0 if len(x) == int(sys.argv[3]) and err <= 1e-9 * 0.016 else 1)
PYEOF
fi
pass "Gmsh-meshed plate in uniform tension: reaction $reaction (120), the analytic displacement at every node"

# imposed fields on every node: the nodal forces F = K u, no solve
imposed() {
  sed -e 's/^  - {type: displacement, region: left, x: 0}/  - {type: displacement, region: all, x: "'"$1"'", y: "'"$2"'"}/' \
      -e '/region: corner/d' -e '/region: right/d' "$TMP/coupling_gmsh_plate.yaml" >"$TMP/imposed.yaml"
  run_peri_in "$TMP" run imposed.yaml -q
  expect_status 0
  value "$TMP/output/imposed/history.csv" out_of_balance
}
er=$(imposed "1e-3 + 2e-3*x + 5e-4*y" "-1e-3 + 3e-4*x - 1e-3*y")
near "$er" 0 1e-13 || fail "linear field: e_r $er, the patch test needs round-off"
er2=$(imposed "1e-4*y*y" "1e-4*x*x")
awk -v e="$er2" 'BEGIN { exit !(e > 1e-6) }' || fail "quadratic field: e_r $er2 should be out of balance"
pass "linear field on every node: e_r $er (quadratic: $er2)"

# the geometries below are meshed into temporary .msh files under TMPDIR: a directory of the
# test's own, which must be empty at the end
saved_tmpdir=${TMPDIR:-/tmp}
export TMPDIR="$TMP/meshes"
mkdir -p "$TMPDIR"

# 1D bars and 3D hexahedra: structured meshes that the Gmsh library makes from a .geo when the
# deck reads it, a linear field imposed on every node
cat >"$TMP/bar.geo" <<'GEO'
Point(1) = {0, 0, 0};
l[] = Extrude {30, 0, 0} { Point{1}; Layers{30}; };
Physical Curve("bar") = {l[1]};
GEO
cat >"$TMP/bar.yaml" <<'DECK'
dimension: 1
materials: {m: {model: pmb, density: 1, youngs_modulus: 1}}
discretization: {spacing: 1, m: 3, cross_section: 1, placement: lattice, fill: [{shape: interval, min: [0], max: [30]}]}
regions: {pd: {shape: interval, min: [9.5], max: [20.5]}}
coupling: {pd_region: pd, mesh: bar.geo}
boundary_conditions: [{type: displacement, region: all, x: "1e-3 + 2e-3*x"}]
solver: {type: implicit, load_steps: 1}
DECK
cat >"$TMP/cube.geo" <<'GEO'
Point(1) = {0, 0, 0};
l[] = Extrude {4, 0, 0} { Point{1}; Layers{8}; };
s[] = Extrude {0, 4, 0} { Curve{l[1]}; Layers{8}; Recombine; };
v[] = Extrude {0, 0, 4} { Surface{s[1]}; Layers{8}; Recombine; };
Physical Volume("cube") = {v[1]};
GEO
cat >"$TMP/cube.yaml" <<'DECK'
dimension: 3
materials: {m: {model: pmb, density: 1, youngs_modulus: 1}}
discretization: {spacing: 0.5, m: 3, placement: lattice, fill: [{shape: box, min: [0, 0, 0], max: [4, 4, 4]}]}
regions: {pd: {shape: box, min: [1.25, 1.25, 1.25], max: [2.75, 2.75, 2.75]}}
coupling: {pd_region: pd, mesh: cube.geo}
boundary_conditions:
  - {type: displacement, region: all, x: "1e-3 + 2e-3*x + 5e-4*y - 1e-3*z", y: "3e-4*x - 1e-3*y + 2e-4*z",
     z: "1e-4*x + 2e-4*y + 7e-4*z"}
solver: {type: implicit, load_steps: 1}
DECK
for case in bar:11 cube:27; do
  name=${case%:*}
  run_peri_in "$TMP" run "$name.yaml" -q
  expect_status 0
  er=$(value "$TMP/output/$name/history.csv" out_of_balance)
  pd=$(value "$TMP/output/$name/history.csv" pd_nodes)
  near "$er" 0 1e-13 || fail "$name: linear field: e_r $er, the patch test needs round-off"
  [[ "$pd" == "${case#*:}" ]] || fail "$name: $pd PD nodes, expected ${case#*:}"
  pass "$name on a Gmsh mesh, linear field on every node: e_r $er with $pd PD nodes"
done

# a geometry that Gmsh 4.8 crashes meshing (the example's, with the frontal-Delaunay algorithm
# for quadrangles, 8): meshed in a child process, so the run exits 2 naming the file instead of
# dying with the library; a later Gmsh that meshes it runs the deck (exit 0). Either way peri
# itself is never ended by a signal. A geometry Gmsh cannot parse is refused with its message.
sed -e 's/Mesh.Algorithm = 6;/Mesh.Algorithm = 8;/' examples/coupling_gmsh_plate.geo >"$TMP/quads8.geo"
sed -e 's/mesh: coupling_gmsh_plate.msh/mesh: quads8.geo/' "$plate" >"$TMP/quads8.yaml"
run_peri_in "$TMP" check quads8.yaml
case "$RUN_STATUS" in
  2) expect_stdout_empty
     # (crashed: a signal; under a sanitizer the child reports the crash and exits: stopped)
     expect_stderr_contains "quads8.geo: the Gmsh library"
     expect_stderr_contains "meshing it"
     pass "a geometry that crashes Gmsh while meshing: exit 2 naming the file" ;;
  0) pass "a geometry that crashed Gmsh 4.8 while meshing is meshed by this Gmsh" ;;
  *) fail "a geometry that crashes Gmsh while meshing: exit status $RUN_STATUS (a signal kills peri itself)" ;;
esac
printf 'Point(1) = {0, 0, 0;\n' >"$TMP/broken.geo"
sed -e 's/mesh: coupling_gmsh_plate.msh/mesh: broken.geo/' "$plate" >"$TMP/broken.yaml"
run_peri_in "$TMP" check broken.yaml
expect_status 2
expect_stderr_contains "broken.geo: cannot read the Gmsh mesh"
pass "a geometry Gmsh cannot parse: exit 2 naming the file"
left=$(ls -A "$TMPDIR")
[[ -z "$left" ]] || fail "the geometries' temporary meshes are left behind: $left"
pass "no temporary mesh left behind (the two geometries and the cube and bar above)"
export TMPDIR=$saved_tmpdir

# the failing cases: a small deck on a 2 x 1 grid of spacing 1, its mesh written by the test
cat >"$TMP/small.yaml" <<'DECK'
dimension: 2
materials: {m: {model: pmb, density: 1, youngs_modulus: 1}}
discretization: {spacing: 1, m: 3, placement: lattice, fill: [{shape: rectangle, min: [0, 0], max: [1, 1]}]}
coupling: {mesh: small.msh}
solver: {type: implicit, load_steps: 1}
DECK
# msh TYPE "TAG NODE..." NODE...: a Gmsh 4.1 file with the nodes (TAG,X,Y) in one surface and
# one element of Gmsh type TYPE
msh() {
  local type=$1 element=$2 tags="" coords="" max=0 node t x y
  shift 2
  for node in "$@"; do
    IFS=, read -r t x y <<<"$node"
    tags+="$t"$'\n' coords+="$x $y 0"$'\n'
    ((t > max)) && max=$t
  done
  {
    printf '$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 %d 1 %d\n2 1 0 %d\n' $# "$max" $#
    printf '%s' "$tags" "$coords"
    printf '$EndNodes\n$Elements\n1 1 7 7\n2 1 %s 1\n%s\n$EndElements\n' "$type" "$element"
  } >"$TMP/small.msh"
}
square=(1,0,0 2,1,0 3,1,1 4,0,1)
# fails WHAT...: peri check exits 2 with nothing on stdout, and stderr holds every WHAT
fails() {
  run_peri_in "$TMP" check small.yaml
  expect_status 2
  expect_stdout_empty
  for what in "$@"; do expect_stderr_contains "$what"; done

}

msh 3 "7 1 2 3 4" "${square[@]}"
run_peri_in "$TMP" check small.yaml
expect_status 0
pass "the small mesh itself is accepted"

sed -i 's/mesh: small.msh/mesh: nothere.msh/' "$TMP/small.yaml"
fails "cannot open mesh file" "nothere.msh"
sed -i 's/mesh: nothere.msh/mesh: small.msh/' "$TMP/small.yaml"
pass "a missing mesh file"

printf '$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1\n' >"$TMP/small.msh"
fails "small.msh: cannot read the Gmsh mesh"
pass "a file Gmsh cannot parse"

msh 3 "7 1 2 3 9" "${square[@]}"
fails "small.msh" "node 9" "element 7"
pass "an element naming a node the file does not define"

msh 3 "7 1 4 3 2" "${square[@]}"
fails "small.msh: element 7" "is inverted"
pass "an inverted element (clockwise corners)"

msh 3 "7 1 2 3 4" 1,0,0 2,0.5,0 3,1,0 4,1.5,0
fails "small.msh: element 7" "is degenerate"
pass "a degenerate element (collinear corners)"

msh 9 "7 1 2 4 5 6 3" "${square[@]}" 5,0.5,0 6,0.5,0.5
fails "small.msh: element 7 is a Triangle 6 (Gmsh type 9)" "no finite element"
pass "an element type peri has no element for"

msh 3 "7 1 2 3 4" "${square[@]}" 5,0.5,0.5
fails "small.msh: node 5 at (0.5, 0.5, 0) belongs to no element"
pass "a node in no element"

# the plate with a PD zone whose horizon reaches the unstructured ring
sed -e 's/pd: {shape: rectangle, min: \[6.25, 4.75\], max: \[9.75, 7.25\]}/pd: {shape: rectangle, min: [4.75, 4.75], max: [9.75, 7.25]}/' \
  "$TMP/coupling_gmsh_plate.yaml" >"$TMP/wide.yaml"
run_peri_in "$TMP" check wide.yaml
expect_status 2
expect_stdout_empty
expect_stderr_contains "coupling: PD node"
expect_stderr_contains "coupling_gmsh_plate.msh"
expect_stderr_matches "(node|element) [0-9]+ of coupling_gmsh_plate.msh"
expect_stderr_contains "the mesh's nodes must coincide with the PD grid"
pass "a PD zone whose horizon reaches the mesh's nodes off the PD grid"

sed -e 's/spacing: 0.5/spacing: 0.4/' -e 's/m: 3/horizon: 1.5/' "$TMP/coupling_gmsh_plate.yaml" >"$TMP/spacing.yaml"
run_peri_in "$TMP" check spacing.yaml
expect_status 2
expect_stderr_contains "coupling_gmsh_plate.msh"
expect_stderr_contains "spacing 0.4"
pass "a mesh made for another spacing"

sed -e 's/max: \[16, 12\]}\]/max: [16, 12]}, {shape: rectangle, min: [17, 0], max: [18, 1]}]/' \
  "$TMP/coupling_gmsh_plate.yaml" >"$TMP/outside.yaml"
run_peri_in "$TMP" check outside.yaml
expect_status 2
expect_stderr_contains "of the PD grid lies outside the mesh"
pass "a grid node outside the mesh that is not PD"

sed -e 's/solver: {type: implicit, load_steps: 1}/solver: {type: implicit, load_steps: 1, breaking: true}/' \
  "$TMP/coupling_gmsh_plate.yaml" >"$TMP/breaking.yaml"
run_peri_in "$TMP" check breaking.yaml
expect_status 2
expect_stderr_contains "key 'mesh': not with solver.breaking yet"
pass "crack growth with switching on a Gmsh mesh is refused at the key"
