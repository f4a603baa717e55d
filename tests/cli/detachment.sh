#!/usr/bin/env bash
# Detachment defects (docs/microstructures.md section 3, Le 2014 section 3.4.9): fill items of
# shape detachment on tests/cli/decks/detachment.yaml, a bi2212 band two rows thick in a 20 x 10
# silver grid of unit spacing (cell centres). The node counts follow from the lattice:
# - thickness 1 over the window x in [5, 15] above the band removes the ten silver nodes of the
#   row next to it (y = 6.5, x = 5.5 ... 14.5): 150 silver nodes are left of 160; it acts after
#   the band although it comes before it in the list;
# - thickness 1.5 reaches the diagonal neighbours (sqrt 2) but no new row: still ten;
#   thickness 2 takes the next row too: twenty;
# - without `within`, both sides of the band along its whole length: 2 x 20 nodes;
# - material soft instead of void keeps the 200 nodes and makes ten of them soft;
# - a thickness below the spacing, the same phase on both sides, a material left unchanged, an
#   unknown material, an unknown key and a graded grid are errors at the key, exit 2.
# Usage: bash tests/cli/detachment.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
deck="$DECKS/detachment.yaml"
item=discretization.fill.1

# nodes of material $1 in the last check's summary
nodes_of() { sed -n "s/^  material     $1: \([0-9]*\) nodes,.*/\1/p" "$RUN_STDOUT"; }
expect_nodes() { # label silver bi2212 [soft]
  local got="$(nodes_of silver) $(nodes_of bi2212)${4:+ $(nodes_of soft)}"
  [[ "$got" == "$2 $3${4:+ $4}" ]] || fail "$1: silver, bi2212${4:+, soft} nodes $got, expected $2 $3${4:+ $4}"
  pass "$1: silver, bi2212${4:+, soft} nodes $got"
}

run_peri check "$deck"
expect_status 0
expect_stdout_contains "  nodes        190"
expect_nodes "thickness 1 over x in [5, 15]" 150 40
run_peri check "$deck" --set $item.thickness=1.5
expect_status 0
expect_nodes "thickness 1.5" 150 40
run_peri check "$deck" --set $item.thickness=2
expect_status 0
expect_nodes "thickness 2" 140 40
run_peri check "$deck" --set "$item={shape: detachment, phase: silver, along: bi2212, thickness: 1, material: void}"
expect_status 0
expect_nodes "no window: both sides, whole length" 120 40
run_peri check "$deck" --set $item.material=soft
expect_status 0
expect_stdout_contains "  nodes        200"
expect_nodes "a soft detachment" 150 40 10

run_peri check "$deck" --set $item.thickness=0.5
expect_status 2
expect_stderr_matches "^--set:1:[0-9]+: error: key 'thickness': 0.5 is less than the node spacing 1"
run_peri check "$deck" --set $item.along=silver
expect_status 2
expect_stderr_contains "'phase' and 'along' are both 'silver'"
run_peri check "$deck" --set $item.material=silver
expect_status 2
expect_stderr_contains "the detached nodes would stay 'silver'"
run_peri check "$deck" --set $item.along=bi2221
expect_status 2
expect_stderr_contains "bi2221"
run_peri check "$deck" --set $item.width=1
expect_status 2
expect_stderr_contains "width"
run_peri check "$deck" --set discretization.fill.0.spacing=0.5
expect_status 2
expect_stderr_contains "a detachment defect needs a uniform grid"
pass "bad detachment keys exit 2 at the key"
