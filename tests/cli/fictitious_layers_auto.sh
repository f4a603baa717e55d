#!/usr/bin/env bash
# discretization.fictitious_layers (docs/deck.md section 3, docs/models.md section 6): the 1D PMB
# bar of fictitious_layer.sh, x in [0, 1] (dx = 0.01, delta = 3 dx), loaded by displacement
# conditions u = 1e-3 x on its end nodes only:
# - with `fictitious_layers: auto` the layers (3 nodes beyond each end, prescribed by the end's
#   condition at their own positions) bring the strain of every pair of body nodes to sigma/E
#   within 2% (sigma = reaction / A), where the same bar without them is off by more than 2%
#   (the skin effect); the frame holds the 100 body nodes only;
# - the faces named ([x_max] only) give layers at that end alone: the left end stays off;
# - a named face without a displacement or velocity condition: exit 2 at the key.
# Usage: bash tests/cli/fictitious_layers_auto.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

PY=""
for candidate in /usr/bin/python3 python3; do
  if command -v "$candidate" >/dev/null && "$candidate" -c 'import numpy' 2>/dev/null; then
    PY=$candidate
    break
  fi
done
if [[ -z "$PY" ]]; then
  echo "SKIP: $CLI_NAME: no python3 with numpy (Debian python3-numpy: scripts/install-deps)"
  exit 0
fi

cat >"$TMP/bar.yaml" <<'YAML'
dimension: 1
materials:
  steel: {model: pmb, density: 7850, youngs_modulus: 200e9, critical_stretch: 1.0}
discretization: {spacing: 0.01, m: 3, cross_section: 0.01, fill: [{shape: interval, min: [0], max: [1]}]}
regions:
  left_end: {shape: interval, min: [-1], max: [0.01]}
  right_end: {shape: interval, min: [0.99], max: [2]}
boundary_conditions:
  - {type: displacement, region: left_end, x: "1e-3*x*t"}
  - {type: displacement, region: right_end, x: "1e-3*x*t"}
solver: {type: nlcg, load_steps: 1}
output:
  fields: [displacement]
  picture: false
YAML

# strain_error DIR: the largest |strain - sigma/E| / (sigma/E) over neighbouring body nodes at
# the left end and at the right end, and the frame's node count
strain_error() {
  "$PY" - "$CLI_DIR/lib" "$1" <<'PYEOF'
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
from check_outputs import read_frame, read_history, read_pvd
d = sys.argv[2]
frames = read_pvd(d, "bar")
a, _ = read_frame(d, frames[-1][1])
names, rows = read_history(d)
sigma = rows[-1][names.index("reaction_right_end_x")] / 0.01
x, u = a["reference_position"][:, 0], a["displacement"][:, 0]
o = np.argsort(x)
err = np.abs(np.diff(u[o]) / np.diff(x[o]) / (sigma / 200e9) - 1.0)
half = len(err) // 2
print("%.6f %.6f %d" % (np.max(err[:half]), np.max(err[half:]), len(x)))
PYEOF
}

run_peri run "$TMP/bar.yaml" --quiet --output "$TMP/plain"
expect_status 0
read -r left right count <<<"$(strain_error "$TMP/plain")"
awk -v e="$right" 'BEGIN { exit !(e > 0.02) }' || fail "without layers the strain is within 2% of sigma/E ($right): the check cannot tell"
pass "loaded on the end nodes without layers: strain off sigma/E by $left (left), $right (right)"

run_peri run "$TMP/bar.yaml" --quiet --output "$TMP/auto" --set discretization.fictitious_layers=auto
expect_status 0
read -r left right count <<<"$(strain_error "$TMP/auto")"
awk -v a="$left" -v b="$right" 'BEGIN { exit !(a < 0.02 && b < 0.02) }' ||
  fail "with automatic layers the strain is off sigma/E by $left (left), $right (right) (> 2%)"
[[ "$count" == 100 ]] || fail "the frame holds $count nodes, not the 100 body nodes"
pass "fictitious_layers: auto: strain = sigma/E within 2% up to both end nodes ($left, $right); the frame holds the 100 body nodes"

run_peri run "$TMP/bar.yaml" --quiet --output "$TMP/right" --set "discretization.fictitious_layers=[x_max]"
expect_status 0
read -r left right count <<<"$(strain_error "$TMP/right")"
awk -v a="$left" -v b="$right" 'BEGIN { exit !(a > 0.02 && b < 0.02) }' ||
  fail "fictitious_layers: [x_max]: strain off by $left (left, expected > 2%) and $right (right, expected < 2%)"
pass "fictitious_layers: [x_max]: the right end within 2% ($right), the left end without a layer off by $left"

cat >"$TMP/free_face.yaml" <<'YAML'
dimension: 1
materials:
  steel: {model: pmb, density: 7850, youngs_modulus: 200e9}
discretization: {spacing: 0.01, m: 3, cross_section: 0.01, fictitious_layers: [x_min], fill: [{shape: interval, min: [0], max: [1]}]}
regions:
  right_end: {shape: interval, min: [0.99], max: [2]}
boundary_conditions:
  - {type: displacement, region: right_end, x: 0}
solver: {type: nlcg, load_steps: 1}
YAML
run_peri check "$TMP/free_face.yaml"
expect_status 2
expect_stderr_contains "free_face.yaml:4"
expect_stderr_contains "x_min"
pass "a named face without a displacement or velocity condition: exit 2 at the key"
echo "PASS: $CLI_NAME"
