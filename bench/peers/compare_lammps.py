#!/usr/bin/env python3
"""peri beside the NumPy re-implementation of the LAMMPS PERI loop (bench/peers/lammps_peri.py)
on the same node set: runs bench/peers/peri_series on examples/lammps_peri_MODEL.yaml with the
given --set overrides, then lammps_peri.py on the nodes it wrote, prints both series side by
side and checks that the mean damage (peri's index and the broken-bond fraction) agrees to
TOL at every printed step. Exit status 0 when it does, 1 otherwise.

  compare_lammps.py PERI_SERIES MODEL [--tol 1e-6] [--every 100] [--radius R --length L]
                    [--steps N] [--short-range] [--set key=value ...]

With --short-range both run the pair styles' short-range contact forces (peri:
contact.short_range, docs/contact.md).
"""
import argparse
import os
import subprocess
import sys
import tempfile

from series import rows

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("peri_series")
    p.add_argument("model", choices=["pmb", "lps"])
    p.add_argument("--tol", type=float, default=1e-6)
    p.add_argument("--every", type=int, default=100)
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--radius", type=float, default=0.005)
    p.add_argument("--length", type=float, default=0.005)
    p.add_argument("--set", action="append", default=[])
    p.add_argument("--short-range", action="store_true")
    a = p.parse_args()
    deck = os.path.join(ROOT, "examples", "lammps_peri_%s.yaml" % a.model)
    sets = ["solver.steps=%d" % a.steps, "discretization.fill.0.radius=%r" % a.radius,
            "discretization.fill.0.length=%r" % a.length,
            "discretization.fill.0.center=[0, %r, 0]" % (-a.length)] + a.set
    if a.short_range:
        sets.append("contact.short_range=true")
    with tempfile.TemporaryDirectory() as tmp:
        nodes = os.path.join(tmp, "nodes.txt")
        peri = subprocess.run([a.peri_series, deck, nodes, str(a.every)] + sets, capture_output=True, text=True)
        if peri.returncode != 0:
            sys.stderr.write(peri.stdout + peri.stderr)
            return 2
        ref = subprocess.run([sys.executable, os.path.join(HERE, "lammps_peri.py"), nodes, "--model", a.model,
                              "--steps", str(a.steps), "--every", str(a.every)] + (["--short-range"] if a.short_range else []),
                             capture_output=True, text=True)
        if ref.returncode != 0:
            sys.stderr.write(ref.stdout + ref.stderr)
            return 2
    P, R = rows(peri.stdout), rows(ref.stdout)
    ok = sorted(P) == sorted(R) and len(P) > 1
    print("%-6s %-12s %-12s %-10s %-12s %-12s %-10s" % ("step", "damage peri", "damage ref", "|diff|",
                                                       "KE peri (J)", "KE ref (J)", "rel diff"))
    for step in sorted(set(P) | set(R)):
        if step not in P or step not in R:
            print("%-6d missing in %s" % (step, "peri" if step not in P else "the re-implementation"))
            ok = False
            continue
        dd = max(abs(P[step][0] - R[step][0]), abs(P[step][1] - R[step][1]))
        ke_rel = abs(P[step][2] - R[step][2]) / max(abs(R[step][2]), 1e-300)
        ok = ok and dd <= a.tol
        print("%-6d %-12.6g %-12.6g %-10.2g %-12.6g %-12.6g %-10.2g" % (step, P[step][0], R[step][0], dd, P[step][2],
                                                                      R[step][2], ke_rel))
    final = R[max(R)] if R else [0.0]
    print("mean damage agrees to %g at every row: %s; final damage %.6g" % (a.tol, "yes" if ok else "NO", final[0]))
    return 0 if ok and final[0] > 0.0 else 1


if __name__ == "__main__":
    sys.exit(main())
