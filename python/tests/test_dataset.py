"""The graph dataset (output.dataset, docs/datasets.md) read with h5py alone: the PMB
internal force of every node, recomputed from the exported edges (receiver, sender,
stretch, broken flag) and constants, is the exported f; and identical runs give identical
files."""
import math
import os
import unittest

import numpy as np

import peri
from support import SOURCE_DIR, TempDirCase

try:
    import h5py
except ImportError:  # Debian python3-h5py, scripts/install-deps
    h5py = None

PLATE = os.path.join(SOURCE_DIR, "tests", "cli", "decks", "plate_pmb.yaml")
# the pre-cracked glass plate of the command-line tests: the crack grows from step ~100
OVERRIDES = {"output.dataset.every": 100, "output.dataset.tags.load": 3.0e6,
             "output.dataset.tags.defect": "crack", "output.picture": "false"}


def run_plate(directory):
    with peri.Simulation(PLATE, overrides=OVERRIDES, output=directory) as sim:
        sim.run()
    return os.path.join(directory, "plate_pmb_graph.h5")


def pmb_forces(h5, frame):
    """f_i = sum over the intact edges k with receiver i of c omega beta V_sender s_k y/|y|
    (docs/models.md, PMB), from the file's arrays and constants only."""
    g, mat = h5["globals"].attrs, h5["materials"]
    x, volume, material = h5["nodes/x"][...], h5["nodes/volume"][...], h5["nodes/material"][...]
    receiver, sender = h5["edges/receiver"][...], h5["edges/sender"][...]
    u = h5[f"frames/{frame}/u"][...]
    stretch, broken = h5[f"frames/{frame}/stretch"][...], h5[f"frames/{frame}/broken"][...]
    xi = x[sender] - x[receiver]
    y = xi + u[sender] - u[receiver]
    r0, r = np.linalg.norm(xi, axis=1), np.linalg.norm(y, axis=1)
    delta, dx = g["horizon"], g["spacing"]
    assert g["partial_volume"] == b"linear" or g["partial_volume"] == "linear"
    assert g["influence"] in (b"constant", "constant")
    beta = np.clip(0.5 + (delta - r0) / dx, 0.0, 1.0)  # the linear partial-volume ramp
    c = mat["micromodulus"][...]
    c_bond = 0.5 * (c[material[receiver]] + c[material[sender]])
    scale = np.where(broken == 0, c_bond * stretch * beta * volume[sender], 0.0)
    f = np.zeros_like(x)
    for d in range(3):
        f[:, d] = np.bincount(receiver, weights=scale * y[:, d] / r, minlength=len(x))
    return f, (r - r0) / r0, scale


@unittest.skipIf(h5py is None, "h5py is missing: install python3-h5py (scripts/install-deps)")
class GraphDataset(TempDirCase):
    @classmethod
    def setUpClass(cls):
        import tempfile
        cls.dir = tempfile.mkdtemp(prefix="peri_dataset_")
        cls.path = run_plate(os.path.join(cls.dir, "a"))

    @classmethod
    def tearDownClass(cls):
        import shutil
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_constants(self):
        with h5py.File(self.path, "r") as h5:
            g = h5["globals"].attrs
            E, h, delta = h5["materials/youngs_modulus"][0], g["thickness"], g["horizon"]
            # 2D plane stress PMB: c = 9 E / (pi h delta^3) (docs/models.md; Ha & Bobaru 2010)
            self.assertAlmostEqual(h5["materials/micromodulus"][0] / (9 * E / (math.pi * h * delta ** 3)), 1.0, 12)
            self.assertAlmostEqual(h5["materials/poisson_ratio"][0], 1.0 / 3.0, 12)
            self.assertEqual(h5["globals/tags"].attrs["load"], 3.0e6)
            self.assertIn(h5["globals/tags"].attrs["defect"], (b"crack", "crack"))
            self.assertEqual(int(h5.attrs["n_edges"]), len(h5["edges/sender"]))
            self.assertEqual(sorted(h5["frames"].keys()), ["000000", "000001", "000002"])
            self.assertEqual([int(h5[f"frames/{k}"].attrs["step"]) for k in sorted(h5["frames"])], [0, 100, 200])
            # bidirected: every edge (i, j) has its reverse (j, i)
            pairs = set(zip(h5["edges/receiver"][...].tolist(), h5["edges/sender"][...].tolist()))
            self.assertTrue(all((j, i) in pairs for i, j in pairs))

    def test_forces_from_edges(self):
        with h5py.File(self.path, "r") as h5:
            broken_last = int(h5["frames/000002/broken"][...].sum())
            self.assertGreater(broken_last, int(h5["frames/000000/broken"][...].sum()),
                               "bonds broke during the run: the broken flags are exercised")
            for frame in sorted(h5["frames"].keys()):
                f, stretch, bond_force = pmb_forces(h5, frame)
                exported = h5[f"frames/{frame}/f"][...]
                scale = np.abs(exported).max()
                if frame != "000000":
                    self.assertGreater(scale, 0.0)
                err = np.abs(f - exported).max() / max(scale, 1e-300)
                self.assertLess(err, 1e-10, f"frame {frame}: f recomputed from the edges differs by {err:.3g} (relative)")
                self.assertLess(np.abs(stretch - h5[f"frames/{frame}/stretch"][...]).max(), 1e-12)
                bf = h5[f"frames/{frame}/bond_force"][...]
                self.assertLess(np.abs(bond_force - bf).max(), 1e-10 * max(np.abs(bf).max(), 1e-300))

    def test_identical_runs_identical_bytes(self):
        again = run_plate(os.path.join(self.dir, "b"))
        with open(self.path, "rb") as a, open(again, "rb") as b:
            self.assertEqual(a.read(), b.read(), "two runs of one deck give different dataset files")


if __name__ == "__main__":
    unittest.main()
