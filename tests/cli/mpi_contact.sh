#!/usr/bin/env bash
# Short-range contact forces on several MPI ranks (docs/contact.md section 2, "MPI"): contact
# partners on other ranks are contact ghosts, numbered in the global node order, so every
# node sums the same pair forces in the same order as one process and history.csv is the
# same on 1, 2 and 3 ranks to a relative 1e-12 (round-off would only enter through the order
# of the sums, which is fixed):
#  - two steel plates thrown face on at each other at +-50 m/s (no bond joins them, none
#    breaks), split by the ranks across the plane of impact: the contact acts across ranks
#    (contact ghosts), the pair list is built as often as on one rank and holds the same
#    pairs; on 2 ranks the plates stay apart: the smallest |y_i - y_j| / d_ij of every step
#    (short_range_min_ratio) stays above the acoustic bound 1 - 2p/(0.9 dx) of
#    tests/verification/test_short_range.c, p = rho c_p v delta / (c_S dx^4), c_p =
#    sqrt(1.8 K / rho), c_S = 15 x 18 K / (pi delta^4), and below 1 (they did meet); the total
#    momentum stays 0 to 1e-12 of sum m |v| (opposite pair forces); once they have parted the
#    energy is the initial kinetic energy to 1% (the explicit integrator's error over the
#    impact, as in two_spheres.sh);
#  - the coarse LAMMPS fragmentation problem (two thirds of the bonds break, fragments pushed
#    together under the indenter): the same history on 1, 2 and 3 ranks.
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_contact.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

deck=tests/cli/decks/two_plates_apart.yaml
builds_line() { grep -E '^  contact      short-range forces, pair list built' "$RUN_STDOUT" | sed -e 's/, [0-9]* contact ghosts.*//'; }
run_peri_mpi 1 run "$deck" --output "$TMP/plates-np1"
expect_status 0
one_rank=$(builds_line)
[[ -n "$one_rank" ]] || fail "no pair-list line in the summary of one rank"
for np in 2 3; do
  run_peri_mpi "$np" run "$deck" --output "$TMP/plates-np$np"
  expect_status 0
  diff_report=$(compare_histories "$TMP/plates-np1/history.csv" "$TMP/plates-np$np/history.csv" "$MPI_TOL") ||
    fail "plates: history.csv on 1 and $np ranks differ: $diff_report"
  [[ "$(builds_line)" == "$one_rank" ]] || fail "plates: '$one_rank' on 1 rank, '$(builds_line)' on $np"
  ghosts=$(grep -oE '[0-9]+ contact ghosts on the ranks' "$RUN_STDOUT" | cut -d' ' -f1)
  [[ -n "$ghosts" && "$ghosts" -gt 0 ]] || fail "plates on $np ranks: no contact ghosts ('$(grep 'pair list' "$RUN_STDOUT")')"
done
pass "plates: 1, 2 and 3 ranks give the same history (tolerance $MPI_TOL) and the same pair-list builds; contact ghosts on the ranks"

h="$TMP/plates-np2/history.csv"
awk -F, -v rho=7800 -v E=200e9 -v v=50 -v dx=1e-3 -v delta=3e-3 \
  -v r="$(csv_column "$h" short_range_min_ratio)" -v pz="$(csv_column "$h" momentum_z)" '
  function abs(x) { return x < 0 ? -x : x }
  BEGIN { pi = atan2(0, -1); K = E / 1.5  # PMB: nu = 1/4
    cs = 15 * 18 * K / (pi * delta ^ 4); cp = sqrt(1.8 * K / rho)
    p = rho * cp * v * delta / (cs * dx ^ 4); bound = 1 - 2 * p / (0.9 * dx); low = 2 }
  NR > 1 { if ($r < low) low = $r; if (abs($pz) > worst) worst = abs($pz) }
  END { scale = 288 * rho * dx ^ 3 * v  # sum m |v| at the start
    printf "2 ranks: min |y_i - y_j| / d_ij = %.4f, bound %.4f; |momentum_z| <= %.3g of %.3g\n", low, bound, worst, scale
    exit !(low >= bound && low < 1 && worst <= 1e-12 * scale) }' "$h" ||
  fail "plates on 2 ranks: closer than the acoustic bound, never in contact, or momentum not conserved"
pass "plates on 2 ranks: min |y_i - y_j| / d_ij above the acoustic bound, momentum 0 to 1e-12 of m v"

awk -F, -v r="$(csv_column "$h" short_range_min_ratio)" -v ke="$(csv_column "$h" kinetic_energy)" \
  -v se="$(csv_column "$h" strain_energy)" '
  NR == 2 { ke0 = $ke } NR > 1 { last_r = $r; last = $ke + $se }
  END { d = last - ke0; if (d < 0) d = -d
    printf "after the impact: KE + SE = %.6g J, KE0 = %.6g J\n", last, ke0; exit !(last_r == 1 && d <= 0.01 * ke0) }' "$h" ||
  fail "plates on 2 ranks: still in contact at the end, or the energy after the impact is not KE0 to 1%"
pass "plates on 2 ranks: parted at the end with the initial energy to 1%"

export MPI_RANKS="1 2 3"
mpi_same_on_ranks fragments examples/lammps_peri_pmb.yaml --set solver.steps=300 --set discretization.fill.0.radius=0.0025 \
  --set discretization.fill.0.length=0.0025 --set "discretization.fill.0.center=[0, -0.0025, 0]" \
  --set contact.short_range=true --set output.history_every=20 --set output.picture=false
pass "fragmentation with short-range forces: 1, 2 and 3 ranks give the same history and broken bonds"

# quasi-static: the loads (and with them the pair list and its exchanges) are evaluated at
# every force evaluation of the solver; every rank takes the same steps
sed -e "s/type: explicit, end_time: 4.0e-4, damping: 4.0e4,/type: nlcg, load_steps: 2,/" \
  tests/cli/decks/tool_load_control.yaml > "$TMP/punch_nlcg.yaml"
printf 'contact:\n  short_range: true\n' >> "$TMP/punch_nlcg.yaml"
export MPI_RANKS="1 2"
mpi_same_on_ranks punch_nlcg "$TMP/punch_nlcg.yaml"
pass "a punch under load control with short-range forces (nlcg): 1 and 2 ranks give the same history"
