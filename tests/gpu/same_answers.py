#!/usr/bin/env python3
"""The GPU path against the CPU path (docs/gpu.md, "Same answers").

Runs each case's deck twice, `--device cpu` and `--device gpu`, with every digit of
history.csv (output.history_digits 17), and compares the histories row by row and column by
column: every value within 1e-12 of its scale (round-off: the GPU sums each node's bonds in
the same order, but its lengths come from other instructions than the CPU's vector kernels),
and the same broken bonds. A column's scale is its largest magnitude over the run, or that of
its kind where larger: the energies' largest for an energy, the largest reaction or indenter
force for a force, and for a momentum the largest momentum or sqrt(2 M KE), M the body's
mass and KE its largest kinetic energy (a momentum that is zero by symmetry is round-off of
sums of terms of that size).

A last case, `restart_pmb_3d`, runs the LAMMPS problem on the GPU with a checkpoint at step
100 and again from that checkpoint, also on the GPU: the two histories must be the same file
(skipped, and said so, in a build without HDF5).

With --reference PERI_REFERENCE (the program built with the CPU's scalar bond loops, whose
operations the GPU kernels follow one for one) the GPU is held to it instead, within 1e-12,
and to the CPU's vector kernels (those of PERI) no farther than the scalar loops themselves
are from them (twice that difference, or 1e-12 if larger): two CPU builds differ at
round-off, which dynamics with breaking carries on. The strain energy and the energy balance
are left out of the comparison with the scalar loops: the host computes them from the GPU's
state with the program's own (vector) energy kernels, so they are compared with the vector
run. Where a bond's stretch lies within round-off of its critical stretch the two
runs may break it at different steps, after which they may part: the first row whose
broken-bond fraction differs is reported as such, the rows before it are compared and the
rows after it are not. A case passes when its rows agree up to that point and at least half
of them were compared.

usage: same_answers.py PERI [--reference PERI_REFERENCE] [--repo DIR] [--keep DIR] [--only NAME ...]
Exit status 0 when every case passes, 1 otherwise.
"""
import argparse
import csv
import os
import re
import subprocess
import sys
import tempfile
import time

TOLERANCE = 1e-12  # relative to the column's scale (the target for the histories)

# name, deck (from the repository root), settings
CASES = [
    ("lammps_pmb_3d", "examples/lammps_peri_pmb.yaml",
     ["solver.steps=300", "output.history_every=10", "output.every=300"]),
    ("lammps_lps_3d", "examples/lammps_peri_lps.yaml",
     ["solver.steps=300", "output.history_every=10", "output.every=300"]),
    ("quickstart_pmb_2d", "examples/quickstart.yaml",
     ["solver.end_time=2.0e-5", "output.history_every=10", "output.frames=1", "output.picture=false"]),
    ("lps_two_materials_2d", "tests/gpu/decks/lps_two_materials_2d.yaml", []),
    ("wave_pmb_1d", "examples/wave_in_bar.yaml", ["output.history_every=10"]),
    ("kalthoff_pmb_3d", "examples/kalthoff_winkler.yaml",
     ["output.history_every=5", "output.frames=1", "output.picture=false"]),
    ("cylinder_lps_3d", "examples/fragmenting_cylinder.yaml",
     ["solver.end_time=1.0e-4", "output.history_every=10", "output.frames=1", "output.picture=false"]),
]


def read_history(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(v) for v in r] for r in rows[1:]]


def run(peri, repo, deck, sets, device, out):
    """(seconds, mass, broken bonds) of the run"""
    cmd = [peri, "run", os.path.join(repo, deck), "--progress=0", "--device", device, "--output", out,
           "--set", "output.history_digits=17"]
    for s in sets:
        cmd += ["--set", s]
    t = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()}")
    if device == "gpu" and "device       GPU" not in p.stdout:
        raise RuntimeError(f"the run did not take the GPU: {p.stderr.strip()}")
    mass = float(re.search(r"^  mass +(\S+) kg", p.stdout, re.M).group(1))
    broken = int(re.search(r"^  broken bonds (\d+)", p.stdout, re.M).group(1))
    return time.time() - t, mass, broken


def kind_of(name):
    if name.endswith("energy") or name in ("external_work", "energy_balance"):
        return "energy"
    if name.startswith("reaction_") or name.startswith("indenter_force_"):
        return "force"
    if name.startswith("momentum_"):
        return "momentum"
    return None


HOST_ENERGY = ("strain_energy", "energy_balance")


def compare(header, cpu, gpu, mass, tolerance=TOLERANCE, label="CPU", leave_out=()):
    """(passed, report lines, largest difference)"""
    lines = []
    if len(cpu) != len(gpu):
        return False, [f"rows: {label} {len(cpu)}, GPU {len(gpu)}"], float("inf")
    broken = header.index("broken_bond_fraction") if "broken_bond_fraction" in header else None
    parted = len(cpu)
    if broken is not None:
        for r, (a, b) in enumerate(zip(cpu, gpu)):
            if a[broken] != b[broken]:
                parted = r
                lines.append(f"broken bonds part at row {r} (t = {a[0]:.6g}): fraction {label} {a[broken]:.10g}, GPU "
                             f"{b[broken]:.10g} (a bond within round-off of its critical stretch); rows from there "
                             f"not compared")
                break
    own = [max([abs(r[c]) for r in cpu[:parted]] + [abs(r[c]) for r in gpu[:parted]] + [0.0])
           for c in range(len(header))]
    kinds = {}
    for c, name in enumerate(header):
        if kind_of(name):
            kinds[kind_of(name)] = max(kinds.get(kind_of(name), 0.0), own[c])
    if "kinetic_energy" in header:
        ke = own[header.index("kinetic_energy")]
        kinds["momentum"] = max(kinds.get("momentum", 0.0), (2.0 * mass * ke) ** 0.5)
    worst, where = 0.0, ""
    for c, name in enumerate(header):
        if name in leave_out:
            continue
        scale = max(own[c], kinds.get(kind_of(name), 0.0))
        for r in range(parted):
            d = abs(cpu[r][c] - gpu[r][c])
            rel = d / scale if scale > 0 else (0.0 if d == 0 else float("inf"))
            if rel > worst:
                worst, where = rel, f"{name} at row {r} ({label} {cpu[r][c]:.12g}, GPU {gpu[r][c]:.12g})"
    lines.append(f"against {label}: {parted} of {len(cpu)} rows compared, largest difference {worst:.3g} of the "
                 f"column's scale (tolerance {tolerance:.3g})" + (f": {where}" if where else ""))
    ok = worst <= tolerance and parted >= max(1, len(cpu) // 2)
    return ok, lines, worst


def restart_case(peri, repo, work):
    """(passed or None when skipped, report lines)"""
    deck = os.path.join(repo, "examples/lammps_peri_pmb.yaml")
    sets = ["solver.steps=200", "output.history_every=10", "output.history_digits=17",
            "output.checkpoint_every=100", "output.checkpoint_file=ck_{step}.h5"]
    full, part = os.path.join(work, "restart", "full"), os.path.join(work, "restart", "part")
    cmd = [peri, "run", deck, "--progress=0", "--device", "gpu", "--output", full]
    for s in sets:
        cmd += ["--set", s]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0 and "HDF5" in p.stderr:
        return None, ["skipped: this build writes no checkpoints (no HDF5)"]
    if p.returncode != 0:
        return False, [f"the run failed: {p.stderr.strip()}"]
    import shutil
    shutil.rmtree(part, ignore_errors=True)
    shutil.copytree(full, part)
    cmd[cmd.index(full)] = part
    p = subprocess.run(cmd + ["--restart", os.path.join(part, "ck_000100.h5")], capture_output=True, text=True)
    if p.returncode != 0:
        return False, [f"the restart failed: {p.stderr.strip()}"]
    with open(os.path.join(full, "history.csv"), "rb") as a, open(os.path.join(part, "history.csv"), "rb") as b:
        same = a.read() == b.read()
    return same, ["restarted at step 100: history.csv " + ("the same file" if same else "DIFFERS")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("peri")
    ap.add_argument("--reference", help="the program with the CPU's scalar bond loops (peri-reference)")
    ap.add_argument("--repo", default=os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
    ap.add_argument("--keep", help="write the runs here (else a temporary folder)")
    ap.add_argument("--only", nargs="*", help="the cases to run (default: all)")
    args = ap.parse_args()
    work = args.keep or tempfile.mkdtemp(prefix="peri-gpu-")
    failed = 0
    for name, deck, sets in CASES:
        if args.only and name not in args.only:
            continue
        try:
            t_cpu, mass, broken_cpu = run(args.peri, args.repo, deck, sets, "cpu", os.path.join(work, name, "cpu"))
            t_gpu, _, broken_gpu = run(args.peri, args.repo, deck, sets, "gpu", os.path.join(work, name, "gpu"))
            header, cpu = read_history(os.path.join(work, name, "cpu", "history.csv"))
            header_g, gpu = read_history(os.path.join(work, name, "gpu", "history.csv"))
            if header != header_g:
                raise ValueError("the columns differ")
            if args.reference:
                _, _, broken_ref = run(args.reference, args.repo, deck, sets, "cpu", os.path.join(work, name, "ref"))
                _, ref = read_history(os.path.join(work, name, "ref", "history.csv"))
                ok, lines, _ = compare(header, ref, gpu, mass, TOLERANCE, "CPU scalar", HOST_ENERGY)
                _, _, apart = compare(header, cpu, ref, mass, float("inf"), "CPU vector")
                ok_v, lines_v, _ = compare(header, cpu, gpu, mass, max(2.0 * apart, TOLERANCE), "CPU vector")
                ok, lines = ok and ok_v, lines + lines_v
                lines.append(f"the CPU's scalar loops against its vector kernels: {apart:.3g}")
                lines.append(f"broken bonds at the end: CPU scalar {broken_ref}, CPU vector {broken_cpu}, GPU {broken_gpu}")
                if broken_ref != broken_gpu and not any("broken bonds part" in l for l in lines):
                    ok = False
            else:
                ok, lines, _ = compare(header, cpu, gpu, mass)
                lines.append(f"broken bonds at the end: CPU {broken_cpu}, GPU {broken_gpu}")
                if broken_cpu != broken_gpu and not any("broken bonds part" in l for l in lines):
                    ok = False
        except (RuntimeError, OSError, ValueError) as e:
            ok, lines, t_cpu, t_gpu = False, [str(e)], 0.0, 0.0
        failed += not ok
        print(f"{'PASS' if ok else 'FAIL'} {name} (CPU {t_cpu:.1f} s, GPU {t_gpu:.1f} s)")
        for line in lines:
            print("     " + line)
        sys.stdout.flush()
    if not args.only or "restart_pmb_3d" in args.only:
        ok, lines = restart_case(args.peri, args.repo, work)
        failed += ok is False
        print(f"{'SKIP' if ok is None else 'PASS' if ok else 'FAIL'} restart_pmb_3d")
        for line in lines:
            print("     " + line)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
