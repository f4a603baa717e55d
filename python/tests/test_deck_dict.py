"""A deck given as a dict: the same simulation as the YAML file it mirrors, bit for bit, and
a quasi-static patch test with the answer from theory.

The bar: 1D PMB steel, E = 200 GPa, section A = 1e-4 m^2, length 1 m, 100 nodes (m = 3),
both end layers (three nodes each, one horizon) moved with the linear field u = eps x,
eps = 1e-3. A linear field is an exact equilibrium of the peridynamic equations wherever a
node's family is whole, which is every free node here: the free nodes must end at u = eps x
(up to the solver's tolerance, 1e-10 relative). The force across any section is then E A eps:
the bond forces c eps xi beta V V summed over the bonds that cross it, with c = 2E / (A delta^2)
and partial volumes beta, add up to c eps A^2 delta^2 / 2 (the sum of k beta_k h^2 over the
three bond lengths is delta^2 / 2, the exact integral of xi over [0, delta]), = E A eps."""
import unittest

import numpy as np

import peri
from support import TempDirCase

E, A, EPS = 200e9, 1.0e-4, 1.0e-3

BAR = {
    "dimension": 1,
    "materials": {"steel": {"model": "pmb", "density": 7850, "youngs_modulus": E}},
    "discretization": {"spacing": 0.01, "m": 3, "cross_section": A,
                       "fill": [{"shape": "interval", "min": [0], "max": [1]}]},
    "regions": {"left": {"shape": "interval", "min": [-1], "max": [0.03]},
                "right": {"shape": "interval", "min": [0.97], "max": [2]}},
    "boundary_conditions": [
        {"type": "displacement", "region": "left", "x": f"{EPS}*x*t"},
        {"type": "displacement", "region": "right", "x": f"{EPS}*x*t"},
    ],
    "solver": {"type": "nlcg", "load_steps": 2, "breaking": False, "tolerance": 1e-10},
    "output": {"picture": False, "frames": 0},
}


class DictDeck(TempDirCase):
    def test_patch_test_from_a_dict(self):
        with peri.Simulation(BAR, output=self.out("bar")) as sim:
            self.assertTrue(sim.quasi_static)
            sim.run()
            x = sim.field("reference_position")[:, 0]
            u = sim.displacement[:, 0]
            reaction = sim.history()["reaction_right_x"][-1]
        self.assertEqual(len(x), 100)
        np.testing.assert_allclose(u, EPS * x, rtol=0, atol=1e-6 * EPS * 1.0)
        self.assertAlmostEqual(reaction, E * A * EPS, delta=1e-6 * E * A * EPS)

    def test_dict_and_yaml_file_give_the_same_run(self):
        path = self.out("bar.yaml")
        with open(path, "w") as f:
            f.write(peri.deck_to_yaml(BAR))
        results = []
        for deck, out in ((BAR, "from_dict"), (path, "from_file")):
            with peri.Simulation(deck, overrides={"solver.load_steps": 1}, output=self.out(out)) as sim:
                sim.run()
                results.append((sim.displacement, sim.force, sim.history().array))
        for a, b in zip(*results):
            self.assertTrue(np.array_equal(a, b))

    def test_yaml_text_of_a_dict(self):
        text = peri.deck_to_yaml({"a": 1, "b": [1.5, -2e-7], "c": {"d": "x*t", "e": True, "f": None},
                                  "g": [{"h": 1, "i": [0, 1]}, {"h": 2}], "j": np.array([1.0, 2.0])})
        self.assertEqual(text, 'a: 1\nb: [1.5, -2e-07]\nc:\n  d: "x*t"\n  e: true\n  f: null\n'
                               'g:\n  - h: 1\n    i: [0, 1]\n  - h: 2\nj: [1.0, 2.0]\n')


if __name__ == "__main__":
    unittest.main()
