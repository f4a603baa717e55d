#!/usr/bin/env bash
# Short-range contact forces from the command line (docs/contact.md): the summary names them,
# the end of a run counts the pair-list builds; bad settings (a negative skin, an unknown key,
# the implicit solver) exit 2 naming file:line:column before any work. Runs on several MPI
# ranks: tests/cli/mpi_contact.sh.
# Usage: bash tests/cli/contact_short_range.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=examples/lammps_peri_pmb.yaml
small=(--set solver.steps=40 --set discretization.fill.0.radius=0.0015 --set discretization.fill.0.length=0.0015
       --set "discretization.fill.0.center=[0, -0.0015, 0]" --set output.every=40)

run_peri run "$deck" "${small[@]}" --set contact.short_range=true --output "$TMP/out"
expect_status 0
expect_stdout_contains "  contact      short-range forces: c_S = 15 c, d = min(0.9 |xi|, 0.000675 m), list skin 0.00015 m, pruned with 4e-05 m"
expect_stdout_matches "^  contact      short-range forces, pair list built [1-9][0-9]* times .*; pruned [1-9][0-9]* times \\(skin 4e-05 m\\)"
pass "the summary names the short-range forces and the run counts its pair-list builds and prunes"

cat > "$TMP/skin.yaml" <<'YAML'
dimension: 3
materials: {m: {model: pmb, density: 2200, bulk_modulus: 14.9e9}}
discretization: {spacing: 0.001, m: 3, fill: [{shape: box, min: [0, 0, 0], max: [0.004, 0.004, 0.004]}]}
contact:
  short_range: {stiffness_factor: 15, skin: -0.001}
solver: {type: explicit, steps: 1}
YAML
run_peri check "$TMP/skin.yaml"
expect_status 2
expect_stderr_contains "skin.yaml:5:"
expect_stderr_contains "key 'skin': must be a positive length"
pass "a negative skin: exit 2 at its line"

sed -e 's/skin: -0.001/skin: 0.0003, prune_skin: 0.0004/' "$TMP/skin.yaml" > "$TMP/prune.yaml"
run_peri check "$TMP/prune.yaml"
expect_status 2
expect_stderr_contains "prune.yaml:5:"
expect_stderr_contains "key 'prune_skin': 0.0004 m is larger than the list's skin 0.0003 m"
sed -e 's/skin: -0.001/prune_skin: 0/' "$TMP/skin.yaml" > "$TMP/prune0.yaml"
run_peri check "$TMP/prune0.yaml"
expect_status 2
expect_stderr_contains "key 'prune_skin': must be a positive length"
pass "a prune skin larger than the skin, or zero: exit 2 at its line"

sed -e 's/stiffness_factor: 15, skin: -0.001/stifness_factor: 15/' "$TMP/skin.yaml" > "$TMP/typo.yaml"
run_peri check "$TMP/typo.yaml"
expect_status 2
expect_stderr_contains "typo.yaml:5:"
expect_stderr_contains "stiffness_factor"
pass "a misspelt key: exit 2 with the suggestion"

sed -e 's/skin: -0.001/skin: 0.0003/' -e 's/type: explicit, steps: 1/type: implicit/' "$TMP/skin.yaml" > "$TMP/implicit.yaml"
run_peri check "$TMP/implicit.yaml"
expect_status 2
expect_stderr_contains "implicit.yaml:5:"
expect_stderr_contains "the implicit solver has no tangent of the short-range forces"
pass "the implicit solver with short-range forces: exit 2"

echo "PASS: contact_short_range.sh"
