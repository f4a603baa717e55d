#!/usr/bin/env bash
# Image input (docs/microstructures.md, docs/deck.md section 6: fill items of shape image):
# - the plate with a hole (docs/verification.md Elasticity 6) at delta = 3 mm, m = 3, built from
#   a PNG of 1 mm pixels (white steel, red hole; scripts/microstructure hole), gives the far-field
#   stress within 2% of the applied 1 MPa and a stress concentration between the
#   horizon-averaged Kirsch value less 5% and 3.7 + 10% (the tolerances of the shape-built plate,
#   tests/verification/test_stress.c); the image path changes nothing: the node count, the
#   concentration and the largest von Mises stress equal those of the plate built from shapes;
# - an unreadable file, a file that is not a PNG, a colour not in the table (named with the file
#   and the pixel), a missing pixel_size and a grid finer than the pixels: exit 2 before any work.
# Usage: bash tests/cli/image_input.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
if ! python3 -c 'import zlib' 2>/dev/null; then
  echo "SKIP: $CLI_NAME: no python3 for scripts/microstructure"
  exit 0
fi
cp "$DECKS/image_hole.yaml" "$TMP/"
python3 scripts/microstructure hole "$TMP/hole.png" --width 100 --height 50 --radius 10 || fail "scripts/microstructure hole"
deck="$TMP/image_hole.yaml"
q=(--set-list solver.tolerance=1e-8 --quantity "max:stress_xx@x=0.0495" --quantity "mean:stress_xx@x=0.02"
   --quantity max_von_mises --quantity nodes)

# the data row of a sweep table without its last column (seconds)
row() { grep '^| 1e-8' "$RUN_STDOUT" | sed 's/| [0-9.]* |$//'; }

run_peri sweep "$deck" "${q[@]}"
expect_status 0
image_row=$(row)
read -r scf far <<<"$(echo "$image_row" | awk -F'|' '{ printf "%.6f %.6g\n", $3 / $4, $4 }')"
awk -v f="$far" 'BEGIN { exit !(f > 0.98e6 && f < 1.02e6) }' || fail "far-field stress $far Pa, applied 1 MPa (2%)"
awk -v s="$scf" 'BEGIN { exit !(s > 0.95 * 2.87 && s < 1.10 * 3.7) }' ||
  fail "stress concentration $scf outside [0.95 x 2.87, 1.1 x 3.7]"
pass "plate with a hole from an image: far field $far Pa, stress concentration $scf"

run_peri sweep examples/plate_with_hole.yaml --set discretization.horizon=3e-3 --set discretization.spacing=1e-3 \
  --set "regions.left_edge.max=[0.003, 1]" --set "regions.right_edge.min=[0.097, -1]" \
  --set boundary_conditions.1.layer=3e-3 "${q[@]}"
expect_status 0
[[ "$(row)" == "$image_row" ]] || fail "image and shapes differ: '$image_row' against '$(row)'"
pass "the image gives the nodes and the stresses of the plate built from shapes"

run_peri check "$deck" --set discretization.fill.0.file=missing.png
expect_status 2
expect_stderr_contains "missing.png: cannot open"
run_peri check "$deck" --set discretization.fill.0.file=image_hole.yaml
expect_status 2
expect_stderr_contains "image_hole.yaml: not a readable PNG image"
run_peri check "$deck" --set 'discretization.fill.0.colors={"#ffffff": steel}'
expect_status 2
expect_stderr_matches "hole.png: pixel \([0-9]+, [0-9]+\) .* has the colour #ff0000, which is not in 'colors'"
run_peri check "$deck" --set 'discretization.fill.0={shape: image, file: hole.png, colors: {"#ffffff": steel}}'
expect_status 2
expect_stderr_contains "missing key 'pixel_size'"
run_peri check "$deck" --set discretization.spacing=0.5e-3
expect_status 2
expect_stderr_contains "finer than the pixel size"
run_peri check "$deck" --set 'discretization.fill.0.colors={"#ffffff": steal, "#ff0000": void}'
expect_status 2
expect_stderr_contains "did you mean 'steel'"
pass "bad images and keys: exit 2 naming the file, the pixel and the key"
