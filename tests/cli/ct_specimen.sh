#!/usr/bin/env bash
# The compact tension specimen of examples/ct_specimen.yaml (docs/plasticity.md §7) at the
# coarse spacing 1.25 mm (a = 20 spacings):
#  - elastic, no breaking, one ADR load step: J over the three rings equals the handbook energy
#    release rate G = K^2/E' (plane strain, E' = E/(1 - nu^2)) with the ASTM E399 stress
#    intensity of the pin-loaded CT specimen,
#      K = P/(B sqrt(W)) f(a/W),
#      f(r) = (2 + r)/(1 - r)^1.5 (0.886 + 4.64 r - 13.32 r^2 + 14.72 r^3 - 5.6 r^4)
#    (ASTM E399-20a, A4.5.3: within 0.5% for 0.2 <= a/W <= 1), P the pins' force, within 5%;
#  - the example's ductile run (sublayers, critical plastic stretch) grows its crack, and J
#    rises with the crack extension (a rising J-R curve: the plastic zone that the growing tip
#    leaves behind dissipates work): J over the largest ring at 4 to 6 mm of growth is at least
#    1.1 times J at the first spacing of growth (an elastic-brittle specimen, fracture_energy
#    1e5 J/m^2 and no sublayers, gives 1.05: a flat R-curve); the run writes the J-R plot.
# Usage: bash tests/cli/ct_specimen.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=examples/ct_specimen.yaml
coarse='discretization.spacing=1.25e-3'

# --- elastic: J against the ASTM E399 K
run_peri run "$deck" --quiet --threads 2 --output "$TMP/elastic" --set "$coarse" \
  --set 'materials.steel={model: lps, density: 8050, youngs_modulus: 210e9, poisson_ratio: 0.3}' \
  --set 'solver={type: adr, end_time: 1, load_steps: 1, breaking: false}' \
  --set 'tools.0.position=[0, "0.01375 + 1.5e-3*t"]' --set 'tools.1.position=[0, "-0.01375 - 1.5e-3*t"]' \
  --set 'output={picture: false}'
expect_status 0
hist="$TMP/elastic/history.csv"
cp=$(csv_column "$hist" tool_top_pin_force_y)
cq=$(csv_column "$hist" tool_bottom_pin_force_y)
c1=$(csv_column "$hist" j_integral_1)
c3=$(csv_column "$hist" j_integral_3)
awk -F, -v cp="$cp" -v cq="$cq" -v c1="$c1" -v c3="$c3" '
  END {
    W = 0.05; r = 0.5; B = 1.0e-3; E = 210e9; nu = 0.3
    P = -$cp; Pq = $cq
    f = (2 + r) / (1 - r)^1.5 * (0.886 + 4.64*r - 13.32*r^2 + 14.72*r^3 - 5.6*r^4)
    K = P / (B * sqrt(W)) * f
    G = K * K * (1 - nu * nu) / E
    printf "  P = %.1f N (bottom pin %.1f N), K = %.4g Pa m^0.5, G = %.1f J/m^2\n", P, Pq, K, G
    if (!(P > 0) || (P - Pq) > 1e-6 * P || (Pq - P) > 1e-6 * P) { print "  the pins do not carry equal loads"; bad = 1 }
    for (c = c1; c <= c3; ++c) {
      printf "  J_%d = %.1f J/m^2 (%+.2f%%)\n", c - c1 + 1, $c, 100 * ($c / G - 1)
      if (!($c / G - 1 < 0.05 && 1 - $c / G < 0.05)) bad = 1
    }
    exit bad
  }' "$hist" || fail "J of the elastic CT specimen is not the ASTM E399 K^2/E' within 5%"
pass "elastic CT specimen: J = K^2/E' of ASTM E399 within 5% over three rings"

# --- ductile crack growth: a rising J-R curve
run_peri run "$deck" --quiet --threads 2 --output "$TMP/ductile" --set "$coarse" \
  --set solver.end_time=1.8e-3 --set output.frames=0 --set output.history_every=25 --set output.picture=false
expect_status 0
hist="$TMP/ductile/history.csv"
cj=$(csv_column "$hist" j_integral_3)
ca=$(csv_column "$hist" crack_extension)
awk -F, -v cj="$cj" -v ca="$ca" '
  NR > 1 && $ca >= 1.25e-3 && j_first == "" { j_first = $cj; a_first = $ca }
  NR > 1 && $ca >= 4e-3 && $ca <= 6e-3 { j_later = $cj; a_later = $ca }
  END {
    if (j_first == "" || j_later == "") { printf "  the crack did not grow to 4-6 mm (last extension %g m)\n", $ca; exit 1 }
    printf "  J = %.4g J/m^2 at extension %g m, %.4g J/m^2 at %g m (ratio %.3f)\n", j_first, a_first, j_later, a_later, j_later / j_first
    exit !(j_first > 0 && j_later >= 1.1 * j_first)
  }' "$hist" || fail "J does not rise with the crack extension"
expect_nonempty_file "$TMP/ductile/j_integral_3_vs_crack_extension.png"
pass "ductile CT specimen: the crack grows and J rises with it; J-R plot written"

echo "PASS: $CLI_NAME"
