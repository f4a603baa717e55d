"""Stepping: n steps and then m steps give the fields and history of n + m steps in one go,
bit for bit, for the explicit solver and for quasi-static load steps."""
import os
import unittest

import numpy as np

import peri
from support import QUICKSTART, QUICKSTART_SHORT, SOURCE_DIR, TempDirCase

QS_BAR = os.path.join(SOURCE_DIR, "tests", "cli", "decks", "qs_bar.yaml")


class Stepping(TempDirCase):
    def compare(self, deck, overrides, n, m, fields):
        parts = peri.Simulation(deck, overrides=overrides, output=self.out("parts"))
        whole = peri.Simulation(deck, overrides=overrides, output=self.out("whole"))
        parts.step(n)
        self.assertEqual(parts.step_index, n)
        parts.field("damage")  # reading fields between the parts changes nothing
        parts.step(m)
        whole.step(n + m)
        self.assertEqual(parts.step_index, n + m)
        self.assertEqual(whole.step_index, n + m)
        self.assertFalse(whole.finished, "the comparison is of a run stopped midway")
        for name in fields:
            a, b = parts.field(name), whole.field(name)
            self.assertTrue(np.array_equal(a, b), f"{name}: largest difference {np.abs(a - b).max()}")
        self.assertTrue(np.array_equal(parts.history().array, whole.history().array))
        broken = whole.history()["broken_bond_fraction"]
        parts.close()
        whole.close()
        return broken

    def test_explicit(self):
        broken = self.compare(QUICKSTART, QUICKSTART_SHORT, 50, 70, ["displacement", "velocity", "force", "damage"])
        self.assertGreater(broken[-1], broken[0], "bonds broke during the steps compared")

    def test_quasi_static_load_steps(self):
        # the bar breaks through at load step 20 of 40: the comparison covers the fracture
        broken = self.compare(QS_BAR, {}, 12, 17, ["displacement", "force", "damage"])
        self.assertGreater(broken[-1], broken[0])

    def test_stepping_past_the_end_stops_there(self):
        with peri.Simulation(QS_BAR, overrides={"solver.load_steps": 5}, output=self.out("end")) as sim:
            sim.step(3)
            self.assertFalse(sim.finished)
            sim.step(10)
            self.assertEqual(sim.step_index, 5)
            self.assertTrue(sim.finished)
            sim.step(1)  # nothing left: a no-op
            self.assertEqual(sim.step_index, 5)
            self.assertEqual(len(sim.history()), 6, "the initial row and one per load step")


if __name__ == "__main__":
    unittest.main()
