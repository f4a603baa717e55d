#!/usr/bin/env bash
# Rigid tools (docs/contact.md "Rigid tools"):
#  - Coulomb friction: a plane pressed into a block and slid at 10 m/s with mu = 0.3. Every
#    node under it slides, each with |f_t| = mu f_n, so F_t / P = mu when the sliding
#    directions agree and never more (the triangle inequality); the nodes' own sideways
#    motion turns a few directions, so 0.99 mu <= CoF <= mu on every row in contact. The
#    sliding distance and the position are the prescribed 10 m/s x t (1e-9).
#  - load control: a flat punch under a load ramped to 200 N and held, with its own damped
#    equation: at rest the body pushes back with P and the base holds P (equilibrium), to 1%
#    (the body's vibration, damped at 4e4 1/s over the 300 us of hold, is below 0.5 N).
#  - a free rigid impactor (load 0, its own mass and initial speed) with kinematic contact:
#    the momentum it loses is the free block's, to round-off, once they have parted.
#  - bad input (exit 2, at the key): a tool starting deeper than half a spacing in the body,
#    load control on a position prescribed along the direction, an initial tool speed in a
#    quasi-static run.
#  - load control under adr and nlcg: the contact force at equilibrium is the load.
# Usage: bash tests/cli/tools.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

deck=tests/cli/decks/tool_sliding_plane.yaml
run_peri run "$deck" --output "$TMP/slide"
expect_status 0
h="$TMP/slide/history.csv"
col() { csv_column "$h" "$1"; }
for name in tool_slider_force_x tool_slider_normal_force tool_slider_tangential_force tool_slider_cof \
            tool_slider_sliding_distance tool_slider_position_x; do
  [ -n "$(col "$name")" ] || fail "history.csv lacks the column $name"
done
awk -F, -v P="$(col tool_slider_normal_force)" -v cof="$(col tool_slider_cof)" '
  NR > 1 && $P > 0 { rows++; if ($cof > 0.3 * (1 + 1e-9) || $cof < 0.99 * 0.3) { bad = 1; print "row " NR ": CoF " $cof } }
  END { if (rows < 3) { print "only " rows " rows in contact"; bad = 1 } exit bad }' "$h" \
  || fail "the coefficient of friction is not 0.3 (Coulomb)"
pass "friction: F_t / P = mu = 0.3 while sliding"
awk -F, -v s="$(col tool_slider_sliding_distance)" -v x="$(col tool_slider_position_x)" '
  function abs(v) { return v < 0 ? -v : v }
  NR > 1 && (abs($s - 10 * $1) > 1e-9 * (10 * $1 + 1e-12) || abs($x - 10 * $1) > 1e-9 * (10 * $1 + 1e-12)) { bad = 1; print "row " NR ": " $s ", " $x }
  END { exit bad }' "$h" || fail "sliding distance is not 10 m/s x t"
pass "sliding distance and position follow the prescribed motion"

deck=tests/cli/decks/tool_load_control.yaml
run_peri run "$deck" --output "$TMP/load"
expect_status 0
h="$TMP/load/history.csv"
tail -n 1 "$h" | awk -F, -v P="$(col tool_punch_normal_force)" -v R="$(col reaction_base_z)" '
  function abs(v) { return v < 0 ? -v : v }
  { printf "P_contact %.4g N, base reaction %.4g N\n", $P, $R; exit !(abs($P - 200) <= 2 && abs($R - 200) <= 2) }' \
  || fail "under load control the contact force and the base reaction should both be the 200 N load"
pass "load control: contact force and support reaction equal the load at rest"

deck=tests/cli/decks/tool_free_impactor.yaml
run_peri run "$deck" --output "$TMP/free"
expect_status 0
h="$TMP/free/history.csv"
# After the parting (no contact force from 30 us on; contact ends near 15 us) the tool flies at
# a constant speed: its speed column and the rate of its position (rows 30 us apart) agree,
# and the tool's momentum (-M speed along z) plus the block's is M v0 = -6e-4 kg m/s. The 10
# digits of history.csv put the error near 1e-9 of M v0 (measured 5e-9 from the positions); a
# lost half kick of the contact would be 1e-2. Tolerance 1e-7. Before contact the speed is v0
# and the penetration depth 0.
awk -F, -v z="$(col tool_hammer_position_z)" -v P="$(col tool_hammer_normal_force)" -v pz="$(col momentum_z)" \
        -v sp="$(col tool_hammer_speed)" -v pen="$(col tool_hammer_penetration)" '
  function abs(v) { return v < 0 ? -v : v }
  NR == 2 && ($sp != 5 || $pen != 0) { print "row 2: speed " $sp ", penetration " $pen; bad = 1 }
  NR > 1 && $1 >= 3e-5 { if (!n++) { t0 = $1; z0 = $z } if ($P != 0) contact = 1; t = $1; zl = $z; p = $pz; v = $sp }
  END { vt = (zl - z0) / (t - t0); total = p - 1.2e-4 * v
        printf "tool %.6g m/s (positions: %.6g), block momentum %.6g, total %.10g kg m/s (M v0 = -6e-4)\n", -v, vt, p, total
        exit !(!bad && n >= 2 && !contact && abs(total + 6e-4) <= 1e-7 * 6e-4 && abs(vt + v) <= 1e-6 * abs(v) && p < -1e-4) }' "$h" \
  || fail "the free impactor's lost momentum should be the block's (M v0 = M v_tool + sum m v)"
pass "kinematic contact of a free rigid impactor: momentum conserved"

sed -e 's/contact: kinematic/contact: kinematic\n    stiffness: 1.0e20/' "$deck" > "$TMP/kstiff.yaml"
run_peri check "$TMP/kstiff.yaml"
expect_status 2
expect_stderr_contains "only for contact: penalty"
pass "kinematic contact with a penalty stiffness: exit 2"

sed -e 's/position: \["10\*t", 0, "0.0036 - 2\*t"\]/position: [0, 0, 0.0028]/' tests/cli/decks/tool_sliding_plane.yaml > "$TMP/inside.yaml"
run_peri check "$TMP/inside.yaml"
expect_status 2
expect_stderr_contains "inside.yaml:20:"
expect_stderr_contains "tool 'slider' is inside the body at t = 0"
pass "a tool inside the body at t = 0: exit 2"

deck=tests/cli/decks/tool_load_control.yaml
sed -e 's/position: \[0, 0, 0.0036\]/position: [0, 0, "0.0036 - t"]/' "$deck" > "$TMP/nofree.yaml"
run_peri check "$TMP/nofree.yaml"
expect_status 2
expect_stderr_contains "load control needs its degree of freedom along direction free"
pass "load control without a free degree of freedom: exit 2"

# load control in the quasi-static solvers: the punch's offset is searched until the contact
# force at equilibrium is the load to 1e-3 (the search's tolerance); the base then holds it
# to the solve's tolerance (asserted 1%), as in the explicit run above.
for solver in adr nlcg; do
  sed -e "s/type: explicit, end_time: 4.0e-4, damping: 4.0e4,/type: $solver, load_steps: 2,/" "$deck" > "$TMP/qs.yaml"
  run_peri run "$TMP/qs.yaml" --output "$TMP/qs_$solver"
  expect_status 0
  h="$TMP/qs_$solver/history.csv"
  tail -n 1 "$h" | awk -F, -v P="$(col tool_punch_normal_force)" -v R="$(col reaction_base_z)" '
    function abs(v) { return v < 0 ? -v : v }
    { printf "P_contact %.6g N, base reaction %.6g N\n", $P, $R; exit !(abs($P - 200) <= 0.2 && abs($R - 200) <= 2) }' \
    || fail "$solver: under load control the contact force and the base reaction should both be the 200 N load"
  pass "load control under $solver: contact force and support reaction equal the load"
done

sed -e 's/type: explicit, end_time: 4.0e-4, damping: 4.0e4,/type: adr, load_steps: 2,/' \
    -e 's/mass: 1.0e-3, damping: 1.0e5}/mass: 1.0e-3, velocity: 1}/' "$deck" > "$TMP/qs_speed.yaml"
run_peri check "$TMP/qs_speed.yaml"
expect_status 2
expect_stderr_contains "a quasi-static run has no speed"
pass "an initial tool speed in a quasi-static run: exit 2"

# load control and sliding together (quasi-static, adr): a plane loaded to 200 N on a block,
# then slid 1 mm with mu = 0.3. Before the slide no node slides on it (CoF 0: the tool's
# velocity in a quasi-static run is the way it came, and it came straight down); while it
# slides every node under it slides the same way, so F_t / P = mu (0.99 mu to mu, as above),
# P is the load to the search's 1e-3, the sliding distance is the prescribed 1e-3 (t - 0.5)/0.5
# (1e-9), and the base holds the friction force (the reaction equals the tool's force, 1%).
deck=tests/cli/decks/tool_load_sliding.yaml
run_peri run "$deck" --output "$TMP/load_slide"
expect_status 0
h="$TMP/load_slide/history.csv"
awk -F, -v P="$(col tool_slider_normal_force)" -v cof="$(col tool_slider_cof)" -v s="$(col tool_slider_sliding_distance)" \
        -v fx="$(col tool_slider_force_x)" -v ft="$(col tool_slider_tangential_force)" -v rx="$(col reaction_base_x)" '
  function abs(v) { return v < 0 ? -v : v }
  NR > 1 && $1 > 0 {
    load = 200 * ($1 < 0.5 ? $1 / 0.5 : 1); slid = $1 > 0.5 ? 1e-3 * ($1 - 0.5) / 0.5 : 0
    if (abs($P - load) > 1e-3 * load) { print "row " NR ": P " $P " for the load " load; bad = 1 }
    if (abs($s - slid) > 1e-9 * 1e-3) { print "row " NR ": sliding distance " $s " (" slid ")"; bad = 1 }
    if ($1 <= 0.5 && $cof != 0) { print "row " NR ": CoF " $cof " before the slide"; bad = 1 }
    if ($1 > 0.5) { slides++; if ($cof > 0.3 * (1 + 1e-9) || $cof < 0.99 * 0.3) { print "row " NR ": CoF " $cof; bad = 1 }
                    if (abs($rx - $fx) > 0.01 * $ft) { print "row " NR ": base " $rx ", tool " $fx; bad = 1 } } }
  END { if (slides < 2) { print "only " slides " sliding rows"; bad = 1 } exit bad }' "$h" \
  || fail "load-controlled sliding: P = load, CoF = 0 then mu, sliding distance and base reaction"
pass "load control while sliding (adr): F_t / P = mu, the load held, the sliding distance exact"

# the scratch (2D, nlcg): a cylinder loaded to 80 N, slid 24 mm, unloaded. Frictionless on an
# elastic block, the quasi-static slide dissipates nothing, so F_t = dE/ds = 0 but for the
# lattice's ripple: |CoF| <= 1e-3 on every row (1% of the a-C films' 0.1; measured 2e-5).
# With mu = 0.3 the tip drags every contact node: CoF = mu to 1% while it slides (the curved
# contact tilts the nodes' normals by a/R ~ 0.03, a change of order (a/R)^2).
deck=tests/cli/decks/tool_scratch.yaml
for mu in 0 0.3; do
  run_peri run "$deck" --set "tools.0.friction=$mu" --output "$TMP/scratch_$mu"
  expect_status 0
  h="$TMP/scratch_$mu/history.csv"
  awk -F, -v mu="$mu" -v P="$(col tool_tip_normal_force)" -v cof="$(col tool_tip_cof)" -v s="$(col tool_tip_sliding_distance)" '
    function abs(v) { return v < 0 ? -v : v }
    NR > 1 && $1 > 0 {
      load = 80 * ($1 < 0.75 ? ($1 < 0.25 ? $1 / 0.25 : 1) : 1 - 0.99 * ($1 - 0.75) / 0.25)
      if (abs($P - load) > 1e-3 * load) { print "row " NR ": P " $P " for the load " load; bad = 1 }
      sliding = $1 > 0.25 && $1 <= 0.75
      if (sliding) n++
      want = sliding ? mu : 0
      if (abs($cof - want) > (want > 0 ? 0.01 * want : 1e-3)) { print "row " NR ": CoF " $cof " (" want ")"; bad = 1 }
      if (sliding && abs($s - 0.024 * ($1 - 0.25) / 0.5) > 1e-12) { print "row " NR ": sliding distance " $s; bad = 1 } }
    END { if (n < 4) { print "only " n " sliding rows"; bad = 1 } exit bad }' "$h" \
    || fail "scratch with mu = $mu: the load held and CoF = mu while sliding"
  pass "scratch (2D, nlcg, load control), mu = $mu: F_t / P = mu while sliding"
done
