#!/usr/bin/env python3
"""peri beside the NumPy re-implementation of Peridigm's Elastic + Critical Stretch update
(bench/peers/peridigm_elastic.py) on the fragmenting cylinder: writes the node file
(bench/peers/cylinder_nodes.py, CELLS through the wall; Peridigm's example has 5), runs
bench/peers/peri_series on a deck with that node file, the peer force state, bonds to the
horizon (partial_volume: none) and Peridigm's time step, then the re-implementation on the
same file, prints both series side by side and checks that the kinetic energy and the mean
damage agree to TOL (relative; the damage once it is above 1e-3) at every printed step.

  compare_peridigm.py PERI_SERIES [--cells 2] [--end-time 2.5e-4] [--every 20] [--tol 0.01]
"""
import argparse
import os
import subprocess
import sys
import tempfile

from series import rows

HERE = os.path.dirname(os.path.abspath(__file__))
DECK = """dimension: 3
materials:
  steel:
    model: lps
    density: 7800
    bulk_modulus: 130.0e9
    shear_modulus: 78.0e9
    critical_stretch: 0.02
    force_state: {force_state}
discretization:
  node_file: {nodes}
  horizon: {horizon!r}
  partial_volume: none
boundary_conditions:
  - type: initial_velocity
    region: all
    x: "(200 - 50*((z/0.05) - 1)^2) * x / sqrt(x^2 + y^2)"
    y: "(200 - 50*((z/0.05) - 1)^2) * y / sqrt(x^2 + y^2)"
    z: "100*((z/0.05) - 1)"
solver:
  type: explicit
  time_step: {dt!r}
  steps: {steps}
output:
  picture: false
"""


def main():
    p = argparse.ArgumentParser()
    p.add_argument("peri_series")
    p.add_argument("--cells", type=int, default=2)
    p.add_argument("--end-time", type=float, default=2.5e-4)
    p.add_argument("--every", type=int, default=20)
    p.add_argument("--tol", type=float, default=0.01)
    p.add_argument("--force-state", default="peer")
    a = p.parse_args()
    size = 0.005 / a.cells
    horizon = 4.17462 * size         # Peridigm's example: 4.17462 mm at 1 mm cells
    dt = 1.8643e-7 * size / 0.001    # its time step (Verlet, safety factor 0.7) at 1 mm cells
    steps = int(round(a.end_time / dt))
    with tempfile.TemporaryDirectory() as tmp:
        nodes = os.path.join(tmp, "cylinder.txt")
        subprocess.run([sys.executable, os.path.join(HERE, "cylinder_nodes.py"), str(a.cells), nodes], check=True,
                       capture_output=True)
        deck = os.path.join(tmp, "cylinder.yaml")
        with open(deck, "w") as f:
            f.write(DECK.format(nodes=nodes, horizon=horizon, dt=dt, steps=steps, force_state=a.force_state))
        peri = subprocess.run([a.peri_series, deck, "-", str(a.every)], capture_output=True, text=True)
        if peri.returncode != 0:
            sys.stderr.write(peri.stdout + peri.stderr)
            return 2
        ref = subprocess.run([sys.executable, os.path.join(HERE, "peridigm_elastic.py"), nodes, "--horizon", repr(horizon),
                              "--dt", repr(dt), "--steps", str(steps), "--every", str(a.every)],
                             capture_output=True, text=True)
        if ref.returncode != 0:
            sys.stderr.write(ref.stdout + ref.stderr)
            return 2
    P, R = rows(peri.stdout), rows(ref.stdout)
    ok = len(P) > 1
    print("cells %d, horizon %.6g m, dt %.6g s, %d steps, force state %s" % (a.cells, horizon, dt, steps, a.force_state))
    print("%-6s %-10s %-12s %-12s %-9s %-12s %-12s %-9s" % ("step", "t (us)", "damage peri", "damage ref", "rel",
                                                          "KE peri (J)", "KE ref (J)", "rel"))
    for step in sorted(set(P) & set(R)):
        dp, dr, kp, kr = P[step][0], R[step][0], P[step][2], R[step][2]
        rel_d = abs(dp - dr) / dr if dr > 1e-3 else abs(dp - dr)
        rel_k = abs(kp - kr) / kr
        ok = ok and rel_d <= a.tol and rel_k <= a.tol
        print("%-6d %-10.4g %-12.6g %-12.6g %-9.2g %-12.6g %-12.6g %-9.2g" % (step, step * dt * 1e6, dp, dr, rel_d, kp,
                                                                           kr, rel_k))
    final = R[max(R)][0] if R else 0.0
    print("kinetic energy and damage agree to %g at every row: %s; final damage %.4g" % (a.tol, "yes" if ok else "NO",
                                                                                     final))
    return 0 if ok and final > 0.01 else 1


if __name__ == "__main__":
    sys.exit(main())
