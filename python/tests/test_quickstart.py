"""The quickstart through the Python module: the damage field it returns has the mean that
the run's history.csv gives (column mean_damage), to the digits the file prints."""
import csv
import os
import unittest

import numpy as np

import peri
from support import QUICKSTART, QUICKSTART_SHORT, TempDirCase


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


class Quickstart(TempDirCase):
    def test_damage_mean_is_the_history_mean(self):
        out = self.out("quickstart")
        with peri.Simulation(QUICKSTART, overrides=QUICKSTART_SHORT, output=out) as sim:
            self.assertEqual(sim.dimension, 2)
            self.assertEqual(sim.nodes, 200 * 80)
            initial = sim.damage.mean()  # the notch (pre-crack) alone
            sim.run()
            self.assertTrue(sim.finished)
            self.assertEqual(sim.step_index, sim.steps)
            damage = sim.damage
            history = sim.history()
        self.assertEqual(damage.shape, (200 * 80,))
        self.assertTrue(np.all((damage >= 0) & (damage <= 1)))
        self.assertGreater(damage.mean(), 1.2 * initial, "the crack should have grown from the notch")

        header, rows = read_csv(os.path.join(out, "history.csv"))
        printed = rows[-1][header.index("mean_damage")]
        # history.csv prints 10 significant digits: equal to within half a unit of the last one
        self.assertLessEqual(abs(damage.mean() - float(printed)), 0.5e-9 * abs(float(printed)),
                             f"mean of the damage field {damage.mean()!r}, history.csv {printed}")

        # the history the module returns is the file's, at full precision
        self.assertEqual(history.columns, header)
        self.assertEqual(len(history), len(rows))
        from_file = np.array([[float(v) for v in row] for row in rows])
        np.testing.assert_allclose(history.array, from_file, rtol=0.5e-9, atol=0)
        self.assertAlmostEqual(history["mean_damage"][-1], damage.mean(), delta=1e-12 * damage.mean())
        self.assertTrue(os.path.exists(os.path.join(out, "damage.png")), "the run finishes as peri run does")

    def test_fields_have_their_shapes(self):
        with peri.Simulation(QUICKSTART, overrides=dict(QUICKSTART_SHORT, **{"solver.end_time": 1e-6}),
                             output=self.out("fields")) as sim:
            sim.step(3)
            n = sim.nodes
            for name in ("position", "reference_position", "displacement", "velocity", "force"):
                self.assertEqual(sim.field(name).shape, (n, 3), name)
            self.assertEqual(sim.field("stress").shape, (n, 3, 3))
            self.assertEqual(sim.field("material").dtype, np.int32)
            np.testing.assert_array_equal(sim.positions, sim.field("reference_position") + sim.displacement)
            # a 2D run: the third components are zero
            self.assertFalse(np.any(sim.displacement[:, 2]))
            self.assertGreater(np.abs(sim.velocity).max(), 0.0, "the traction has set the edges moving")
            with self.assertRaises(peri.DeckError) as caught:
                sim.field("dilatation")  # PMB has none
            self.assertIn("no field 'dilatation'", str(caught.exception))


if __name__ == "__main__":
    unittest.main()
