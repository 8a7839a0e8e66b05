"""calibration.png as a lab reads it: the curves in the data's unit (µN for data in µN), a
logarithmic panel where a long hold's small forces can be read, and the fitted values with the
digits their standard errors allow, in the unit of --param (λp in (kPa s)⁻¹)."""
import tempfile
import unittest
from pathlib import Path
from unittest import mock

import numpy as np

from poroplast_tools import experiments as exps
from poroplast_tools import fitplots


class Legend(unittest.TestCase):
    def test_digits_follow_the_standard_error(self):
        self.assertEqual(fitplots.plus_minus(1.5019711020927744, 0.0052), "1.5020 ± 0.0052")
        self.assertEqual(fitplots.plus_minus(0.00200987, 2.8e-05), "0.002010 ± 0.000028")
        self.assertEqual(fitplots.plus_minus(2.9849, 0.012), "2.985 ± 0.012")
        self.assertEqual(fitplots.plus_minus(0.096, 0.22), "0.10 ± 0.22")
        self.assertEqual(fitplots.plus_minus(28800.0, 300.0), "28800 ± 300")
        self.assertEqual(fitplots.plus_minus(2.88e5, 3000.0), "(2.880 ± 0.030)e5")
        self.assertEqual(fitplots.plus_minus(2.5e-05, 3e-07), "(2.500 ± 0.030)e-5")
        self.assertEqual(fitplots.plus_minus(5.0, float("nan")), "5")
        self.assertEqual(fitplots.plus_minus(0.000500000000172, 2.9e-15), "0.0005 ± 2.9e-15")
        self.assertEqual(fitplots.plus_minus(1.50197110209, 1e-9), "1.50197 ± 1e-09")

    def test_values_in_the_scenes_unit(self):
        self.assertEqual(fitplots.legend("material.remodelling.lambda_p", 0.00200987, 2.8e-05),
                         "λp = 0.002010 ± 0.000028 (kPa s)⁻¹")
        self.assertEqual(fitplots.legend("material.drained_shear_modulus", 1.5019711020927744, 0.0052),
                         "G = 1.5020 ± 0.0052 kPa")
        self.assertEqual(fitplots.legend("material.mu@r150", 2.5, 0.01), "µ@r150 = 2.500 ± 0.010 kPa")
        self.assertEqual(fitplots.legend("surface.tension", 2.9849, 0.012), "γ = 2.985 ± 0.012 mN/m")


class Figure(unittest.TestCase):
    def test_the_data_unit_and_a_log_panel(self):
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        e = exps.Experiment("hold", "tst_hold", "force_total_mg")
        params = exps.params(["material.remodelling.lambda_p=0.002"], [e])
        t = np.linspace(0, 1000, 101)
        model = 5.0 * np.exp(-t / 50) + 0.02              # mg: a peak, then a long hold at 0.02 mg
        data = [(list(t[1:]), model[1:] * 1.01)]
        result = {"material.remodelling.lambda_p": {"value": 0.002, "sigma": 2e-5},
                  "experiments": [{"rms_residual": 0.01, "rms_weighted": 1.0}]}
        study = Path(tempfile.mkdtemp())
        figs = []
        with mock.patch.object(plt, "close", figs.append):
            fitplots.curves(study, [e], data, [{"time": t, "force_total_mg": model}], result, params,
                            {"hold": ("uN", 1 / 9.81)})
        self.assertTrue((study / "calibration.png").exists())
        top, bottom = figs[0].axes
        self.assertEqual(top.get_ylabel(), "total force (µN)")
        self.assertEqual((top.get_yscale(), bottom.get_yscale()), ("linear", "log"))
        # The curves in µN: the peak 5.02 mg = 49.25 µN; the hold's 0.02 mg = 0.196 µN is within
        # the log panel's range.
        self.assertAlmostEqual(max(top.lines[0].get_ydata()), 5.02 * 9.81, places=9)
        lo, hi = bottom.get_ylim()
        self.assertLess(lo, 0.0202 * 9.81)
        self.assertIn("λp = 0.002000 ± 0.000020 (kPa s)⁻¹", top.get_legend().get_texts()[0].get_text())
        self.assertIn("rms residual 0.01 µN", top.get_title())
        plt.close(figs[0])
        # A compressive stress (all values below 0): no logarithmic panel.
        e = exps.Experiment("relax", "relaxation", "stress_zz")
        params = exps.params(["material.remodelling.lambda_p=0.002"], [e])
        with mock.patch.object(plt, "close", figs.append):
            fitplots.curves(study, [e], [(list(t[1:]), -model[1:])], [{"time": t, "stress_zz": -model}], result,
                            params, {"relax": ("kPa", 1.0)})
        self.assertEqual(len(figs[1].axes), 1)
        self.assertEqual(figs[1].axes[0].get_ylabel(), "stress_zz (kPa)")
        plt.close(figs[1])


if __name__ == "__main__":
    unittest.main()
