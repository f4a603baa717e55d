#!/usr/bin/env bash
# Two fragments of the fragmenting cylinder colliding (examples/cylinder_fragments_collision.yaml,
# docs/contact.md "Bodies"): two axial strips of the steel tube, |y| <= 6 mm, from opposite
# sides (x > 0 and x < 0), the left one raised by 50 mm, thrown at each other at -200 and
# +100 m/s. The deck as it is (dx = 2 mm, 856 steps, a few seconds).
#  - momentum: only the bodies' forces on each other act, so the total momentum stays
#    m (-200 + 100) (both strips have the same mass m) to 1e-12 of m * 300 m/s at every row,
#    and the z momentum (the left strip's axial profile is odd about its middle) at 0;
#  - no force before they touch: each strip keeps its initial momentum exactly until the
#    first row where two nodes are closer than their contact distance (short_range_min_ratio
#    < 1), and that row comes when rigid motion brings the nearest nodes within the contact
#    distance 1.35 dx: the strips' inner nodes lie between x = sqrt(0.02^2 - 0.006^2) and
#    0.02 + dx from the axis (the inner radius, the strip's half width, a grid within dx of the
#    surface), so the gap G in [0.03816, 0.044] m closes to 1.35 dx = 0.0027 m at 300 m/s
#    between 118 and 138 us (the row's time may trail the contact by one history interval);
#  - energy: the collision and the cracks take energy, none is made: KE + SE at the end at
#    most the initial kinetic energy, to the integrator's 1%; and the strips did collide: the
#    right strip's x momentum changed by at least a tenth of m * 300 m/s.
# Usage: bash tests/cli/fragments_collision.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=examples/cylinder_fragments_collision.yaml
OMP_NUM_THREADS=2 run_peri run "$deck" --quiet --output "$TMP/frag" --set output.frames=0 --set output.picture=false
expect_status 0
h="$TMP/frag/history.csv"
for name in momentum_x momentum_z mass_right mass_left momentum_right_x momentum_left_x \
            short_range_min_ratio kinetic_energy strain_energy time; do
  [ -n "$(csv_column "$h" "$name")" ] || fail "history.csv lacks the column $name"
done
col() { csv_column "$h" "$1"; }

awk -F, -v p="$(col momentum_x)" -v pz="$(col momentum_z)" -v mr="$(col mass_right)" -v ml="$(col mass_left)" '
  function abs(v) { return v < 0 ? -v : v }
  NR == 2 { m = $mr; if (abs($mr - $ml) > 1e-12 * m) { print "masses differ: " $mr ", " $ml; bad = 1 }
            p0 = m * (-200 + 100); scale = m * 300 }
  NR > 1 { if (abs($p - p0) > 1e-12 * scale || abs($pz) > 1e-12 * scale) { bad = 1; print "row " NR ": " $p ", " $pz } }
  END { exit bad }' "$h" || fail "the total momentum is not m(-200 + 100), 0 along z, to round-off"
pass "momentum conserved to round-off (1e-12 of m * 300 m/s)"

awk -F, -v t="$(col time)" -v r="$(col short_range_min_ratio)" -v pr="$(col momentum_right_x)" \
    -v pl="$(col momentum_left_x)" -v mr="$(col mass_right)" '
  function abs(v) { return v < 0 ? -v : v }
  NR == 2 { m = $mr }
  NR > 1 && !touched && $r < 1 { touched = 1; tc = $t }
  NR > 1 && !touched { if (abs($pr + 200 * m) > 1e-12 * 300 * m || abs($pl - 100 * m) > 1e-12 * 300 * m) { bad = 1; print "row " NR ": a force before contact" } }
  NR > 1 { dt = $t - last; last = $t }
  END {
    if (!touched) { print "the strips never touched"; exit 1 }
    if (tc < 118e-6 || tc > 138e-6 + dt) { printf "first contact at %.4g s, expected 118-138 us\n", tc; exit 1 }
    exit bad }' "$h" || fail "the strips interact before they touch, or touch at the wrong time"
pass "no force between the strips before contact, first contact within 118-138 us"

awk -F, -v ke="$(col kinetic_energy)" -v se="$(col strain_energy)" -v pr="$(col momentum_right_x)" -v mr="$(col mass_right)" '
  function abs(v) { return v < 0 ? -v : v }
  NR == 2 { e0 = $ke; m = $mr; p0 = $pr }
  NR > 1 { e = $ke + $se; p = $pr }
  END {
    if (e > 1.01 * e0) { printf "energy grew: %.6g J from %.6g J\n", e, e0; exit 1 }
    if (abs(p - p0) < 0.1 * m * 300) { printf "the right strip lost only %.3g of its momentum\n", p - p0; exit 1 } }' "$h" \
  || fail "energy or momentum exchange of the collision"
pass "the collision exchanges momentum and creates no energy"
