"""Scenario generator and batch runner for graph datasets (docs/surrogates.md).

A material table (CSV, python/surrogate/data/materials.csv) becomes peri decks of 2D plates
in tension, each material under several load magnitudes with no defect, a random pre-crack
or random holes (drawn from the seed), split into train and test sets by material; the batch
runs them with `peri run` and writes one graph dataset (output.dataset, docs/datasets.md)
per run. An interrupted batch resumes: a run whose marker file exists is not redone.

    python3 -m surrogate.generate --out data/small --train 12 --test 4 --peri build/peri

The same table, seed and options give the same decks, and so byte-identical datasets."""
import argparse
import csv
import math
import os
import random
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_TABLE = os.path.join(HERE, "data", "materials.csv")
DEFECTS = ("none", "crack", "holes")


def read_materials(path):
    """The rows of the table (comment lines start with #), numbers as floats (None when empty)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    out = []
    for line, row in enumerate(rows, start=2):
        try:
            m = {"class": row["class"], "name": row["name"], "source": row["source"],
                 "E": float(row["youngs_modulus_GPa"]) * 1e9, "nu": float(row["poisson_ratio"]),
                 "rho": float(row["density_kg_m3"]), "K_IC": float(row["fracture_toughness_MPa_sqrt_m"]) * 1e6,
                 "yield": float(row["yield_stress_MPa"]) * 1e6 if row["yield_stress_MPa"] else None,
                 "n": float(row["hardening_exponent"]) if row["hardening_exponent"] else None}
        except (KeyError, ValueError) as e:
            raise SystemExit(f"{path}: material row {line}: {e}")
        if not (m["E"] > 0 and 0 < m["nu"] < 0.5 and m["rho"] > 0 and m["K_IC"] > 0):
            raise SystemExit(f"{path}: material '{m['name']}': E, rho, K_IC must be > 0 and nu in (0, 0.5)")
        out.append(m)
    return out


class Plate:
    """The plate of every scenario: L x H, spacing dx, horizon 3 dx (plane stress)."""

    def __init__(self, length=0.04, height=0.02, spacing=1.0e-3, steps=200, every=5):
        self.L, self.H, self.dx, self.steps, self.every = length, height, spacing, steps, every
        self.delta = 3.0 * spacing


def critical_stretch(m, plate):
    """s0 of plane-stress PMB from G0 = K_IC^2 / E (Ha & Bobaru 2010): sqrt(4 pi G0 / (9 E delta))."""
    G0 = m["K_IC"] ** 2 / m["E"]
    return math.sqrt(4.0 * math.pi * G0 / (9.0 * m["E"] * plate.delta))


def scenario_deck(m, plate, defect, load_factor, rng, name):
    """The YAML deck of one scenario: the traction is load_factor E s0 on the top and bottom rows."""
    traction = load_factor * m["E"] * critical_stretch(m, plate)
    L, H, dx = plate.L, plate.H, plate.dx
    lines = [f"# graph dataset scenario {name}: {m['name']} ({m['class']}), defect {defect}, "
             f"traction {traction:.6g} Pa ({load_factor:g} E s0)",
             "dimension: 2", "plane: stress", "materials:", f"  {m['name']}:", "    model: lps",
             f"    density: {m['rho']:.6g}", f"    youngs_modulus: {m['E']:.6g}", f"    poisson_ratio: {m['nu']:.6g}",
             f"    fracture_toughness: {m['K_IC']:.6g}",
             "discretization:", f"  spacing: {dx:.6g}", "  m: 3", f"  thickness: {dx:.6g}",
             f"  fill: [{{shape: rectangle, min: [0, 0], max: [{L:.6g}, {H:.6g}]}}]"]
    # defects from the scenario's own random stream, away from the loaded rows
    margin = 3 * dx
    if defect == "holes":
        holes = []
        for _ in range(rng.randint(1, 3)):
            r = rng.uniform(1.5 * dx, 3.5 * dx)
            holes.append(f"{{shape: circle, center: [{rng.uniform(r + dx, L - r - dx):.6g}, "
                         f"{rng.uniform(margin + r + dx, H - margin - r - dx):.6g}], radius: {r:.6g}}}")
        lines.append(f"  remove: [{', '.join(holes)}]")
    if defect == "crack":
        a = rng.uniform(0.15, 0.35) * L
        x0, y0 = rng.uniform(0.2 * L, 0.8 * L), rng.uniform(0.35 * H, 0.65 * H)
        angle = rng.uniform(-math.pi / 6, math.pi / 6)
        dxa, dya = 0.5 * a * math.cos(angle), 0.5 * a * math.sin(angle)
        lines.append(f"precracks: [{{from: [{x0 - dxa:.6g}, {y0 - dya:.6g}], to: [{x0 + dxa:.6g}, {y0 + dya:.6g}]}}]")
    lines += ["regions:",
              f"  top: {{shape: rectangle, min: [-{dx:.6g}, {H - dx:.6g}], max: [{L + dx:.6g}, {H + dx:.6g}]}}",
              f"  bottom: {{shape: rectangle, min: [-{dx:.6g}, -{dx:.6g}], max: [{L + dx:.6g}, {dx:.6g}]}}",
              f"  top_rows: {{shape: rectangle, min: [-{dx:.6g}, {H - 3 * dx:.6g}], max: [{L + dx:.6g}, {H + dx:.6g}], no_fail: true}}",
              f"  bottom_rows: {{shape: rectangle, min: [-{dx:.6g}, -{dx:.6g}], max: [{L + dx:.6g}, {3 * dx:.6g}], no_fail: true}}",
              "boundary_conditions:",
              f"  - {{type: traction, region: top, y: {traction:.6g}}}",
              f"  - {{type: traction, region: bottom, y: {-traction:.6g}}}",
              "solver:", "  type: explicit", f"  steps: {plate.steps}", "  safety_factor: 0.8",
              "output:", "  every: 1000000", "  history_every: 1000000", "  picture: false",
              f"  dataset: {{every: {plate.every}, file: graph.h5, "
              f"tags: {{traction: {traction:.6g}, load_factor: {load_factor:g}, defect: {defect}, "
              f"material: {m['name']}, material_class: {m['class']}}}}}"]
    return "\n".join(lines) + "\n"


def plan(materials, seed, n_train, n_test, load_factors, defects, plate):
    """(name, split, deck text) of every scenario, in a fixed order."""
    if n_train + n_test > len(materials):
        raise SystemExit(f"asked for {n_train} + {n_test} materials, the table has {len(materials)}")
    rng = random.Random(seed)
    chosen = rng.sample(range(len(materials)), n_train + n_test)
    runs = []
    for rank, index in enumerate(chosen):
        m = materials[index]
        split = "train" if rank < n_train else "test"
        for defect in defects:
            for load in load_factors:
                name = f"{split}/{m['name']}_{defect}_{load:g}"
                scenario_rng = random.Random(f"{seed}/{name}")  # one stream per scenario: order-free
                runs.append((name, split, scenario_deck(m, plate, defect, load, scenario_rng, name)))
    return runs


def run_batch(runs, out, peri, threads, log=sys.stderr):
    """Writes the decks under out/ and runs those without a marker file; returns failures."""
    failures, t0 = 0, time.time()
    for k, (name, _, deck) in enumerate(runs, start=1):
        folder = os.path.join(out, name)
        marker = os.path.join(folder, "done")
        if os.path.exists(marker):
            print(f"[{k}/{len(runs)}] {name}: done before, kept", file=log)
            continue
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, "deck.yaml"), "w") as f:
            f.write(deck)
        t = time.time()
        result = subprocess.run([peri, "run", os.path.join(folder, "deck.yaml"), "--quiet", "--threads", str(threads),
                                 "--output", folder], capture_output=True, text=True)
        if result.returncode != 0:
            failures += 1
            print(f"[{k}/{len(runs)}] {name}: FAILED (status {result.returncode}): {result.stderr.strip()}", file=log)
            continue
        open(marker, "w").close()
        left = (time.time() - t0) / k * (len(runs) - k)
        print(f"[{k}/{len(runs)}] {name}: {time.time() - t:.1f} s (about {left:.0f} s left)", file=log)
    return failures


def write_manifest(runs, out):
    with open(os.path.join(out, "manifest.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["run", "split", "file"])
        for name, split, _ in runs:
            w.writerow([name, split, f"{name}/graph.h5"])


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--materials", default=DEFAULT_TABLE, help="material table CSV (default: the shipped table)")
    p.add_argument("--out", required=True, help="dataset folder (decks, runs, manifest.csv)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--train", type=int, default=12, help="materials in the training set")
    p.add_argument("--test", type=int, default=4, help="materials in the test set (never seen in training)")
    p.add_argument("--loads", default="0.6,1.0", help="traction magnitudes as multiples of E s0, comma-separated")
    p.add_argument("--defects", default=",".join(DEFECTS), help="of none, crack, holes")
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--every", type=int, default=5, help="steps between graph frames")
    p.add_argument("--spacing", type=float, default=1.0e-3, help="grid spacing of the 40 x 20 mm plate (m)")
    p.add_argument("--peri", default=os.environ.get("PERI_PROGRAM", "peri"), help="the peri program")
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--decks-only", action="store_true", help="write the decks and manifest, run nothing")
    a = p.parse_args(argv)
    defects = tuple(d for d in a.defects.split(",") if d)
    bad = [d for d in defects if d not in DEFECTS]
    if bad:
        p.error(f"--defects: unknown {bad} (choose from {', '.join(DEFECTS)})")
    loads = [float(x) for x in a.loads.split(",")]
    plate = Plate(spacing=a.spacing, steps=a.steps, every=a.every)
    runs = plan(read_materials(a.materials), a.seed, a.train, a.test, loads, defects, plate)
    os.makedirs(a.out, exist_ok=True)
    write_manifest(runs, a.out)
    if a.decks_only:
        for name, _, deck in runs:
            os.makedirs(os.path.join(a.out, name), exist_ok=True)
            with open(os.path.join(a.out, name, "deck.yaml"), "w") as f:
                f.write(deck)
        return 0
    failures = run_batch(runs, a.out, a.peri, a.threads)
    if failures:
        print(f"{failures} of {len(runs)} runs failed; run the same command again to retry them", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
