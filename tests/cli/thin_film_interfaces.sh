#!/usr/bin/env bash
# Interfaces between materials and a film's deflection profile (docs/thin_films.md):
# - a 1D PMB bar of two materials a | b (same E = 200 GPa, dx = 0.01, delta = 3 dx, the
#   partial-volume ramp reaching delta + dx/2) at a uniform strain s = 1e-3:
#   * the `interface` field marks the 3 nodes on each side whose family reaches across
#     (nodes at the cell centres x = 0.475 ... 0.525), no other;
#   * max_interface_stress = the PMB pair force c s (c = 2E/(A delta^2)) times V^2 over the
#     cross-section A = 2 E s dx^2 / delta^2 = 44.44 MPa within 2% (the strain is uniform to
#     2% with fictitious layers, tests/cli/fictitious_layer.sh);
#   * the region energies of the two sides add up to strain_energy;
#   * with the pair's critical stretch 2e-3 > s no bond breaks; with 5e-4 < s every bond that
#     crosses breaks: the 6 pairs within the cutoff, 12 directed bonds, and no other bond;
# - a 2D film every node of which is given y = 1e-4 sin(2 pi x / 0.0233) plus a tilt (4.3 waves
#   in the window, not a whole number): wrinkle_amplitude = 1e-4 within 2% and
#   wrinkle_wavelength = 0.0233 within 1%;
# - bad keys exit 2 at the key: `wrinkles: all`, an unknown region, a sine imperfection
#   without wavelength.
# Usage: bash tests/cli/thin_film_interfaces.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"
bar="$DECKS/interface_bar.yaml"
profile="$DECKS/wrinkle_profile.yaml"

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

# last VALUE of history.csv column NAME in DIR
last() {
  local col
  col=$(csv_column "$1/history.csv" "$2")
  [[ -n "$col" ]] || { echo "missing"; return; }
  tail -n 1 "$1/history.csv" | cut -d, -f"$col"
}

run_peri run "$bar" --quiet --output "$TMP/bar"
expect_status 0
flagged=$("$PY" - "$CLI_DIR/lib" "$TMP/bar" <<'PYEOF'
import sys
sys.path.insert(0, sys.argv[1])
import numpy as np
from check_outputs import read_frame, read_pvd
frames = read_pvd(sys.argv[2], "interface_bar")
a, _ = read_frame(sys.argv[2], frames[-1][1])
x = a["reference_position"][:, 0]
print(" ".join("%.3f" % v for v in np.sort(x[a["interface"] == 1])))
PYEOF
)
[[ "$flagged" == "0.475 0.485 0.495 0.505 0.515 0.525" ]] || fail "interface nodes at x = '$flagged', not 0.475 ... 0.525"
stress=$(last "$TMP/bar" max_interface_stress)
awk -v s="$stress" 'BEGIN { e = 2 * 200e9 * 1e-3 * 0.01^2 / 0.03^2; exit !(s > 0.98 * e && s < 1.02 * e) }' ||
  fail "max_interface_stress $stress Pa, not 2 E s dx^2/delta^2 = 4.444e7 Pa within 2%"
total=$(last "$TMP/bar" strain_energy)
a_side=$(last "$TMP/bar" strain_energy_a_side)
b_side=$(last "$TMP/bar" strain_energy_b_side)
awk -v t="$total" -v a="$a_side" -v b="$b_side" 'BEGIN { d = a + b - t; exit !(t > 0 && (d < 0 ? -d : d) < 1e-9 * t) }' ||
  fail "the region energies $a_side + $b_side J do not add up to strain_energy $total J"
[[ "$(last "$TMP/bar" broken_interface_bonds)" == 0 ]] || fail "interface bonds broke below their critical stretch"
pass "interface nodes x = 0.475 ... 0.525; sigma_int $stress Pa = 2 E s dx^2/delta^2 within 2%; region energies add up to $total J; none broken at s0 = 2e-3"

run_peri run "$bar" --quiet --output "$TMP/weak" --set interfaces.0.critical_stretch=5e-4
expect_status 0
broken=$(last "$TMP/weak" broken_interface_bonds)
fraction=$(last "$TMP/weak" broken_bond_fraction)
[[ "$broken" == 12 ]] || fail "$broken broken interface bonds at s0 = 5e-4 < s, not the 12 directed bonds across"
awk -v f="$fraction" 'BEGIN { exit !(f * 624 > 11.99 && f * 624 < 12.01) }' || fail "broken bonds $fraction x 624 beyond the 12 interface bonds"
[[ "$(last "$TMP/weak" max_interface_stress)" == 0 ]] || fail "max_interface_stress is not 0 with every interface bond broken"
pass "interface critical stretch 5e-4 < s: the 12 directed bonds across break, no other"

run_peri run "$profile" --quiet --output "$TMP/profile"
expect_status 0
amplitude=$(last "$TMP/profile" wrinkle_amplitude)
wavelength=$(last "$TMP/profile" wrinkle_wavelength)
awk -v a="$amplitude" -v l="$wavelength" 'BEGIN { exit !(a > 0.98e-4 && a < 1.02e-4 && l > 0.99 * 0.0233 && l < 1.01 * 0.0233) }' ||
  fail "prescribed sine 1e-4 m, 23.3 mm: wrinkle_amplitude $amplitude, wrinkle_wavelength $wavelength"
pass "prescribed sine: amplitude $amplitude m (1e-4 within 2%), wavelength $wavelength m (0.0233 within 1%)"

run_peri check "$profile" --set output.wrinkles=all
expect_status 2
expect_stderr_contains "wrinkles"
run_peri check "$profile" --set output.wrinkles=flim
expect_status 2
expect_stderr_contains "unknown region 'flim'; did you mean 'film'?"
run_peri check "$profile" --set "imperfection={region: film, amplitude: 1e-6, mode: sine}"
expect_status 2
expect_stderr_contains "wavelength"
run_peri check "$profile" --set "imperfection={region: film, amplitude: -1e-6}"
expect_status 2
expect_stderr_contains "amplitude"
pass "bad wrinkles and imperfection keys: exit 2 at the key"
