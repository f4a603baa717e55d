#!/usr/bin/env bash
# Several bodies in one deck (docs/contact.md "Bodies"): no bond joins two bodies, so a bar
# leaving its neighbour at 1 m/s exerts no force on it (the neighbour's reaction is exactly 0
# at every step, where the same two bars as one body pull on each other); the total momentum
# stays that of the leaving bar, -rho A L v = -0.01 kg m/s. Overlapping bodies, an unknown
# region and a body without nodes exit 2 at the key, naming the bodies.
# Usage: bash tests/cli/bodies.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=tests/cli/decks/two_bodies_bar.yaml
run_peri run "$deck" --output "$TMP/bodies"
expect_status 0
h="$TMP/bodies/history.csv"
col=$(csv_column "$h" reaction_right_x)
mom=$(csv_column "$h" momentum_x)
[ -n "$col" ] && [ -n "$mom" ] || fail "history.csv lacks reaction_right_x or momentum_x"
# exact zero: the right bar has no bond to the left one and no other load
awk -F, -v c="$col" 'NR > 1 && $c + 0 != 0 { bad = 1 } END { exit bad }' "$h" \
  || fail "the right body feels a force from the left one: $(cut -d, -f"$col" "$h" | tr '\n' ' ')"
# momentum: rho A L v = 1000 * 1e-4 * 0.1 * 1 (ten nodes of volume 1e-6), to round-off
awk -F, -v c="$mom" 'NR > 1 { d = $c + 0.01; if (d < 0) d = -d; if (d > 1e-15) bad = 1 } END { exit bad }' "$h" \
  || fail "total momentum is not -0.01 kg m/s"
pass "two bodies: no force across them, momentum conserved"

grep -v '^bodies:' "$deck" > "$TMP/one.yaml"
run_peri run "$TMP/one.yaml" --output "$TMP/one"
expect_status 0
awk -F, -v c="$col" 'NR > 1 && $c + 0 != 0 { any = 1 } END { exit !any }' "$TMP/one/history.csv" \
  || fail "without bodies the bars should pull on each other (the test cannot tell otherwise)"
pass "the same bars as one body pull on each other"

sed -e 's/right: {block: 2}/right: {shape: interval, min: [0.095], max: [1]}/' "$deck" > "$TMP/overlap.yaml"
run_peri check "$TMP/overlap.yaml"
expect_status 2
expect_stderr_contains "overlap.yaml:15:"
expect_stderr_contains "bodies 'left' and 'right' overlap at t = 0"
pass "overlapping bodies: exit 2 naming both"

sed -e 's/^bodies: \[left, right\]/bodies: [left, rigth]/' "$deck" > "$TMP/unknown.yaml"
run_peri check "$TMP/unknown.yaml"
expect_status 2
expect_stderr_contains "unknown.yaml:15:"
pass "an unknown region in bodies: exit 2 at it"

sed -e 's/right: {block: 2}/right: {shape: interval, min: [5], max: [6]}/' "$deck" > "$TMP/empty.yaml"
run_peri check "$TMP/empty.yaml"
expect_status 2
expect_stderr_contains "region 'right' contains no node"
pass "a body without nodes: exit 2"

# body_interfaces: two bars bonded as bodies. With an interface critical stretch of 1e-4 (the
# bars' own is 1, never reached) exactly the bonds across break, 6 pairs of a 3-node horizon
# (1 + 2 + 3) = 12 of the 108 directed bonds, and the damaged mass of the left body is its 3
# nodes within the horizon of the interface (3 x 1000 kg/m^3 x 1e-6 m^3).
deck=tests/cli/decks/bonded_bodies_bar.yaml
run_peri run "$deck" --output "$TMP/bonded"
expect_status 0
h="$TMP/bonded/history.csv"
frac=$(csv_column "$h" broken_bond_fraction)
dmg=$(csv_column "$h" damaged_mass_left)
[ -n "$frac" ] && [ -n "$dmg" ] || fail "history.csv lacks broken_bond_fraction or damaged_mass_left"
tail -n 1 "$h" | awk -F, -v f="$frac" -v d="$dmg" '
  function abs(v) { return v < 0 ? -v : v }
  { exit !(abs($f - 12 / 108) <= 1e-9 && abs($d - 0.003) <= 1e-12) }' \
  || fail "the interface should break its 12 bonds and damage 3 left nodes: $(tail -n 1 "$h")"
pass "bonded bodies: the interface's own critical stretch breaks exactly the bonds across"

sed -e 's/, critical_stretch: 1.0e-4}/}/' "$deck" > "$TMP/glued.yaml"
run_peri run "$TMP/glued.yaml" --output "$TMP/glued"
expect_status 0
awk -F, -v f="$frac" -v c="$(csv_column "$TMP/glued/history.csv" reaction_right_x)" \
  'NR > 1 && $f + 0 != 0 { bad = 1 } NR > 1 && $c + 0 != 0 { pulled = 1 } END { exit bad || !pulled }' "$TMP/glued/history.csv" \
  || fail "bonded bodies without an interface stretch should pull on each other and keep their bonds"
pass "bonded bodies without an interface stretch: one body"

sed -e 's/material: right_steel/material: left_steel/' "$deck" > "$TMP/same.yaml"
run_peri check "$TMP/same.yaml"
expect_status 2
expect_stderr_contains "same.yaml:21:"
expect_stderr_contains "give one body its own material"
pass "an interface stretch between bodies of one material: exit 2"

sed -e 's/bodies: \[left, right\], critical/bodies: [left, rihgt], critical/' "$deck" > "$TMP/nobody.yaml"
run_peri check "$TMP/nobody.yaml"
expect_status 2
expect_stderr_contains "'rihgt' is not a body"
pass "body_interfaces naming no body: exit 2"
