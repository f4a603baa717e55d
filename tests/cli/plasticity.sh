#!/usr/bin/env bash
# Sublayer plasticity from the command line (docs/plasticity.md):
#  - a 1D bar loaded quasi-statically (ADR) through the breakpoints of Ebrahimi Table 5.2,
#    unloaded and reloaded in compression: the reaction per area follows the power-law curve
#    sigma = 400 MPa (eps/0.002)^0.1 at every breakpoint, unloads with slope E, and on the
#    reverse branch drops by 2 sigma_k at eps_a - 2 eps_k (Masing rule), each within 2%;
#  - ductile failure: with critical_plastic_stretch the bar breaks between the strains where the
#    plastic stretch sum_k W_k (eps - s_yk)+ passes it;
#  - energy failure: with critical_bond_energy the bonds of each length break at the strain where
#    their work (stored and dissipated) reaches the w_c of G0, and the bar's stress falls by their share;
#  - peri check reports the sublayers and the plastic state's bytes per directed bond;
#  - bad plasticity input: file:line:column, exit 2 (calibration: family with given weights or in 1D; weights that do not sum to 1, yield
#    stretches that do not increase, a curve with a negative slope, a solver with trial states,
#    Cowper-Symonds constants that are not positive or with a quasi-static solver);
#  - the thread count does not change a plastic fracture run (history and frames bitwise);
#  - a plastic material that never reaches its first yield moves bitwise as the elastic one
#    (PMB and LPS), and the LPS screen gives the plastic path's results where the plate yields in part;
#  - the deviatoric yield rule (docs/plasticity.md section 8): peri check's sublayers and bytes per
#    bond, 1 and 3 threads bitwise on a 3D block that yields through, bad combinations exit 2.
# Usage: bash tests/cli/plasticity.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# --- the cyclic bar
deck="$DECKS/plastic_bar.yaml"
run_peri run "$deck" --quiet --output "$TMP/bar"
expect_status 0
hist="$TMP/bar/history.csv"
col=$(csv_column "$hist" reaction_pulled_x)
[[ -n "$col" ]] || fail "history.csv has no reaction_pulled_x"
# expected stress per load step: the curve at the four breakpoints, flat to the peak 0.025,
# elastic unloading by 0.003 (600 MPa), then sigma_peak - 2 sigma_k at 0.025 - 2 eps_k
awk -F, -v c="$col" '
  function curve(e) { return 400e6 * (e / 0.002) ^ 0.1 }
  BEGIN {
    split("0.002 0.0065 0.0124 0.0168", eps, " ")
    for (k = 1; k <= 4; ++k) want[k] = curve(eps[k])
    peak = curve(0.0168); want[5] = peak; want[6] = peak - 200e9 * 0.003
    for (k = 1; k <= 4; ++k) want[6 + k] = peak - 2 * curve(eps[k])
  }
  NR > 2 {
    step = $2; got = $c / 1.0e-4
    err = (got - want[step]) / (want[step] < 0 ? -want[step] : want[step])
    if (err < 0) err = -err
    printf "  load step %d: %.6g Pa, expected %.6g Pa (%.3f%%)\n", step, got, want[step], 100 * err
    if (err > 0.02) bad = 1
    ++rows
  }
  END { exit (bad || rows != 10) }' "$hist" || fail "the bar does not follow the hardening curve and the Masing rule (above)"
pass "1D bar (ADR): breakpoints, elastic unloading and the Masing reverse branch within 2%"

# --- ductile failure: critical_plastic_stretch 0.005; the plastic stretch of the bar's bonds,
# sum_k W_k (eps - s_yk)+, reaches it at eps_f = (0.005 + 0.9444 * 0.002 + 0.03015 * 0.0065) /
# (0.9444 + 0.03015) = 0.00727: the bar carries load at eps = 0.0072 and none at 0.0074
sed -e 's|power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}|&\n      critical_plastic_stretch: 0.005|' \
  -e 's|x\*(t<1.5 ? 0.002\*t .*)"|x*(t<1.5 ? 0.0072*t : 0.0074)"|' \
  -e 's|end_time: 10, load_steps: 10|end_time: 2, load_steps: 2|' "$deck" >"$TMP/ductile.yaml"
grep -q 'critical_plastic_stretch: 0.005' "$TMP/ductile.yaml" && grep -q '0.0074)' "$TMP/ductile.yaml" ||
  fail "could not write the ductile bar deck"
run_peri run "$TMP/ductile.yaml" --quiet --output "$TMP/ductile"
expect_status 0
hist="$TMP/ductile/history.csv"
r1=$(sed -n 3p "$hist" | cut -d, -f"$(csv_column "$hist" reaction_pulled_x)")
r2=$(sed -n 4p "$hist" | cut -d, -f"$(csv_column "$hist" reaction_pulled_x)")
b2=$(sed -n 4p "$hist" | cut -d, -f"$(csv_column "$hist" broken_bond_fraction)")
# at 0.0072 the curve gives 400 MPa (0.0072/0.002)^0.1 between breakpoints 2 and 3
awk -v r="$r1" 'BEGIN { s = r / 1.0e-4; exit !(s > 450e6 && s < 480e6) }' || fail "ductile bar at 0.0072: $r1 N"
awk -v r="$r2" -v b="$b2" 'BEGIN { exit !(r < 1 && r > -1 && b > 0.99) }' ||
  fail "ductile bar at 0.0074: reaction $r2 N, broken fraction $b2 (expected 0 and every bond)"
pass "critical plastic stretch: the bar holds at eps = 0.0072 ($r1 N) and has broken at 0.0074"

# --- energy failure: critical_bond_energy from G0 = 9e4 J/m^2. Every node of the bar follows
# the affine field, so every bond is at the bar's strain eps; a bond of length xi breaks when
# its work c xi sum_k W_k phi_k(eps) reaches w_c = 2 G0 / (A delta^2), with c = 2E / (A delta^2):
# at E xi sum_k W_k phi_k(eps) = G0, eps = 0.00801 (xi = 3 dx), 0.01123 (2 dx), 0.02043 (dx).
# The bar (30 nodes) has 54, 56 and 58 directed bonds of 3, 2 and 1 spacings; a bond of k
# spacings carries k beta_k of the stress (beta_3 = 1/2), so after the longest break the bar
# carries 3/4.5 of the curve's stress and after the next 1/4.5.
sed -e 's|power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}|&\n      critical_bond_energy: {fracture_energy: 9.0e4}|' \
  -e 's|x\*(t<1.5 ? 0.002\*t .*)"|x*(t<0.5 ? 0 : t<1.5 ? 0.0079 : t<2.5 ? 0.0082 : t<3.5 ? 0.0111 : t<4.5 ? 0.0114 : t<5.5 ? 0.0200 : 0.0209)"|' \
  -e 's|held: {shape: interval, min: \[-1\], max: \[0.035\]}|held: {shape: interval, min: [-1], max: [0.15]}|' \
  -e 's|pulled: {shape: interval, min: \[0.265\], max: \[1\]}|pulled: {shape: interval, min: [0.15], max: [1]}|' \
  -e 's|end_time: 10, load_steps: 10|end_time: 6, load_steps: 6|' "$deck" >"$TMP/energy.yaml"
grep -q 'critical_bond_energy' "$TMP/energy.yaml" && grep -q '0.0209)' "$TMP/energy.yaml" && grep -q 'max: \[0.15\]' "$TMP/energy.yaml" ||
  fail "could not write the energy failure deck"
run_peri run "$TMP/energy.yaml" --quiet --output "$TMP/energy"
expect_status 0
hist="$TMP/energy/history.csv"
awk -F, -v cb="$(csv_column "$hist" broken_bond_fraction)" -v cr="$(csv_column "$hist" reaction_pulled_x)" '
  function curve(e) { # the piecewise-linear curve of Table 5.2 through the power-law breakpoints
    if (e <= 0.0065) return 400e6 + (e - 0.002) / 0.0045 * (400e6 * 3.25 ^ 0.1 - 400e6)
    if (e <= 0.0124) return 400e6 * 3.25 ^ 0.1 + (e - 0.0065) / 0.0059 * (400e6 * 6.2 ^ 0.1 - 400e6 * 3.25 ^ 0.1)
    if (e <= 0.0168) return 400e6 * 6.2 ^ 0.1 + (e - 0.0124) / 0.0044 * (400e6 * 8.4 ^ 0.1 - 400e6 * 6.2 ^ 0.1)
    return 400e6 * 8.4 ^ 0.1
  }
  BEGIN {
    split("0.0079 0.0082 0.0111 0.0114 0.0200 0.0209", eps, " ")
    split("0 54 54 110 110 168", broken, " ")
    split("4.5 3 3 1 1 0", share, " ") # of 4.5
  }
  NR > 2 {
    k = NR - 2; want_b = broken[k] / 168; want_s = curve(eps[k]) * share[k] / 4.5; got_s = $cr / 1.0e-4
    printf "  eps %s: broken fraction %.6f (expected %.6f), stress %.6g Pa (expected %.6g)\n", eps[k], $cb, want_b, got_s, want_s
    if ($cb - want_b > 1e-9 || want_b - $cb > 1e-9) bad = 1
    if (want_s == 0 ? (got_s > 1 || got_s < -1) : ((got_s - want_s) / want_s > 0.02 || (want_s - got_s) / want_s > 0.02)) bad = 1
  }
  END { exit bad }' "$hist" || fail "energy failure: the bonds do not break at the work of G0"
pass "critical bond energy: the bonds of 3, 2 and 1 spacings break at the strains where their work reaches w_c"

# --- peri check: the sublayers and the plastic state's bytes per bond
run_peri check "$deck"
expect_status 0
expect_stdout_contains "plasticity   steel: 4 sublayers (W, s_y): (0.9444, 0.002) (0.0302, 0.0065) (0.0086, 0.0124) (0.0168, 0.0168)"
expect_stdout_contains "plastic state 32 bytes per directed bond (4 plastic stretches)"
pass "peri check lists the sublayers and 32 bytes per directed bond"

# --- bad input: file:line:column, exit 2
bad_deck() { # NAME PLASTICITY_LINES...: the bar with these plasticity lines
  local name=$1
  shift
  {
    printf 'dimension: 1\nmaterials:\n  steel:\n    model: pmb\n    density: 7800\n    youngs_modulus: 200e9\n'
    printf '    plasticity:\n'
    printf '      %s\n' "$@"
    printf 'discretization: {spacing: 0.01, m: 3, cross_section: 1.0e-4, fill: [{shape: interval, min: [0], max: [0.3]}]}\n'
    printf 'solver: {type: explicit, steps: 10}\noutput: {picture: false}\n'
  } >"$TMP/$name.yaml"
  echo "$TMP/$name.yaml"
}
d=$(bad_deck sum "weights: [0.9, 0.05]" "yield_stretches: [0.002, 0.004]")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:8:16: error: materials.steel.plasticity: the weights sum to 0.95, not 1 (within 0.001)"
d=$(bad_deck order "weights: [0.9, 0.1]" "yield_stretches: [0.002, 0.002]")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:9:32: error: materials.steel.plasticity: yield stretch 2 (0.002) must be positive and larger than the one before"
d=$(bad_deck slope "strains: [0.002, 0.004, 0.006]" "stresses: [400e6, 450e6, 440e6]")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:9:32: error: materials.steel.plasticity: point 3: the curve has a negative slope"
d=$(bad_deck line "strains: [0.002, 0.004]" "stresses: [300e6, 450e6]")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:9:18: error: materials.steel.plasticity: the first point (0.002, 3e+08) must lie on the elastic line"
d=$(bad_deck rate "weights: [1]" "yield_stretches: [0.002]" "cowper_symonds: {d: 0, p: 5}")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:10:27: error: materials.steel.plasticity.cowper_symonds: d must be a positive rate (1/s)"
d=$(bad_deck rate_qs "weights: [1]" "yield_stretches: [0.002]" "cowper_symonds: {d: 40.4, p: 5}")
run_peri check "$d" --set 'solver={type: adr, load_steps: 10}'
expect_status 2
expect_stderr_contains "$d:10:23: error: materials.steel.plasticity.cowper_symonds: rate dependence needs solver type explicit"
d=$(bad_deck fit_given "weights: [1]" "yield_stretches: [0.002]" "calibration: family")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:10:7: error: materials.steel.plasticity.calibration: only with a curve"
# Table 5.2's breakpoints as stresses on the power law: W = 0.944378, 0.030150, 0.008663,
# 0.016809 at eps0 (sigma/sigma0)^10 = 0.002, 0.0064946, 0.0123835, 0.0168454 (the chords,
# docs/plasticity.md section 1; they round to the printed 0.9444, 0.0301, 0.0087, 0.0168)
d=$(bad_deck law_stresses "power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}" \
  "stresses: [400e6, 450e6, 480e6, 495e6]")
run_peri check "$d"
expect_status 0
expect_stdout_contains "4 sublayers (W, s_y): (0.9444, 0.002) (0.0301, 0.006495) (0.0087, 0.01238) (0.0168, 0.01685)"
pass "power_law with stresses: Table 5.2's sublayers from the round stresses"
d=$(bad_deck law_low "power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}" \
  "stresses: [400e6, 380e6]")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:9:25: error: materials.steel.plasticity: stress 3.8e+08 is below the power law's yield_stress 4e+08"
d=$(bad_deck law_both "power_law: {yield_stress: 400e6, yield_strain: 0.002, exponent: 0.1}" \
  "stresses: [400e6, 450e6]" "strains: [0.002, 0.004]")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:8:18: error: materials.steel.plasticity: with power_law give the breakpoints as strains or as stresses (one of them)"
d=$(bad_deck fit_1d "strains: [0.002, 0.004]" "stresses: [400e6, 450e6]" "calibration: family")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:10:20: error: materials.steel.plasticity.calibration: family is for dimension 2 or 3"
run_peri check "$deck" --set solver.type=nlcg
expect_status 2
expect_stderr_contains "plasticity needs solver type explicit, adr or dynamic_relaxation"
run_peri check "$DECKS/plate_pmb.yaml" --set discretization.surface_correction=energy \
  --set 'materials.glass={model: pmb, density: 2440, youngs_modulus: 72.0e9, plasticity: {weights: [1], yield_stretches: [1.0e-4]}}'
expect_status 2
expect_stderr_contains "error: discretization.surface_correction: not available with plastic materials"
pass "bad plasticity input: file:line:column, exit 2"

# --- threads: a plastic fracture run is the same with 1 and 3 threads
plate="$DECKS/plate_pmb.yaml"
plastic_glass='materials.glass={model: pmb, density: 2440, youngs_modulus: 72.0e9, fracture_energy: 3.8, plasticity: {weights: [0.9, 0.1], yield_stretches: [5.0e-5, 2.0e-4]}}'
for threads in 1 3; do
  run_peri run "$plate" --quiet --threads "$threads" --output "$TMP/plate$threads" --set "$plastic_glass" \
    --set 'output.fields=[displacement, damage, yield_index, plastic_stretch]'
  expect_status 0
done
cmp -s "$TMP/plate1/history.csv" "$TMP/plate3/history.csv" || fail "history.csv differs between 1 and 3 threads"
for f in "$TMP"/plate1/*.vtu; do
  cmp -s "$f" "$TMP/plate3/$(basename "$f")" || fail "$(basename "$f") differs between 1 and 3 threads"
done
psi=$(tail -n 1 "$TMP/plate1/history.csv" | cut -d, -f"$(csv_column "$TMP/plate1/history.csv" mean_yield_index)")
awk -v p="$psi" 'BEGIN { exit !(p > 0.1 && p < 1) }' || fail "the plate barely yields (mean yield index $psi): the comparison tests little"
pass "threads 1 and 3: history.csv and frames bitwise equal (mean yield index $psi)"

# --- a plastic material below its first yield is the elastic one: the plastic force pass
# keeps the elastic loops' force for every node that has not yielded (docs/plasticity.md
# section 5), so the displacements are bitwise those of the elastic material
glass='materials.glass={model: pmb, density: 2440, youngs_modulus: 72.0e9'
for kind in elastic plastic; do
  layers=""
  [ "$kind" = plastic ] && layers=', plasticity: {weights: [0.9, 0.1], yield_stretches: [1.0e-2, 2.0e-2]}'
  run_peri run "$plate" --quiet --threads 2 --output "$TMP/below_$kind" --set "$glass$layers}" \
    --set 'output.fields=[displacement]'
  expect_status 0
done
n_frames=0
for f in "$TMP"/below_elastic/*.vtu; do
  cmp -s "$f" "$TMP/below_plastic/$(basename "$f")" || fail "$(basename "$f"): a plastic material that never yields differs from the elastic one"
  n_frames=$((n_frames + 1))
done
[ "$n_frames" -gt 1 ] || fail "no frames to compare"
pass "below its first yield the plastic material moves bitwise as the elastic one ($n_frames frames)"

# --- the LPS screen (docs/plasticity.md section 5): the LPS twin of the plate, no fracture.
# Below its first yield a plastic material moves bitwise as the elastic one (every node keeps
# the elastic loops' sums and force).
lps_plate="$DECKS/plate_lps.yaml"
lps_glass='materials.glass={model: lps, density: 2440, youngs_modulus: 72.0e9, poisson_ratio: 0.22'
for kind in elastic plastic; do
  layers=""
  [ "$kind" = plastic ] && layers=', plasticity: {weights: [0.9, 0.1], yield_stretches: [1.0e-2, 2.0e-2]}'
  run_peri run "$lps_plate" --quiet --threads 2 --output "$TMP/lps_below_$kind" --set "$lps_glass$layers}" \
    --set 'output.fields=[displacement]'
  expect_status 0
done
n_frames=0
for f in "$TMP"/lps_below_elastic/*.vtu; do
  cmp -s "$f" "$TMP/lps_below_plastic/$(basename "$f")" || fail "LPS: $(basename "$f"): a plastic material that never yields differs from the elastic one"
  n_frames=$((n_frames + 1))
done
[ "$n_frames" -gt 1 ] || fail "LPS: no frames to compare"
pass "LPS: below its first yield the plastic material moves bitwise as the elastic one ($n_frames frames)"

# The screened and unscreened paths agree where the plate yields in part: the same sublayers
# with a first layer of weight 1e-12 that yields at a stretch of 1e-12 send every loaded node
# through the plastic path (nothing is screened) and change the force by 1e-12 of itself, so
# the displacements agree to round-off (bound 1e-9 of the largest) and so do the yield indices
# of the real layers (the first-layer index counts the extra layer: compared through the plastic
# stretch instead, within 1e-9 of its largest value).
PY=""
for candidate in /usr/bin/python3 python3; do
  if command -v "$candidate" >/dev/null && "$candidate" -c 'import numpy' 2>/dev/null; then PY=$candidate; break; fi
done
if [[ -n "$PY" ]]; then
  for kind in screened unscreened; do
    layers='plasticity: {weights: [0.9, 0.1], yield_stretches: [5.0e-5, 2.0e-4]}'
    [ "$kind" = unscreened ] && layers='plasticity: {weights: [1.0e-12, 0.9, 0.1], yield_stretches: [1.0e-12, 5.0e-5, 2.0e-4]}'
    run_peri run "$lps_plate" --quiet --threads 2 --output "$TMP/lps_$kind" --set "$lps_glass, $layers}" \
      --set 'output.fields=[displacement, yield_index, plastic_stretch]'
    expect_status 0
  done
  read -r du dp psi_s psi_u <<<"$("$PY" - "$CLI_DIR/lib" "$TMP" <<'PYEOF'
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
from check_outputs import read_frame, read_pvd
t = sys.argv[2]
a, _ = read_frame(t + "/lps_screened", read_pvd(t + "/lps_screened", "plate_lps")[-1][1])
b, _ = read_frame(t + "/lps_unscreened", read_pvd(t + "/lps_unscreened", "plate_lps")[-1][1])
du = np.max(np.abs(a["displacement"] - b["displacement"])) / np.max(np.abs(a["displacement"]))
dp = np.max(np.abs(a["plastic_stretch"] - b["plastic_stretch"])) / np.max(np.abs(a["plastic_stretch"]))
print("%.3e %.3e %.4f %.4f" % (du, dp, np.mean(a["yield_index"]), np.mean(b["yield_index"])))
PYEOF
)"
  awk -v p="$psi_s" 'BEGIN { exit !(p > 0.01 && p < 0.9) }' || fail "LPS: the plate yields in no useful part (mean yield index $psi_s): the comparison tests little"
  awk -v p="$psi_u" 'BEGIN { exit !(p > 0.95) }' || fail "LPS: the extra layer left nodes unyielded (mean yield index $psi_u): not every node took the plastic path"
  awk -v a="$du" -v b="$dp" 'BEGIN { exit !(a < 1e-9 && b < 1e-9) }' || fail "LPS: screened and unscreened paths differ: displacement by $du, plastic stretch by $dp of the largest"
  pass "LPS: screened and unscreened paths agree (displacement $du, plastic stretch $dp of the largest; mean yield index $psi_s screened)"
else
  echo "SKIP (part): no python3 with numpy for the LPS screened/unscreened comparison"
fi

# --- the deviatoric yield rules (docs/plasticity.md sections 8 and 10): peri check, threads,
# bad input
block="$DECKS/plastic_block3d.yaml"
# rule_threads NAME [--set ...]: the block on 1 and 3 threads into $TMP/NAME1 and NAME3,
# history.csv and the VTU bitwise; prints the final mean yield index (asserted above 0.5)
rule_threads() {
  local name=$1 threads f psi
  shift
  for threads in 1 3; do
    run_peri run "$block" "$@" --quiet --threads "$threads" --output "$TMP/$name$threads"
    expect_status 0
  done
  cmp -s "$TMP/${name}1/history.csv" "$TMP/${name}3/history.csv" || fail "$name: history.csv differs between 1 and 3 threads"
  for f in "$TMP/${name}1"/*.vtu; do
    cmp -s "$f" "$TMP/${name}3/$(basename "$f")" || fail "$name: $(basename "$f") differs between 1 and 3 threads"
  done
  psi=$(tail -n 1 "$TMP/${name}1/history.csv" | cut -d, -f"$(csv_column "$TMP/${name}1/history.csv" mean_yield_index)")
  awk -v p="$psi" 'BEGIN { exit !(p > 0.5) }' || fail "$name: the block barely yields (mean yield index $psi)"
  echo "$psi"
}
run_peri check "$block"
expect_status 0
expect_stdout_contains "plasticity   steel: deviatoric yield rule, 4 sublayers (W, e_y): (0.9532, 0.001667)"
expect_stdout_contains "plastic state about 64 bytes per directed bond (4 plastic deviatoric stretches, the reverse bond's index, the plastic term, its reverse's and its own slot)"
psi=$(rule_threads deviatoric) || exit 1 # (a failure inside has said why)
d=$(bad_deck dev_pmb "strains: [0.002, 0.004]" "stresses: [400e6, 450e6]" "yield_rule: deviatoric")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:10:19: error: materials.steel.plasticity.yield_rule: deviatoric is a rule of the lps model"
sed 's|      yield_rule: deviatoric|&\n      critical_plastic_stretch: 0.01|' "$block" >"$TMP/dev_ductile.yaml"
run_peri check "$TMP/dev_ductile.yaml"
expect_status 2
expect_stderr_contains "$TMP/dev_ductile.yaml:16:7: error: materials.steel.plasticity.critical_plastic_stretch: not with yield_rule deviatoric"
pass "deviatoric rule: peri check (64 bytes per bond), threads 1 and 3 bitwise (mean yield index $psi), bad input exit 2"

# the tensor rule: its state per node in peri check, the same checks
tensor=(--set materials.steel.plasticity.yield_rule=deviatoric_tensor)
run_peri check "$block" "${tensor[@]}"
expect_status 0
expect_stdout_contains "plasticity   steel: deviatoric tensor yield rule, 4 sublayers (W, e_y): (0.9532, 0.001667)"
expect_stdout_contains "plastic state 628 bytes per node, none per bond (4 plastic tensors of 6 components"
psi_t=$(rule_threads tensor "${tensor[@]}") || exit 1
d=$(bad_deck ten_pmb "strains: [0.002, 0.004]" "stresses: [400e6, 450e6]" "yield_rule: deviatoric_tensor")
run_peri check "$d"
expect_status 2
expect_stderr_contains "$d:10:19: error: materials.steel.plasticity.yield_rule: deviatoric_tensor is a rule of the lps model"
sed 's|      yield_rule: deviatoric|&_tensor\n      cowper_symonds: {d: 40, p: 5}|' "$block" >"$TMP/ten_rate.yaml"
run_peri check "$TMP/ten_rate.yaml"
expect_status 2
expect_stderr_contains "$TMP/ten_rate.yaml:16:7: error: materials.steel.plasticity.cowper_symonds: not with yield_rule deviatoric_tensor"
pass "tensor rule: peri check (628 bytes per node, none per bond), threads 1 and 3 bitwise (mean yield index $psi_t), bad input exit 2"

echo "PASS: $CLI_NAME"
