#!/usr/bin/env bash
# Wrinkling of a stiff film on a compliant substrate (docs/thin_films.md §5): the coarse
# examples/thin_film_wrinkling.yaml (E_f/E_s = 100, nu_f = 0.33, h = 2 mm = 2 dx,
# imperfection 0.05 h) at the two ends of the substrate's Poisson ratios of the study,
# nu_s = 0 and 0.45. The applied strain is 0.020 at the first load step, then rises by
# 0.001 a step to 0.031 (the pseudo-time t counts the steps: eps = 0.020 min(t, 1) +
# 0.001 max(t - 1, 0)), which brackets Mei's onset at both:
# - the onset of wrinkling (wrinkling.csv, the first local maximum of the film's energy rate)
#   lies within 10% of Mei's eps*_cr, the minimum over kh of Ebrahimi 2020 Eq. 4.3
#   (computed here by a scan of kh from the moduli; the seed prints its closed form, Eq. 4.5,
#   with the exponent +2/3 where Eq. 4.3 gives -2/3: docs/thin_films.md §5);
# - the wrinkle wavelength one load step past it lies within 10% of Mei's lambda* (Eq. 4.4);
# - wrinkling_energy.png is written and the summary names the onset;
# nu_s = 0 by `peri run` (wrinkling.csv and history.csv), nu_s = 0.45 by `peri sweep` and its
# film quantities (wrinkling_onset, wrinkle_wavelength_at_onset, and film_regime = 1:
# wrinkling only, as the deck does not break bonds; docs/thin_films.md §8).
# Usage: bash tests/cli/thin_film_wrinkling.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

# mei NU T WAVELENGTH: the onset at pseudo-time T and the wavelength against Mei (10%)
mei() {
  local nu=$1 t=$2 wavelength=$3
  awk -v t="$t" -v l="$wavelength" -v nus="$nu" 'BEGIN {
    e = 0.020 * (t < 1 ? t : 1) + 0.001 * (t > 1 ? t - 1 : 0)   # the applied strain at t
    r = (2e9 / (1 - nus^2)) / (200e9 / (1 - 0.33^2)); h = 2e-3; pi = atan2(0, -1)
    a = ((1 - 2 * nus) / (1 - nus))^2
    best = 1e9
    for (kh = 0.05; kh < 1; kh += 1e-5) {                      # Mei, Eq. 4.3
      c = kh^2 / 12 + r / (2 * kh) / (1 - 0.5 * a / (r / kh + 2))
      if (c < best) { best = c; khmin = kh }
    }
    lam = 2 * pi * h / khmin
    g = 1 - a / 4
    lam44 = 2 * pi * h * (1 / (3 * r))^(1 / 3) * g^(1 / 3)     # Mei, Eq. 4.4
    printf "eps*_cr %.5f, lambda* %.5f m (Eq. 4.4: %.5f m); PD onset strain %.4f\n", best, lam, lam44, e
    exit !(e > 0.9 * best && e < 1.1 * best && l > 0.9 * lam && l < 1.1 * lam && l > 0.9 * lam44 && l < 1.1 * lam44) }' \
    >"$TMP/mei.txt" ||
    fail "nu_s = $nu: onset at t = $t, wavelength $wavelength m: not within 10% of Mei's $(cat "$TMP/mei.txt")"
}

# the deck at nu_s: the strain of the pseudo-time and each layer's Poisson expansion
film_sets() {
  local nu=$1 eps="(0.020*min(t,1)+0.001*max(t-1,0))"
  local y="$eps*$nu/(1-$nu)*(y+0.02)"
  sets=(--set materials.substrate.poisson_ratio="$nu"
    --set "boundary_conditions.0.x=-$eps*x" --set "boundary_conditions.1.x=-$eps*x"
    --set "boundary_conditions.2.x=-$eps*x" --set "boundary_conditions.0.y=$y"
    --set "boundary_conditions.1.y=$y" --set "boundary_conditions.2.y=$y"
    --set solver.end_time=12 --set solver.load_steps=12 --set output.frames=0 --set output.picture=false)
}

nu=0
film_sets "$nu"
run_peri run examples/thin_film_wrinkling.yaml --threads 2 --output "$TMP/film_$nu" "${sets[@]}"
expect_status 0
expect_stdout_contains "onset        wrinkling at t = "
expect_nonempty_file "$TMP/film_$nu/wrinkling_energy.png"
expect_nonempty_file "$TMP/film_$nu/wrinkling.csv"
read -r t step <<<"$(awk -F, '$1 == "wrinkling" { print $2, $3 }' "$TMP/film_$nu/wrinkling.csv")"
[[ -n "${step:-}" ]] || fail "nu_s = $nu: no wrinkling onset in wrinkling.csv: $(cat "$TMP/film_$nu/wrinkling.csv")"
col=$(csv_column "$TMP/film_$nu/history.csv" wrinkle_wavelength)
# history.csv row of load step k is line k + 2 (header, step 0)
wavelength=$(sed -n "$((step + 3))p" "$TMP/film_$nu/history.csv" | cut -d, -f"$col")
mei "$nu" "$t" "$wavelength"
pass "nu_s = $nu (peri run): wavelength $wavelength m, $(cat "$TMP/mei.txt"): within 10%"

nu=0.45
film_sets "$nu"
run_peri sweep examples/thin_film_wrinkling.yaml --threads 2 "${sets[@]}" --set-list materials.substrate.poisson_ratio="$nu" \
  --quantity wrinkling_onset --quantity wrinkle_wavelength_at_onset --quantity film_regime --quantity delamination_onset
expect_status 0
# the table's row: | nu | onset | wavelength | regime | delamination | seconds |
read -r t wavelength regime delamination <<<"$(awk -F'|' 'NR == 3 { print $3, $4, $5, $6 }' "$RUN_STDOUT")"
[[ "${regime:-}" == 1 && "${delamination:-}" == nan ]] ||
  fail "nu_s = $nu (peri sweep): film_regime '${regime:-}', delamination_onset '${delamination:-}', not 1 (wrinkling only) and nan: $(cat "$RUN_STDOUT")"
mei "$nu" "$t" "$wavelength"
pass "nu_s = $nu (peri sweep): wavelength $wavelength m, $(cat "$TMP/mei.txt"): within 10%; film_regime 1"
