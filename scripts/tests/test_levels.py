"""Mesh levels of a convergence study scale every size of the scene with h, whether the scene
gives its sizes in µm (mesh.params) or as fractions of R (mesh.relative_sizes)."""

import unittest

from poroplast_tools.levels import h_levels


class HLevels(unittest.TestCase):
    def test_relative_sizes_are_scaled_in_micrometres(self):
        # The shipped reference: R = 100 µm, h = 0.2 R, h_pole = 0.03 R.
        levels = dict(h_levels("reference", [10.0])[0])
        self.assertEqual(levels["mesh.params.h"], "10")
        self.assertAlmostEqual(float(levels["mesh.params.h_pole"]), 1.5)

    def test_sizes_given_in_micrometres_win_over_relative_ones(self):
        levels = dict(h_levels("reference", [5.0], ["mesh.params.h_pole=4", "mesh.params.h_surf=4"])[0])
        self.assertAlmostEqual(float(levels["mesh.params.h_pole"]), 1.0)  # 4 µm at h = 20 µm
        self.assertAlmostEqual(float(levels["mesh.params.h_surf"]), 1.0)

    def test_absolute_sizes_as_before(self):
        levels = dict(h_levels("terzaghi", [10.0])[0])
        self.assertEqual(levels["mesh.params.h"], "10")


if __name__ == "__main__":
    unittest.main()
