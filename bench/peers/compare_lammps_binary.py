#!/usr/bin/env python3
"""peri beside LAMMPS itself (the `lmp` program of Debian's lammps package) on the LAMMPS
examples/peri problem with the pair style's short-range contact forces, which LAMMPS always
runs and peri runs with contact.short_range (docs/contact.md). LAMMPS runs
/usr/share/lammps/examples/peri/in.peri.MODEL (optionally a smaller target) and prints the mean
of compute damage/atom (the broken-bond fraction) and the kinetic energy every EVERY steps;
peri runs examples/lammps_peri_MODEL.yaml through bench/peers/peri_series with the same target.
Checks the broken-bond fraction to TOL and the kinetic energy to KE_TOL (relative) at every
printed step. Exit 0 when they agree, 1 when not, 77 when LAMMPS is not installed (skipped).

  compare_lammps_binary.py PERI_SERIES MODEL [--tol 1e-6] [--ke-tol 1e-6] [--radius R]
                           [--length L] [--steps N] [--every 100]
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

from series import rows

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
EXAMPLES = "/usr/share/lammps/examples/peri"
VOLUME = 1.25e-10  # set group all volume 1.25e-10: LAMMPS's KinEng sums rho v^2/2 (rmass = density)


def lammps_rows(text):
    """{step: [broken fraction, kinetic energy]} of the thermo lines `step c_2 ke`."""
    out, on = {}, False
    for line in text.splitlines():
        f = line.split()
        if f[:1] == ["Step"]:
            on = True
            continue
        if on and len(f) == 3:
            try:
                out[int(f[0])] = [float(f[1]), float(f[2]) * VOLUME]
            except ValueError:
                on = False
        elif on:
            on = False
    return out


def main():
    p = argparse.ArgumentParser()
    p.add_argument("peri_series")
    p.add_argument("model", choices=["pmb", "lps"])
    p.add_argument("--tol", type=float, default=1e-6)
    p.add_argument("--ke-tol", type=float, default=1e-6)
    p.add_argument("--every", type=int, default=100)
    p.add_argument("--steps", type=int, default=1000)
    p.add_argument("--radius", type=float, default=0.005)
    p.add_argument("--length", type=float, default=0.005)
    a = p.parse_args()
    lmp = shutil.which("lmp") or shutil.which("lmp_serial")
    if not lmp or not os.path.exists(os.path.join(EXAMPLES, "in.peri." + a.model)):
        print("LAMMPS (lmp and its examples/peri) not installed: skipped (scripts/install-deps --bench)")
        return 77
    with open(os.path.join(EXAMPLES, "in.peri." + a.model)) as f:
        script = f.read()
    region = "region          target cylinder y 0.0 0.0 0.0050 -0.0050 0.0 units box"
    if region not in script:
        sys.stderr.write("in.peri.%s: the target region line changed\n" % a.model)
        return 2
    script = script.replace(region, "region target cylinder y 0.0 0.0 %r %r 0.0 units box" % (a.radius, -a.length))
    script = script.replace("thermo          100", "compute 2 all reduce ave c_1\nthermo_style custom step c_2 ke\n"
                            "thermo %d" % a.every)
    script = script.replace("run             1000", "run %d" % a.steps)
    deck = os.path.join(ROOT, "examples", "lammps_peri_%s.yaml" % a.model)
    sets = ["solver.steps=%d" % a.steps, "discretization.fill.0.radius=%r" % a.radius,
            "discretization.fill.0.length=%r" % a.length,
            "discretization.fill.0.center=[0, %r, 0]" % (-a.length), "contact.short_range=true"]
    with tempfile.TemporaryDirectory() as tmp:
        with open(os.path.join(tmp, "in.peri"), "w") as f:
            f.write(script)
        ref = subprocess.run([lmp, "-in", "in.peri", "-log", "none"],
                             capture_output=True, text=True, cwd=tmp)
        if ref.returncode != 0:
            sys.stderr.write(ref.stdout + ref.stderr)
            return 2
        peri = subprocess.run([a.peri_series, deck, "-", str(a.every)] + sets, capture_output=True, text=True)
        if peri.returncode != 0:
            sys.stderr.write(peri.stdout + peri.stderr)
            return 2
    P, L = rows(peri.stdout), lammps_rows(ref.stdout)
    ok = sorted(P) == sorted(L) and len(P) > 1
    print("%-6s %-14s %-14s %-10s %-12s %-12s %-10s" % ("step", "broken peri", "broken LAMMPS", "|diff|",
                                                       "KE peri (J)", "KE LAMMPS", "rel diff"))
    for step in sorted(set(P) | set(L)):
        if step not in P or step not in L:
            print("%-6d missing in %s" % (step, "peri" if step not in P else "LAMMPS"))
            ok = False
            continue
        dd = abs(P[step][1] - L[step][0])
        ke = abs(P[step][2] - L[step][1]) / max(abs(L[step][1]), 1e-300)
        ok = ok and dd <= a.tol and (L[step][1] == 0.0 or ke <= a.ke_tol)
        print("%-6d %-14.8g %-14.8g %-10.2g %-12.6g %-12.6g %-10.2g" % (step, P[step][1], L[step][0], dd, P[step][2],
                                                                       L[step][1], ke))
    final = L[max(L)][0] if L else 0.0
    print("broken-bond fraction agrees to %g, kinetic energy to %g: %s; final fraction %.6g" %
          (a.tol, a.ke_tol, "yes" if ok else "NO", final))
    return 0 if ok and final > 0.0 else 1


if __name__ == "__main__":
    sys.exit(main())
