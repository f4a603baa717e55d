"""The graph-network surrogate (python/surrogate, docs/surrogates.md) trained briefly on a
tiny dataset beats the constant-velocity baseline on materials it never saw. Skipped with a
message where PyTorch is missing (Debian python3-torch, scripts/install-deps)."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from support import SOURCE_DIR

try:
    import torch
except ImportError:
    torch = None

PERI = os.environ.get("PERI_PROGRAM", os.path.join(SOURCE_DIR, "build", "peri"))
# 4 train and 2 test materials, no defect and a pre-crack, one load: 12 runs of a coarse
# plate (2 mm spacing, 20 x 10 nodes), 100 steps, a graph frame every 5
GENERATE = ["--train", "4", "--test", "2", "--defects", "none,crack", "--loads", "0.8", "--spacing", "2e-3",
            "--steps", "100", "--every", "5", "--seed", "3", "--peri", PERI]
# the section 8.3 architecture, narrowed to train in seconds
SMALL = {"edge_hidden": 32, "node_hidden": 32, "global_hidden": 32, "latent": 16, "state": 8}


@unittest.skipIf(torch is None, "PyTorch is missing: install python3-torch (scripts/install-deps) to test the "
                                "surrogate models")
class Surrogate(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="peri_surrogate_")
        env = dict(os.environ, PYTHONPATH=os.path.join(SOURCE_DIR, "python"))
        r = subprocess.run([sys.executable, "-m", "surrogate.generate", "--out", cls.dir, *GENERATE], env=env,
                           capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(r.stderr)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_beats_constant_velocity_on_unseen_materials(self):
        from surrogate import evaluate, train
        torch.set_num_threads(2)
        ckpt = os.path.join(self.dir, "forward.pt")
        # two epochs (320 samples; 60-70 s on two cores shared with other work): a fixed amount of
        # training, so the figures do not depend on the machine's speed
        train.train(self.dir, "forward", SMALL, epochs=2, lr=3e-3, noise=0.05, batch=2, out=ckpt, device="cpu")
        r = evaluate.evaluate(self.dir, ckpt, "test", steps=10, pictures=os.path.join(self.dir, "pictures"),
                              device="cpu")
        # The untrained model is the baseline exactly (its decoder's last layer starts at
        # zero: ratio 1.000), so a one-step error below 0.6 of the baseline's, in u* and in
        # v*, on two materials never seen in training, is dynamics the model learned and
        # carried over through the scaled units. Two epochs reach 0.43-0.44 (u*) and
        # 0.39-0.43 (v*) with training seeds 0 and 1: the margin to 0.6 is four times that spread.
        for what in ("one_step_u", "one_step_v"):
            self.assertLess(r[what], 0.6 * r["baseline_" + what], f"{what}: {r}")
        self.assertEqual(len(r["pictures"]), 4)
        with open(r["pictures"][0], "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


if __name__ == "__main__":
    unittest.main()
