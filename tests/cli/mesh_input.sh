#!/usr/bin/env bash
# Meshes in decks (docs/deck.md, "Meshes"): examples/mesh_plate.yaml reads a Gmsh geometry
# and runs; a bad mesh or a bad set is an input error (exit 2) naming the file and the
# entity, before any work: a missing file, a truncated Gmsh mesh, a damaged one that crashes
# the Gmsh library, a block without a material, an unknown node set, a node set file naming
# a node that does not exist, and node files with PeriLab's header and CSV headers read by
# peri check. Without Gmsh in the build the deck is refused with a message that names the
# missing library.
# Usage: bash tests/cli/mesh_input.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=examples/mesh_plate.yaml
[[ -f "$deck" ]] || fail "run from the repository root ($deck not found)"
run_peri check "$deck"
have_gmsh=1
if grep -q "built without" "$RUN_STDERR"; then
  expect_status 2
  expect_stderr_contains "libgmsh-dev"
  pass "$deck: refused by a build without Gmsh, naming libgmsh-dev"
  have_gmsh=0
fi
if [[ $have_gmsh -eq 1 ]]; then
expect_status 0
nodes=$(sed -nE 's/^ *nodes +([0-9]+).*/\1/p' "$RUN_STDOUT")
[[ -n "$nodes" && $nodes -gt 1000 ]] || fail "$deck: expected over 1000 nodes, got '$nodes'"
run_peri run "$deck" --quiet --output "$TMP/plate" --set solver.end_time=5e-6
expect_status 0
expect_nonempty_file "$TMP/plate/history.csv"
pass "$deck: $nodes nodes from the Gmsh geometry, runs"
fi

# a deck in TMP reading mesh files there: mesh_deck MESH [EXTRA YAML LINES]
mesh_deck() {
  {
    printf 'dimension: 2\nmaterials:\n  a: {model: pmb, density: 1000, youngs_modulus: 1e9}\n'
    printf '  b: {model: pmb, density: 1000, youngs_modulus: 2e9}\n'
    printf 'discretization:\n  mesh: %s\n  m: 3\n  thickness: 1e-3\n' "$1"
    shift
    printf '%s\n' "$@"
    printf 'solver: {type: explicit, steps: 1}\noutput: {picture: false}\n'
  } >"$TMP/deck.yaml"
}

mesh_deck missing.msh '  blocks: [a]'
run_peri check "$TMP/deck.yaml"
expect_status 2
expect_stderr_contains "missing.msh"
pass "a missing mesh file: exit 2, named"

if [[ $have_gmsh -eq 1 ]]; then
# a truncated Gmsh mesh
gmsh_file="$TMP/plate.msh"
cat >"$TMP/plate.geo" <<'GEO'
Point(1) = {0, 0, 0, 0.2}; Point(2) = {1, 0, 0, 0.2}; Point(3) = {1, 1, 0, 0.2}; Point(4) = {0, 1, 0, 0.2};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Surface("left_half") = {1}; Physical Curve("edge") = {4};
GEO
mesh_deck plate.geo '  blocks: {left_half: a}' 'regions:' '  edge: {node_set: edgee}'
run_peri check "$TMP/deck.yaml"
expect_status 2
expect_stderr_contains "the mesh has no set 'edgee'; did you mean 'edge'?"
pass "an unknown node set: exit 2, with a suggestion"

mesh_deck plate.geo '  blocks: {left_half: a, right_half: b}'
run_peri check "$TMP/deck.yaml"
expect_status 2
expect_stderr_contains "has no such block (its blocks: 'left_half' (id 1))"
pass "a block the mesh does not have: exit 2, with the mesh's blocks"

mesh_deck plate.geo
run_peri check "$TMP/deck.yaml"
expect_status 2
expect_stderr_contains "block 'left_half' (id 1) of $TMP/plate.geo has no material"
pass "a block without a material: exit 2, named"

if command -v gmsh >/dev/null; then
  gmsh -2 "$TMP/plate.geo" -o "$gmsh_file" -v 0 >/dev/null 2>&1 || fail "gmsh could not mesh $TMP/plate.geo"
  head -c $(( $(stat -c %s "$gmsh_file") / 2 )) "$gmsh_file" >"$TMP/cut.msh"
  mesh_deck cut.msh '  blocks: [a]'
  run_peri check "$TMP/deck.yaml"
  expect_status 2
  expect_stderr_contains "$TMP/cut.msh"
  pass "a truncated Gmsh mesh: exit 2, named"
fi

# a damaged mesh whose element names a negative node tag: Gmsh 4.8 crashes reading it (the
# reading runs in a child process first, whose crash is reported as bad input)
sed '1213s/^101 218 66 65 138 *$/101 218 -5 65 138/' examples/coupling_gmsh_plate.msh >"$TMP/negative.msh"
cmp -s examples/coupling_gmsh_plate.msh "$TMP/negative.msh" && fail "the element line to damage was not found"
run_peri check examples/coupling_gmsh_plate.yaml --set "coupling.mesh=$TMP/negative.msh"
expect_status 2
expect_stderr_contains "$TMP/negative.msh"
pass "an element with a negative node tag: exit 2, named ($(head -n 1 "$RUN_STDERR" | sed 's/.*msh: //'))"
# a node coordinate that overflows to infinity (the bond search then spanned it without end)
sed '69s/^1.14285714285487 0 0 *$/1.1e285714285487 0 0/' examples/coupling_gmsh_plate.msh >"$TMP/infinite.msh"
cmp -s examples/coupling_gmsh_plate.msh "$TMP/infinite.msh" && fail "the node line to damage was not found"
run_peri check examples/coupling_gmsh_plate.yaml --set "coupling.mesh=$TMP/infinite.msh"
expect_status 2
expect_stderr_contains "$TMP/infinite.msh: node 9 lies at x = inf; positions must be finite"
pass "a node at an infinite coordinate: exit 2, named"
fi

# node files with headers, and a node set file naming a node that does not exist
printf 'header: x y block_id volume\n0.5e-3 0.5e-3 1 1e-9\n1.5e-3 0.5e-3 1 1e-9\n2.5e-3 0.5e-3 2 1e-9\n' >"$TMP/nodes.txt"
printf 'x,y,block_id,volume\n0.5e-3,0.5e-3,1,1e-9\n1.5e-3,0.5e-3,1,1e-9\n2.5e-3,0.5e-3,2,1e-9\n' >"$TMP/nodes.csv"
for f in nodes.txt nodes.csv; do
  mesh_deck "$f" '  blocks: [a, b]'
  run_peri check "$TMP/deck.yaml"
  expect_status 0
  expect_stdout_matches "nodes +3"
done
pass "node files with PeriLab's header and with a CSV header"
printf '1\n4\n' >"$TMP/clamp.txt"
mesh_deck nodes.txt '  blocks: [a, b]' 'regions:' '  clamp: {node_set_file: clamp.txt}'
run_peri check "$TMP/deck.yaml"
expect_status 2
expect_stderr_contains "clamp.txt:2: node 4 does not exist"
pass "a node set file naming a node that does not exist: exit 2, file:line"

# the Gmsh example with its node-set regions on 1 and 2 ranks: the history of one process
[[ $have_gmsh -eq 1 ]] || exit 0
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
mpi_init
MPI_RANKS="1 2"
mpi_same_on_ranks mesh_plate "$deck" --set solver.end_time=10e-6
pass "$deck: the same history.csv on 1 and 2 ranks"
