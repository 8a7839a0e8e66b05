"""The identifiability report flags a parameter without effect and a near-collinear pair (with the
remedy where the pair is known), and its table gives the first-order effect of a 10% change."""
import math
import unittest

import numpy as np

from poroplast_tools.identify import hint, report


class Identify(unittest.TestCase):
    def test_effect_of_ten_percent(self):
        # Curve c(t) = a t: dc/dln a = a t. With a = 2 at t = 1..4 the +10% change is 0.2 t.
        t = np.arange(1.0, 5.0)
        lines, refusals, warnings = report(np.column_stack([2.0 * t]), ["a"], scale=1.0)
        rms = 0.2 * math.sqrt(np.mean(t ** 2))
        self.assertIn(f"a: {rms:.3g} ", lines[1])
        self.assertEqual((refusals, warnings), ([], []))
        lines, _, _ = report(np.column_stack([2.0 * t]), ["a"], scale=1.0, unit="mg")
        self.assertIn(f"a: {rms:.3g} mg ({100 * rms:.3g}% of the data's RMS)", lines[1])

    def test_a_parameter_without_effect_is_refused(self):
        t = np.arange(1.0, 5.0)
        _, refusals, warnings = report(np.column_stack([t, np.zeros(4)]), ["a", "b"], scale=1.0)
        self.assertEqual(refusals, ["b"])
        self.assertEqual(warnings, [])

    def test_collinear_pair_is_warned(self):
        t = np.arange(1.0, 5.0)
        # Columns t and 3 t + tiny: one parameter's change is undone by the other's.
        jac = np.column_stack([t, 3 * t + 1e-4 * t ** 2, np.exp(-t)])
        _, refusals, warnings = report(jac, ["a", "b", "c"], scale=1.0)
        self.assertEqual(refusals, [])
        self.assertEqual(len(warnings), 1)
        self.assertIn("a and b move the curve alike", warnings[0])

    def test_surface_tension_and_yield_stress_at_one_compression_are_told_the_remedy(self):
        t = np.arange(1.0, 5.0)
        jac = np.column_stack([t, 3 * t + 1e-4 * t ** 2, np.exp(-t)])
        for keys in (["surface.tension", "material.remodelling.sigma_y", "material.remodelling.lambda_p"],
                     ["material.remodelling.sigma_y@c30", "surface.tension", "material.mu"]):
            _, _, [warning] = report(jac, keys, scale=1.0)
            self.assertIn("move the curve alike", warning)
            self.assertIn("two compressions", warning)
        _, _, [warning] = report(jac, ["material.mu", "material.remodelling.sigma_y", "x"], scale=1.0)
        self.assertNotIn("two compressions", warning)
        self.assertIsNone(hint("material.mu", "surface.tension"))


if __name__ == "__main__":
    unittest.main()
