#!/usr/bin/env bash
# Several bodies on MPI ranks (docs/contact.md section 4, "Bodies"): every rank builds the
# bodies' labels of all nodes before the decomposition and keeps its own nodes' and its ghosts'
# after it; the per-body sums of history.csv run in the fixed blocks of the global node order
# and the penetration front is a largest value over the ranks, so history.csv is the same on
# 1, 2 and 3 ranks to a relative 1e-12 (round-off could only enter through the order of the
# sums, which is fixed):
#  - two elastic spheres in a head-on collision (tests/cli/two_spheres.sh), split by the ranks:
#    the per-body masses are 280 nodes x rho dx^3 each on every rank count, the per-body
#    momenta opposite, and the bodies meet through the short-range forces across ranks;
#  - a projectile thrown at a plate with its penetration column (tests/cli/impact_penetration.sh);
#  - two bars bonded as bodies with an interface critical stretch (tests/cli/bodies.sh);
#  - the spheres restarted on 3 ranks from a checkpoint written on 2 (with HDF5).
# Skipped when peri was built without MPI.
# Usage: bash tests/cli/mpi_bodies.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
source "$(dirname "${BASH_SOURCE[0]}")/lib/mpi.bash"
cli_init "$@"
mpi_init

export MPI_RANKS="1 2 3"
mpi_same_on_ranks spheres tests/cli/decks/two_spheres_collision.yaml
pass "two spheres: 1, 2 and 3 ranks give the same history, per-body sums included"

# every rank count's run has the two bodies' columns with each body's whole mass, 280 nodes of
# 1e-9 m^3 at 7800 kg/m^3, and opposite momenta (the sums over the ranks take every node once)
for np in 2 3; do
  h="$TMP/spheres-np$np/history.csv"
  awk -F, -v ml="$(csv_column "$h" mass_left)" -v mr="$(csv_column "$h" mass_right)" \
    -v pl="$(csv_column "$h" momentum_left_x)" -v pr="$(csv_column "$h" momentum_right_x)" '
    function abs(x) { return x < 0 ? -x : x }
    NR > 1 { rows++; m = 280 * 7800e-9
      if (abs($ml - m) > 1e-12 * m || abs($mr - m) > 1e-12 * m) bad++
      if (abs($pl + $pr) > 1e-12 * m * 5) bad++ }
    END { exit !(rows > 0 && bad == 0) }' "$h" ||
    fail "spheres on $np ranks: a body's mass is not 280 rho dx^3 or the bodies' momenta are not opposite"
done
pass "spheres on 2 and 3 ranks: each body's mass is 280 rho dx^3 to 1e-12, momenta opposite"

mpi_same_on_ranks projectile tests/cli/decks/projectile_penetration.yaml
h="$TMP/projectile-np3/history.csv"
[[ -n "$(csv_column "$h" penetration_projectile)" ]] || fail "projectile on 3 ranks: no penetration_projectile column"
pass "projectile and plate: 1, 2 and 3 ranks give the same history, the penetration depth included"

mpi_same_on_ranks bonded tests/cli/decks/bonded_bodies_bar.yaml
pass "two bars bonded as bodies with an interface: 1, 2 and 3 ranks give the same history and broken bonds"

# a checkpoint of the spheres written on 2 ranks at step 100 (before they meet) and restarted
# on 3 continues to the history of the run that was never interrupted (the bodies' labels come
# from the deck, the rest from the checkpoint); needs HDF5, so it comes last
skip_without_checkpoints
every=(--set output.checkpoint_every=100 --set 'output.checkpoint_file=ck_{step}.h5')
run_peri_mpi 2 run tests/cli/decks/two_spheres_collision.yaml --output "$TMP/ck-full" "${every[@]}"
expect_status 0
mkdir -p "$TMP/ck-part"
cp "$TMP/ck-full/ck_000100.h5" "$TMP/ck-full/history.csv" "$TMP/ck-part/"
run_peri_mpi 3 run tests/cli/decks/two_spheres_collision.yaml --output "$TMP/ck-part" "${every[@]}" \
  --restart "$TMP/ck-part/ck_000100.h5"
expect_status 0
expect_stdout_contains "restart      from $TMP/ck-part/ck_000100.h5 at step 100"
diff_report=$(compare_histories "$TMP/ck-full/history.csv" "$TMP/ck-part/history.csv" "$MPI_TOL") ||
  fail "spheres: the checkpoint of 2 ranks restarted on 3 differs from the run without interruption: $diff_report"
pass "spheres: a checkpoint of 2 ranks restarted on 3 gives the uninterrupted history, per-body sums included"
