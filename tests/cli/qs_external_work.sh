#!/usr/bin/env bash
# External work of quasi-static runs (src/solver/qs_work.c). For a linear elastic body loaded
# quasi-statically, the work of the loads and of the supports' reactions equals the strain
# energy (Clapeyron's theorem: W = U = 1/2 F.u); the force is linear along the load path,
# so the trapezoid rule over load steps is exact and W differs from U only by the solver
# tolerance (1e-8) and the geometric nonlinearity of bonds at strains ~1e-3 (~1e-3
# relative at most): the test allows 1%. Before this, external_work was 0 in every
# quasi-static history, so energy_balance was -U.
#  - a 3D LPS bar pulled by a prescribed displacement (the reactions' work), nlcg;
#  - a 2D PMB plate loaded by a traction (the load's work), adr;
#  - a 1D bar pulled through fracture: W >= U at every row and, after the break, W - U
#    (the energy taken by the broken bonds) stays positive while U falls to ~0.
# Usage: bash tests/cli/qs_external_work.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# values HISTORY NAME: the column NAME of HISTORY, one value a line (header left out)
values() {
  local k
  k=$(csv_column "$1" "$2")
  [[ -n "$k" ]] || fail "$1: no column $2"
  tail -n +2 "$1" | cut -d, -f"$k"
}

# check_clapeyron HISTORY LABEL: every row after the first has W > 0 and |W - U| <= 1% of U
check_clapeyron() {
  local history=$1 label=$2 se ew
  se=$(values "$history" strain_energy)
  ew=$(values "$history" external_work)
  paste <(echo "$se") <(echo "$ew") | awk -v label="$label" '
    NR == 1 { next } # the unloaded start
    { rows++; if (!($2 > 0) || ($2 - $1 > 0.01 * $1) || ($1 - $2 > 0.01 * $1)) { print label ": row " NR ": U = " $1 ", W = " $2; bad = 1 } }
    END { if (rows < 3) { print label ": only " rows " load steps"; bad = 1 } exit bad }' ||
    fail "$label: the external work should equal the strain energy within 1%"
}

cat >"$TMP/bar3d.yaml" <<'DECK'
dimension: 3
materials:
  steel: {model: lps, density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25, critical_stretch: 1.0e-3}
discretization: {spacing: 1.0e-3, m: 3, fill: [{shape: box, min: [0, 0, 0], max: [0.021, 0.007, 0.007]}]}
regions:
  held: {shape: box, min: [-1, -1, -1], max: [0.001, 1, 1]}
  pulled: {shape: box, min: [0.020, -1, -1], max: [1, 1, 1]}
boundary_conditions:
  - {type: displacement, region: held, x: 0, y: 0, z: 0}
  - {type: displacement, region: pulled, x: "1.0e-5*t", y: 0, z: 0}
solver: {type: nlcg, load_steps: 4, breaking: false}
output: {picture: false}
DECK
run_peri run "$TMP/bar3d.yaml" --quiet --output "$TMP/bar3d"
expect_status 0
check_clapeyron "$TMP/bar3d/history.csv" "3D LPS bar, prescribed displacement"
pass "3D bar pulled by a prescribed displacement: W = U within 1% at every load step"

cat >"$TMP/plate.yaml" <<'DECK'
dimension: 2
materials:
  steel: {model: pmb, density: 7850, youngs_modulus: 200e9, critical_stretch: 1.0e-3}
discretization: {spacing: 1.0e-3, m: 3, thickness: 1.0e-3, fill: [{shape: rectangle, min: [0, 0], max: [0.03, 0.01]}]}
regions:
  held: {shape: rectangle, min: [-1, -1], max: [0.001, 1]}
  loaded: {shape: rectangle, min: [0.029, -1], max: [1, 1]}
boundary_conditions:
  - {type: displacement, region: held, x: 0, y: 0}
  - {type: traction, region: loaded, x: "20e6*t"}
solver: {type: adr, load_steps: 5, breaking: false}
output: {picture: false}
DECK
run_peri run "$TMP/plate.yaml" --quiet --output "$TMP/plate"
expect_status 0
check_clapeyron "$TMP/plate/history.csv" "2D PMB plate, traction"
pass "2D plate under a traction: W = U within 1% at every load step"

run_peri run tests/cli/decks/qs_bar.yaml --quiet --output "$TMP/fracture"
expect_status 0
paste <(values "$TMP/fracture/history.csv" strain_energy) <(values "$TMP/fracture/history.csv" external_work) |
  awk 'NR == 1 { next }
       { if ($2 < $1 * (1 - 1e-6) - 1e-12) { print "row " NR ": W = " $2 " < U = " $1; bad = 1 }
         if ($2 > peak_w) peak_w = $2; last_u = $1; last_w = $2 }
       END { if (!(last_w > 0.5 * peak_w) || !(last_u < 1e-6 * last_w)) { print "after the break U = " last_u ", W = " last_w; bad = 1 } exit bad }' ||
  fail "1D bar through fracture: the external work should bound the strain energy and keep the dissipated energy"
pass "1D bar through fracture: W >= U at every row, W kept after the break (U ~ 0)"
echo "PASS: $CLI_NAME"
