#!/usr/bin/env bash
# Two identical elastic spheres in a head-on collision (docs/contact.md "Bodies"):
# two bodies of 280 nodes at +-5 m/s, meeting through the short-range forces only.
#  - momentum: the pair's forces are opposite, so the total momentum stays 0 to round-off
#    (|sum| <= 1e-12 m v at every row, from the body sums and from momentum_x);
#  - restitution e = (v_right - v_left)/10 m/s after the rebound: at most 1 (energy) and at
#    least 0.9. Hertz's quasi-static impact gives e -> 1 for v << c; what is lost goes into
#    elastic vibrations of the spheres, of order (v/c)^(3/5) of the energy (Hunter 1957:
#    1.04 (v/c0)^(3/5) = 2.5% at v/c0 = 10/5064 for a half-space). 0.9 allows 19% for a
#    coarse contact of a few nodes;
#  - the translational energy lost is found in the spheres: KE + SE - (1/2)(m_l v_l^2 + m_r v_r^2)
#    = (1 - e^2) KE0 to 1% of KE0 (the explicit integrator's energy error);
#  - the per-body sums agree with the whole: mean velocities +-5 m/s at t = 0 (the initial
#    conditions) and kinetic_energy_left + kinetic_energy_right = kinetic_energy at every
#    row, to 1e-12 and 1e-9 (the 10 digits of history.csv); the body field is written,
#    and 1 and 2 threads give the same history.csv bit for bit.
# Usage: bash tests/cli/two_spheres.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=tests/cli/decks/two_spheres_collision.yaml
OMP_NUM_THREADS=2 run_peri run "$deck" --output "$TMP/two"
expect_status 0
h="$TMP/two/history.csv"
for name in momentum_x mass_left momentum_left_x momentum_right_x kinetic_energy mass_right \
            strain_energy mean_velocity_left_x mean_velocity_right_x kinetic_energy_left damaged_mass_left detached_mass_left; do
  [ -n "$(csv_column "$h" "$name")" ] || fail "history.csv lacks the column $name"
done
col() { csv_column "$h" "$1"; }

awk -F, -v p="$(col momentum_x)" -v pl="$(col momentum_left_x)" -v pr="$(col momentum_right_x)" '
  function abs(v) { return v < 0 ? -v : v }
  NR == 2 { scale = abs($pl) }
  NR > 1 { if (abs($p) > 1e-12 * scale || abs($pl + $pr) > 1e-12 * scale) { bad = 1; print "row " NR ": " $p ", " $pl " + " $pr } }
  END { exit bad }' "$h" || fail "the total momentum is not 0 to round-off"
pass "momentum conserved to round-off (1e-12 of m v)"

# the last row, after the rebound
read -r vl vr ml mr ke se ke0 mass <<<"$(awk -F, -v vl="$(col mean_velocity_left_x)" -v vr="$(col mean_velocity_right_x)" \
  -v ml="$(col mass_left)" -v mr="$(col mass_right)" -v ke="$(col kinetic_energy)" -v se="$(col strain_energy)" '
  NR == 2 { ke0 = $ke } NR > 1 { last = $vl " " $vr " " $ml " " $mr " " $ke " " $se }
  END { print last, ke0 }' "$h")"
awk -v vl="$vl" -v vr="$vr" 'BEGIN { e = (vr - vl) / 10; printf "restitution e = %.4f\n", e; exit !(vl < 0 && vr > 0 && e >= 0.9 && e <= 1) }' \
  || fail "restitution out of [0.9, 1]: v_left $vl, v_right $vr after the collision"
pass "the spheres rebound with 0.9 <= e <= 1"

awk -v vl="$vl" -v vr="$vr" -v ml="$ml" -v mr="$mr" -v ke="$ke" -v se="$se" -v ke0="$ke0" 'BEGIN {
  e = (vr - vl) / 10; translational = 0.5 * (ml * vl * vl + mr * vr * vr)
  inside = ke + se - translational; expected = (1 - e * e) * ke0
  printf "energy in the spheres %.4g J, (1 - e^2) KE0 = %.4g J\n", inside, expected
  d = inside - expected; if (d < 0) d = -d; exit !(d <= 0.01 * ke0) }' \
  || fail "the translational energy lost is not in the spheres' vibrations"
pass "the lost translational energy is the spheres' vibration energy (1% of KE0)"

awk -F, -v vl="$(col mean_velocity_left_x)" -v vr="$(col mean_velocity_right_x)" -v ke="$(col kinetic_energy)" \
  -v kl="$(col kinetic_energy_left)" -v kr="$(col kinetic_energy_right)" '
  function abs(v) { return v < 0 ? -v : v }
  NR == 2 && (abs($vl - 5) > 5e-12 || abs($vr + 5) > 5e-12) { bad = 1; print "initial mean velocities " $vl ", " $vr }
  NR > 1 && abs($kl + $kr - $ke) > 1e-9 * $ke { bad = 1; print "row " NR ": " $kl " + " $kr " != " $ke }
  END { exit bad }' "$h" || fail "the per-body sums do not add up to the whole"
pass "per-body sums: initial mean velocities, kinetic energies add up"

grep -q 'Name="body"' "$TMP"/two/two_spheres_collision_000000.vtu || fail "the body field is not in the frame"
pass "body field written"

OMP_NUM_THREADS=1 run_peri run "$deck" --output "$TMP/one"
expect_status 0
compare_histories "$TMP/one/history.csv" "$h" 0 || fail "1 and 2 threads differ"
pass "1 and 2 threads: the same history.csv"
