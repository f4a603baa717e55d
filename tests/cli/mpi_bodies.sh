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
#  - two bars bonded as bodies with an interface critical stretch (tests/cli/bodies.sh).
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
