"""Errors come back as exceptions carrying peri's messages: a bad deck raises DeckError with
file:line:column before any work, a run that fails RunError, and the interpreter goes on."""
import os
import unittest

import peri
from support import SOURCE_DIR, TempDirCase

VALID = os.path.join(SOURCE_DIR, "tests", "cli", "decks", "valid_small.yaml")


class Errors(TempDirCase):
    def test_misspelt_key_in_a_deck_file(self):
        with open(VALID) as f:
            text = f.read()
        self.assertIn("    density: 2440\n", text)
        bad = text.replace("    density: 2440\n", "    densty: 2440\n")
        line = bad[:bad.index("densty")].count("\n") + 1
        path = self.out("bad.yaml")
        with open(path, "w") as f:
            f.write(bad)
        with self.assertRaises(peri.DeckError) as caught:
            peri.Simulation(path, output=self.out("never"))
        error = caught.exception
        self.assertEqual(error.status, 2)
        self.assertTrue(str(error).startswith(f"{path}:{line}:5: error: unknown key 'densty'"), str(error))
        self.assertIn("did you mean 'density'?", str(error))
        self.assertFalse(os.path.exists(self.out("never")), "no output before the deck is valid")

    def test_misspelt_key_in_a_dict(self):
        deck = {"dimension": 1,
                "materials": {"steel": {"model": "pmb", "density": 7850, "youngs_modulus": 200e9,
                                        "critical_stretch": 1e-3}},
                "discretization": {"spacing": 0.01, "m": 3, "cross_section": 0.01,
                                   "fill": [{"shape": "interval", "min": [0], "max": [1]}]},
                "solver": {"type": "explicit", "stpes": 10}}
        with self.assertRaises(peri.DeckError) as caught:
            peri.Simulation(deck, name="bar")
        # the line and column are those of the key in the YAML text the dict became
        text = peri.deck_to_yaml(deck)
        line = text[:text.index("stpes")].count("\n") + 1
        self.assertTrue(str(caught.exception).startswith(f"bar:{line}:3: error: unknown key 'stpes' in solver"),
                        str(caught.exception))

    def test_missing_deck(self):
        with self.assertRaises(peri.DeckError) as caught:
            peri.Simulation(self.out("no_such_deck.yaml"))
        self.assertIn("cannot open deck", str(caught.exception))

    def test_bad_override(self):
        with self.assertRaises(peri.DeckError) as caught:
            peri.Simulation(VALID, overrides=["discretization.spacing=-1"])
        self.assertRegex(str(caught.exception), r"^--set:1:\d+: error: ")

    def test_unknown_field(self):
        with peri.Simulation(VALID, output=self.out("unknown")) as sim:
            with self.assertRaises(peri.DeckError) as caught:
                sim.field("displacment")
            self.assertIn("unknown field 'displacment'", str(caught.exception))
            sim.step(2)  # the simulation is still usable
            self.assertEqual(sim.step_index, 2)

    def test_divergence_raises_and_the_interpreter_goes_on(self):
        # a time step 3 times the stable estimate: the kinetic energy runs away (the deck's header)
        deck = os.path.join(SOURCE_DIR, "tests", "cli", "decks", "diverge.yaml")
        sim = peri.Simulation(deck, output=self.out("diverge"))
        with self.assertRaises(peri.RunError) as caught:
            sim.run()
        self.assertEqual(caught.exception.status, 1)
        self.assertIn("diverged", str(caught.exception))
        self.assertTrue(sim.finished)
        self.assertLess(sim.step_index, sim.steps)
        with self.assertRaises(peri.RunError) as again:
            sim.step(1)
        self.assertIn("the run stopped at step", str(again.exception))
        self.assertTrue(os.path.exists(os.path.join(self.out("diverge"), "history.csv")), "what was written is kept")
        sim.close()


if __name__ == "__main__":
    unittest.main()
