"""The scenario generator (python/surrogate/generate.py, docs/surrogates.md): the same
material table and seed give byte-identical HDF5 datasets, the split is by material, and an
interrupted batch resumes without redoing finished runs."""
import csv
import filecmp
import os
import subprocess
import sys
import unittest

from support import SOURCE_DIR, TempDirCase

PERI = os.environ.get("PERI_PROGRAM", os.path.join(SOURCE_DIR, "build", "peri"))
# two train materials and one test material, a pre-crack and holes, one load: 6 runs of a
# coarse plate (2 mm spacing, 20 x 10 nodes), 60 steps each
ARGS = ["--train", "2", "--test", "1", "--defects", "crack,holes", "--loads", "1.0", "--spacing", "2e-3",
        "--steps", "60", "--every", "20", "--seed", "7", "--peri", PERI]


def generate(out, *extra):
    env = dict(os.environ, PYTHONPATH=os.path.join(SOURCE_DIR, "python"))
    return subprocess.run([sys.executable, "-m", "surrogate.generate", "--out", out, *ARGS, *extra], env=env,
                          capture_output=True, text=True)


class Generator(TempDirCase):
    def test_deterministic_and_resumable(self):
        a, b = self.out("a"), self.out("b")
        for folder in (a, b):
            r = generate(folder)
            self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(a, "manifest.csv")) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 6)
        for row in rows:
            fa, fb = os.path.join(a, row["file"]), os.path.join(b, row["file"])
            self.assertTrue(filecmp.cmp(fa, fb, shallow=False), f"{row['file']}: the two batches' files differ")
        # split by material: no material in both sets
        material = lambda r: os.path.basename(r["run"]).rsplit("_", 2)[0]
        train = {material(r) for r in rows if r["split"] == "train"}
        test = {material(r) for r in rows if r["split"] == "test"}
        self.assertEqual((len(train), len(test), len(train & test)), (2, 1, 0))
        # the holes and cracks differ between runs (drawn per scenario)
        decks = set()
        for r in rows:
            with open(os.path.join(a, r["run"], "deck.yaml")) as f:
                decks.add(f.read().split("\n", 1)[1])
        self.assertEqual(len(decks), 6)
        # resume: finished runs are kept as they are, a run without its marker is redone
        again = rows[0]
        os.remove(os.path.join(a, again["run"], "done"))
        before = {r["file"]: os.stat(os.path.join(a, r["file"])).st_mtime_ns for r in rows}
        r = generate(a)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stderr.count("done before, kept"), 5, r.stderr)
        for row in rows[1:]:
            self.assertEqual(os.stat(os.path.join(a, row["file"])).st_mtime_ns, before[row["file"]])
        self.assertTrue(filecmp.cmp(os.path.join(a, again["file"]), os.path.join(b, again["file"]), shallow=False))


if __name__ == "__main__":
    unittest.main()
