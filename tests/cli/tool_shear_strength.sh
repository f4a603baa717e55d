#!/usr/bin/env bash
# Friction with an interfacial shear strength (docs/contact.md §5, "Friction with a shear
# strength"): Bowden and Tabor's F_t = tau0 A + mu P. A rigid cylinder is loaded to P = 160 N
# on an elastic half-plane (2D plane strain, h = 2 mm) and slid under that load with
# tau0 = 2 MPa and mu = 0.1 (tests/cli/decks/tool_shear_strength.yaml).
#  - the law: on every sliding row F_t = tau0 A + mu P with A the contact area of history.csv
#    (the faces V / dx = dx h of the nodes in contact), but for the nodes at the edge of the
#    contact whose pressure is below tau0 (their shear is capped by it): at most the two edge
#    nodes' faces, so tau0 (A - 2 dx h) + mu P <= F_t <= tau0 A + mu P, each bound to 1% (the
#    nodes' normals tilt by at most b/R = 0.03 from the slide, a change of order (b/R)^2, and
#    a frictionless slide leaves 2e-5 P: tools.sh).
#  - the area is Hertz's: b = sqrt(4 P R / (pi h E*)), E* = E / (1 - nu^2) (Johnson, Contact
#    Mechanics, eq. 4.45, rigid cylinder), 3.09 mm. A node carries the pressure of its whole
#    cell, so it touches when its cell reaches into the contact: over the four lattice phases
#    of the slide the nodes in contact cover 2 b + dx, A = (2 b + dx) h. Mean of the sliding
#    rows within 5% (the 3D Hertz test finds force and depth within 2-4% at this contact size).
#  - hence F_t = tau0 (2 b + dx) h + mu P within 5% on the mean.
#  - a negative shear strength is refused with exit 2 at the key.
# Usage: bash tests/cli/tool_shear_strength.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=tests/cli/decks/tool_shear_strength.yaml
run_peri run "$deck" --output "$TMP/slide"
expect_status 0
h="$TMP/slide/history.csv"
col() { csv_column "$h" "$1"; }
[ -n "$(col tool_tip_contact_area)" ] || fail "history.csv lacks the column tool_tip_contact_area"
awk -F, -v P="$(col tool_tip_normal_force)" -v ft="$(col tool_tip_tangential_force)" -v A="$(col tool_tip_contact_area)" '
  function abs(v) { return v < 0 ? -v : v }
  BEGIN { tau0 = 2e6; mu = 0.1; R = 0.1; E = 1e9; nu = 0.25; h = 2e-3; dx = 1e-3; pi = atan2(0, -1)
          b = sqrt(4 * 160 * R / (pi * h * E / (1 - nu * nu))); hertz = (2 * b + dx) * h }
  NR > 1 && $1 > 0.3 {
    n++; law = tau0 * $A + mu * $P; low = tau0 * ($A - 2 * dx * h) + mu * $P; sa += $A; sf += $ft; sp += $P
    printf "t %g: P %.6g N, F_t %.6g N, tau0 A + mu P %.6g N (without two edge faces %.6g), A %.4g m^2\n", $1, $P, $ft, law, low, $A
    if ($ft > 1.01 * law || $ft < 0.99 * low) { print "  F_t is not tau0 A + mu P"; bad = 1 } }
  END { if (n != 4) { print n " sliding rows, not 4"; exit 1 }
        a = sa / n; f = sf / n; want = tau0 * hertz + mu * sp / n
        printf "b %.4g m; mean A %.5g m^2 against (2b + dx) h = %.5g (2bh = %.5g); mean F_t %.5g N against %.5g\n", b, a, hertz, 2 * b * h, f, want
        if (abs(a - hertz) > 0.05 * hertz) { print "the contact area is not Hertz'"'"'s"; bad = 1 }
        if (abs(f - want) > 0.05 * want) { print "F_t is not tau0 A_Hertz + mu P"; bad = 1 }
        exit bad }' "$h" \
  || fail "friction with a shear strength: F_t = tau0 A + mu P, A from Hertz"
pass "shear strength: F_t = tau0 A + mu P on every sliding row, A = Hertz's (2b + dx) h"

sed -e 's/shear_strength: 2.0e6 /shear_strength: -1 /' "$deck" > "$TMP/negative.yaml"
run_peri check "$TMP/negative.yaml"
expect_status 2
expect_stderr_contains "negative.yaml:"
expect_stderr_contains "shear_strength"
pass "a negative shear strength: exit 2"
