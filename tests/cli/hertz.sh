#!/usr/bin/env bash
# Hertz contact (docs/contact.md "Hertz contact"): examples/hertz_contact.yaml at a
# coarse size, a rigid sphere R = 12.5 mm pressed 0.6 mm into an LPS block (E = 1 GPa,
# nu = 0.25, m = 3, position-aware surface correction; 15 x 15 x 8 nodes) in six load steps
# under nlcg. Hertz (Johnson, Contact Mechanics, §4.2): F = (4/3) E* sqrt(R) d^(3/2), E* =
# E / (1 - nu^2) for a rigid sphere. The block is finite (held at its base 8 spacings down),
# so the approach d to the distant surface is found from the relative approach of the centre
# node and the surface node at r0 = 5 mm, m = u_c - u(r0), with Hertz's surface displacement
# outside the contact (Johnson eq. 3.42b): u(r) = d/pi [(2 - r^2/a^2) asin(a/r) + sqrt(r^2/a^2 - 1)],
# a = sqrt(R d), i.e. m = d (1 - u(r0)/d), solved for d by bisection.
#  - every row whose contact radius spans at least 2 spacings (a >= 2 dx, the rows where the
#    contact holds a few rings of nodes) has F within 10% of Hertz at its d (the
#    target's bound);
#  - the least-squares exponent of F against d over those rows is 3/2 within 0.1: a tenth of
#    the way to a cone's 2 or a flat punch's 1.
# Usage: bash tests/cli/hertz.sh PATH_TO_PERI   (from the repository root)
set -u
source "$(dirname "${BASH_SOURCE[0]}")/lib/assert.bash"
cli_init "$@"

run_peri run examples/hertz_contact.yaml --output "$TMP/hertz" \
  --set "discretization.fill.0.min=[-0.0075, -0.0075, -0.008]" --set "discretization.fill.0.max=[0.0075, 0.0075, 0]" \
  --set "regions.base.max=[1, 1, -0.007]" \
  --set "regions.ring.min=[4.9e-3, -1.0e-4, -6.0e-4]" --set "regions.ring.max=[5.1e-3, 1.0e-4, -4.0e-4]" \
  --set tools.0.radius=0.0125 --set 'tools.0.position=[0, 0, "0.0125 - 5.0e-4 - 6.0e-4*t"]' \
  --set solver.load_steps=6 --set output.plot.reference="4/3*1.0e9/(1 - 0.25^2)*sqrt(0.0125)*(-x)^1.5"
expect_status 0
h="$TMP/hertz/history.csv"
[ -s "$TMP/hertz/tool_ball_normal_force_vs_displacement_center_z.png" ] || fail "the plot against Hertz is missing"
awk -F, -v E=1.0e9 -v nu=0.25 -v R=0.0125 -v r0=0.005 -v dx=1.0e-3 '
  function asin_(s) { return atan2(s, sqrt(1 - s * s)) }
  function ring(rho) { return ((2 - rho * rho) * asin_(1 / rho) + sqrt(rho * rho - 1)) / 3.141592653589793 }
  function relative(d) { return d * (1 - ring(r0 / sqrt(R * d))) }
  NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  { F = $c["tool_ball_normal_force"]; m = $c["displacement_ring_z"] - $c["displacement_center_z"]
    if (!(F > 0) || !(m > 0)) next
    lo = m; hi = r0 * r0 / R    # d > m, and a < r0
    for (k = 0; k < 200; k++) { mid = (lo + hi) / 2; if (relative(mid) < m) lo = mid; else hi = mid }
    d = (lo + hi) / 2; a = sqrt(R * d); hertz = 4 / 3 * E / (1 - nu * nu) * sqrt(R) * d ^ 1.5
    printf "d %.4g m, a/dx %.2f: F %.5g N, Hertz %.5g N, ratio %.3f\n", d, a / dx, F, hertz, F / hertz
    if (a < 2 * dx) next
    n++; if (F / hertz > 1.1 || F / hertz < 0.9) bad = 1
    X = log(d); Y = log(F); sx += X; sy += Y; sxx += X * X; sxy += X * Y }
  END { if (n < 3) { print "only " n " rows with a >= 2 dx"; exit 1 }
        p = (n * sxy - sx * sy) / (n * sxx - sx * sx); printf "exponent %.3f over %d rows\n", p, n
        exit bad || p < 1.4 || p > 1.6 }' "$h" || fail "the force is not Hertz's F = (4/3) E* sqrt(R) d^(3/2) within 10%"
pass "a rigid sphere on an LPS block follows Hertz within 10%, exponent 3/2 within 0.1"
