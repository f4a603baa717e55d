#!/usr/bin/env bash
# The interface traction and the interface strength `normal_strength` (docs/thin_films.md §6):
# 1. Two layers of the same LPS constants pulled apart in plane strain through fictitious
#    layers on all sides (tests/cli/decks/interface_strength.yaml), the homogeneous uniaxial
#    stress sigma_yy = E/(1 - nu^2) t: max_interface_traction within 10% of it (the lattice
#    sum of the bond forces across the interface at delta = 3 dx); with normal_strength
#    3.9 MPa, between sigma_yy at t = 0.003 and 0.004, no interface bond is broken at
#    t = 0.003 and interface bonds break at t = 0.004.
# 2. The wrinkling film of examples/thin_film_wrinkling.yaml (E_f/E_s = 100, nu_s = 0.33) with a
#    sine imperfection of 0.01 h at Mei's lambda* (a random one kinks the film column by
#    column, and the kinks load the interface before it wrinkles), strain 0.020 at the first
#    load step, then 0.001 a step to 0.033: the wrinkling onset lies within 10% of Mei's
#    eps*_cr (the minimum of Eq. 4.3), and, for interface strengths sigma_int = 120, 160 and
#    200 MPa, the first strain at which the interface traction reaches sigma_int (where
#    normal_strength breaks the interface) lies within 15% of Mei's Eq. 4.7,
#    eps**_cr = eps*_cr + ((3 - 4 nu_s)/(4 (1 - nu_s)^2) sigma_int/Es_bar)^2.
# 3. normal_strength not positive, or on a material with itself: exit 2 at the key.
# Usage: bash tests/cli/thin_film_delamination.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
layers=tests/cli/decks/interface_strength.yaml

# 1. the traction of a homogeneous state, and the strength
run_peri run "$layers" --quiet --output "$TMP/layers"
expect_status 0
h="$TMP/layers/history.csv"
cb=$(csv_column "$h" broken_interface_bonds)
ct=$(csv_column "$h" max_interface_traction)
# rows: line k + 2 is t = 0.001 k
read -r b3 q3 <<<"$(sed -n 5p "$h" | awk -F, -v b="$cb" -v q="$ct" '{ print $b, $q }')"
read -r b4 <<<"$(sed -n 6p "$h" | awk -F, -v b="$cb" '{ print $b }')"
awk -v q="$q3" 'BEGIN { s = 1e9 / (1 - 0.25^2) * 0.003; exit !(q > 0.9 * s && q < 1.1 * s) }' ||
  fail "max_interface_traction $q3 Pa at t = 0.003: not within 10% of E/(1 - nu^2) t = 3.2 MPa"
[[ "$b3" == 0 ]] || fail "interface bonds broken at t = 0.003 ($b3), below the strength"
[[ "$b4" -gt 0 ]] || fail "no interface bond broken at t = 0.004, above the strength"
pass "layers pulled apart: traction $q3 Pa at t = 0.003 (E/(1 - nu^2) t = 3.2e6), intact; $b4 interface bonds broken at t = 0.004"

# 2. the wrinkling film's traction against Mei's Eq. 4.7
nu=0.33
read -r eps_cr lam <<<"$(awk -v nus="$nu" 'BEGIN {
  r = (2e9 / (1 - nus^2)) / (200e9 / (1 - 0.33^2)); h = 2e-3; pi = atan2(0, -1)
  a = ((1 - 2 * nus) / (1 - nus))^2; best = 1e9
  for (kh = 0.05; kh < 1; kh += 1e-5) {                        # Mei, Eq. 4.3
    c = kh^2 / 12 + r / (2 * kh) / (1 - 0.5 * a / (r / kh + 2))
    if (c < best) { best = c; khmin = kh }
  }
  printf "%.6f %.6f\n", best, 2 * pi * h / khmin }')"
eps="(0.020*min(t,1)+0.001*max(t-1,0))"
y="$eps*$nu/(1-$nu)*(y+0.02)"
run_peri run examples/thin_film_wrinkling.yaml --threads 2 --output "$TMP/film" \
  --set "imperfection={region: film, amplitude: 2.0e-5, mode: sine, wavelength: $lam}" \
  --set materials.substrate.poisson_ratio="$nu" \
  --set "boundary_conditions.0.x=-$eps*x" --set "boundary_conditions.1.x=-$eps*x" \
  --set "boundary_conditions.2.x=-$eps*x" --set "boundary_conditions.0.y=$y" \
  --set "boundary_conditions.1.y=$y" --set "boundary_conditions.2.y=$y" \
  --set solver.end_time=14 --set solver.load_steps=14 --set output.frames=0 --set output.picture=false
expect_status 0
t_onset=$(awk -F, '$1 == "wrinkling" { print $2 }' "$TMP/film/wrinkling.csv")
[[ -n "$t_onset" ]] || fail "no wrinkling onset in wrinkling.csv"
ct=$(csv_column "$TMP/film/history.csv" max_interface_traction)
awk -F, -v q="$ct" -v t1="$t_onset" -v ecr="$eps_cr" -v nus="$nu" '
  function strain(t) { return 0.020 * (t < 1 ? t : 1) + 0.001 * (t > 1 ? t - 1 : 0) }
  NR > 1 { n++; e[n] = strain($1); trac[n] = $q }
  END {
    e1 = strain(t1)
    if (!(e1 > 0.9 * ecr && e1 < 1.1 * ecr)) { printf "wrinkling onset %.4f: not within 10%% of %.5f\n", e1, ecr; bad = 1 }
    else printf "wrinkling onset %.4f, Mei %.5f\n", e1, ecr
    Es = 2e9 / (1 - nus^2)
    split("1.2e8 1.6e8 2.0e8", sig, " ")
    for (s = 1; s <= 3; s++) {
      delam = ecr + ((3 - 4 * nus) / (4 * (1 - nus)^2) * sig[s] / Es)^2   # Mei, Eq. 4.7
      reach = -1
      for (k = 1; k <= n && reach < 0; k++) if (trac[k] >= sig[s]) reach = e[k]
      ok = reach > 0.85 * delam && reach < 1.15 * delam
      printf "sigma_int %g Pa: traction reaches it at strain %.4f, Eq. 4.7 %.5f%s\n", sig[s], reach, delam, ok ? "" : " (not within 15%)"
      if (!ok) bad = 1
    }
    exit bad }' "$TMP/film/history.csv" >"$TMP/eq47.txt" || fail "$(cat "$TMP/eq47.txt")"
pass "$(tr '\n' ';' <"$TMP/eq47.txt")"

# 3. errors at the key
run_peri check "$layers" --set "interfaces=[{materials: [a, b], normal_strength: -1}]"
expect_status 2
expect_stderr_matches "--set:1:[0-9]+: .*normal_strength must be a positive number"
run_peri check "$layers" --set "interfaces=[{materials: [a, a], normal_strength: 1.0e6}]"
expect_status 2
expect_stderr_contains "normal_strength needs two different materials"
pass "normal_strength: errors at the key"
run_peri check "$layers" --set "solver={type: explicit, steps: 10}"
expect_status 2
expect_stderr_contains "normal_strength needs a quasi-static solver"
pass "normal_strength with the explicit solver: exit 2"
