#!/usr/bin/env bash
# The penetration depth of a deformable projectile (output.penetration, docs/contact.md
# "Bodies"): tests/cli/decks/projectile_penetration.yaml throws a steel block at 100 m/s along
# +x at a free steel plate 5 mm away (between the foremost nodes).
#  - at t = 0 penetration_projectile is the reference gap between the foremost nodes, -5 mm
#    (1e-15 m);
#  - while no force acts on the projectile (its momentum still m 100 m/s) the penetration is
#    -5 mm + 100 t, free flight (1e-12 m: the 10 digits history.csv prints);
#  - at every row it is at most free flight (1e-12 m): contact only slows the projectile;
#  - the projectile rebounds: its mean velocity ends negative, and the last penetration is more
#    than 2 mm below the largest;
#  - bad input exits 2 at the key: a name that is not a body, a zero direction, a direction with
#    nothing ahead, and output.penetration without bodies.
# Usage: bash tests/cli/impact_penetration.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=tests/cli/decks/projectile_penetration.yaml
run_peri run "$deck" --quiet --output "$TMP/pen"
expect_status 0
h="$TMP/pen/history.csv"
col() { csv_column "$h" "$1"; }
for name in time penetration_projectile momentum_projectile_x mass_projectile mean_velocity_projectile_x; do
  [ -n "$(col "$name")" ] || fail "history.csv lacks the column $name"
done
awk -F, -v t="$(col time)" -v pen="$(col penetration_projectile)" -v p="$(col momentum_projectile_x)" \
    -v m="$(col mass_projectile)" -v v="$(col mean_velocity_projectile_x)" '
  function abs(x) { return x < 0 ? -x : x }
  NR == 2 { if (abs($pen + 0.005) > 1e-15) { print "penetration at t = 0: " $pen ", the gap -0.005 m"; bad = 1 } }
  NR > 1 {
    free = -0.005 + 100 * $t
    if ($p == 100 * $m && abs($pen - free) > 1e-12) { print "row " NR ": " $pen " before contact, free flight " free; bad = 1 }
    if ($pen > free + 1e-12) { print "row " NR ": " $pen " beyond free flight " free; bad = 1 }
    if ($pen > most) most = $pen
    last = $pen; vend = $v }
  END {
    if (!(vend < 0)) { print "the projectile did not rebound: mean velocity " vend; bad = 1 }
    if (!(last < most - 0.002)) { print "last penetration " last ", largest " most; bad = 1 }
    exit bad }' "$h" || fail "penetration_projectile is not the free flight before contact, or beyond it after"
pass "penetration: -5 mm at t = 0, free flight before contact and a bound after, rebound"

bad_deck() { # NAME SED: the deck with one change
  sed "$2" "$deck" >"$TMP/$1.yaml"
  echo "$TMP/$1.yaml"
}
fails_at() {
  run_peri check "$1"
  expect_status 2
  locate "$2" "$1"
  expect_stderr_contains "$1:$LOC_LINE:$LOC_COL: error: $3"
}
d=$(bad_deck name 's/penetration: {projectile: \[1, 0\]}/penetration: {projectil: [1, 0]}/')
fails_at "$d" "projectil:" "output.penetration: 'projectil' is not a body"
d=$(bad_deck zero 's/penetration: {projectile: \[1, 0\]}/penetration: {projectile: [0, 0]}/')
fails_at "$d" "[0, 0]}" "output.penetration.projectile: the direction is zero"
d=$(bad_deck behind 's/penetration: {projectile: \[1, 0\]}/penetration: {projectile: [-1, 0]}/')
fails_at "$d" "[-1, 0]}" "output.penetration.projectile: no node of another body lies ahead of it"
d=$(bad_deck nobodies 's/^bodies: .*//')
fails_at "$d" "{projectile: [1, 0]}" "key 'penetration': needs 'bodies'"
pass "output.penetration: an unknown body, a zero direction, nothing ahead and no bodies are positioned errors"
