#!/usr/bin/env bash
# Fictitious layer regions (docs/deck.md section 10, docs/models.md section 6):
# - a 1D PMB bar x in [0, 1] (dx = 0.01, delta = 3 dx) pulled through layers of width delta at
#   both ends, the layers' motion prescribed as u = 1e-3 x: the strain (u_{i+1} - u_i)/dx of
#   every pair of body nodes, the boundary nodes included, equals sigma/E within 2%, where
#   sigma = reaction / A is read from history.csv. Without layers (the same bar loaded on its
#   end nodes) the strain next to the loaded ends is off by more than 2% (the skin effect);
# - the VTU frame holds the body nodes only (100, the layers' 2 x 3 nodes left out);
# - bonds with an end in a layer never break even far above the critical stretch, while the
#   same region without the flag loses bonds;
# - a sweep's max_displacement is the body's (the layers move further);
# - a layer region with no node, and a layer without a prescribed motion: exit 2 at the key.
# Usage: bash tests/cli/fictitious_layer.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
deck="$DECKS/layer_bar.yaml"

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

# strain_error DIR: the largest |strain - sigma/E| / (sigma/E) over neighbouring body nodes
# (E = 200e9 Pa, A = 0.01 m^2 as in the deck), and the frame's node count
strain_error() {
  "$PY" - "$CLI_DIR/lib" "$1" <<'PYEOF'
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
from check_outputs import read_frame, read_history, read_pvd
d = sys.argv[2]
frames = read_pvd(d, "layer_bar")
a, _ = read_frame(d, frames[-1][1])
names, rows = read_history(d)
sigma = rows[-1][names.index("reaction_right_layer_x")] / 0.01
x, u = a["reference_position"][:, 0], a["displacement"][:, 0]
o = np.argsort(x)
strain = np.diff(u[o]) / np.diff(x[o])
print("%.6f %d" % (np.max(np.abs(strain / (sigma / 200e9) - 1.0)), len(x)))
PYEOF
}

run_peri run "$deck" --quiet --output "$TMP/layers"
expect_status 0
read -r err count <<<"$(strain_error "$TMP/layers")"
awk -v e="$err" 'BEGIN { exit !(e < 0.02) }' || fail "with layers the strain is off sigma/E by $err (> 2%)"
[[ "$count" == 100 ]] || fail "the frame holds $count nodes, not the 100 body nodes"
pass "layers of width delta: strain = sigma/E within 2% up to the boundary nodes (largest error $err); the frame holds the 100 body nodes"

run_peri run "$deck" --quiet --output "$TMP/ends" --set "discretization.fill=[{shape: interval, min: [0], max: [1]}]" \
  --set "regions.left_layer={shape: interval, min: [-1], max: [0.01]}" \
  --set "regions.right_layer={shape: interval, min: [0.99], max: [2]}"
expect_status 0
read -r err count <<<"$(strain_error "$TMP/ends")"
awk -v e="$err" 'BEGIN { exit !(e > 0.02) }' || fail "without layers the strain is within 2% of sigma/E ($err): the check cannot tell"
pass "loaded on the end nodes without layers: strain off sigma/E by $err (> 2%)"

# bonds of a layer stretched by 1% (critical stretch 1e-3): none breaks; the body is held still
cat >"$TMP/break.yaml" <<'YAML'
dimension: 1
materials:
  steel: {model: pmb, density: 7850, youngs_modulus: 200e9, critical_stretch: 1.0e-3}
discretization: {spacing: 0.01, m: 3, cross_section: 0.01, fill: [{shape: interval, min: [-0.03], max: [1.03]}]}
regions:
  body: {shape: interval, min: [0], max: [1]}
  left_layer: {shape: interval, min: [-1], max: [0], fictitious_layer: true}
  right_layer: {shape: interval, min: [1], max: [2], fictitious_layer: true}
boundary_conditions:
  - {type: displacement, region: body, x: 0}
  - {type: displacement, region: left_layer, x: 0}
  - {type: displacement, region: right_layer, x: "1e-2*(x-1)*t"}
solver: {type: nlcg, load_steps: 2}
output: {fields: [damage], picture: false}
YAML
broken() { awk -F, -v c="$(csv_column "$1/history.csv" broken_bond_fraction)" 'END { print $c }' "$1/history.csv"; }
run_peri run "$TMP/break.yaml" --quiet --output "$TMP/brk"
expect_status 0
b=$(broken "$TMP/brk")
awk -v b="$b" 'BEGIN { exit !(b == 0) }' || fail "a layer lost bonds: broken_bond_fraction $b"
run_peri run "$TMP/break.yaml" --quiet --output "$TMP/brk_plain" --set regions.right_layer.fictitious_layer=false
expect_status 0
b=$(broken "$TMP/brk_plain")
awk -v b="$b" 'BEGIN { exit !(b > 0) }' || fail "without the flag no bond broke either ($b): the check cannot tell"
pass "bonds of a layer stretched 10x past the critical stretch never break (they do without the flag: $b)"

run_peri check "$deck" --set "regions.right_layer={shape: interval, min: [5], max: [6], fictitious_layer: true}"
expect_status 2
expect_stderr_contains "--set:1:"
expect_stderr_contains "a fictitious layer must contain nodes"
pass "a layer with no node: exit 2"

sed 's/^  - {type: displacement, region: right_layer.*$/  - {type: body_force, region: right_layer, x: 1}/' "$deck" >"$TMP/free_layer.yaml"
run_peri check "$TMP/free_layer.yaml"
expect_status 2
expect_stderr_contains "no prescribed motion"
expect_stderr_matches "free_layer.yaml:10:[0-9]+: error"  # the right_layer line
pass "a layer without a prescribed motion: exit 2 at file:line:column"

# a sweep's maxima are over the body: the largest body displacement is 1e-3 x 0.995 m (the
# outermost body node), the layers' outermost nodes reach 1e-3 x 1.025 m
run_peri sweep "$deck" --quiet --output "$TMP/sweep" --set-list solver.load_steps=1 --quantity max_displacement
expect_status 0
expect_stdout_contains "| 1 | 0.000995 |"
pass "max_displacement of a sweep leaves the layers out"
