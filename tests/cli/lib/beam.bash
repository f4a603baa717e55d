# The notched beam in three-point bending (examples/notched_beam_3pb.yaml) coarsened to
# dx = 2.5 mm for the command-line tests: one support node on each side, the two load nodes
# next to the midline. Sourced after assert.bash; each test adds its own load steps:
#   run_peri run "$BEAM_DECK" "${BEAM_COARSE[@]}" --set solver.load_steps=12 ...
BEAM_DECK=examples/notched_beam_3pb.yaml
[[ -f "$BEAM_DECK" ]] || fail "run from the repository root ($BEAM_DECK not found)"
BEAM_COARSE=(--set discretization.spacing=2.5e-3
  --set "regions.left_support.min=[-0.0495, -1]" --set "regions.left_support.max=[-0.048, 0.0014]"
  --set "regions.right_support.min=[0.048, -1]" --set "regions.right_support.max=[0.0495, 0.0014]"
  --set "regions.load.min=[-0.0013, 0.023]" --set "regions.load.max=[0.0013, 1]")
