"""The tensiometry study's pure parts: its protocols, the time from which the reading stays within
5% of γ, the measured domain of the reading (`rule`), and docs/studies.md's claim of that domain
against the committed table (docs/figures/data/tensiometry.csv, written by
scripts/tensiometry.py --docs). Pure Python."""
import math
import re
import unittest
from pathlib import Path

import numpy as np

import tensiometry as tst
from poroplast_tools.tables import read_rows

ROOT = Path(__file__).resolve().parent.parent.parent
TABLE = ROOT / "docs" / "figures" / "data" / "tensiometry.csv"
STUDIES = ROOT / "docs" / "studies.md"


class Protocols(unittest.TestCase):
    def test_one_hold_two_holds_released_and_straight_on(self):
        one = tst.Case("x", 0.01, 5.0, ((0.3, 1000.0),))
        self.assertEqual(one.table(), ("[[0, 0], [5, 0.3], [1005, 0.3]]", [(0.3, 5.0, 1005.0)]))
        two = tst.Case("x", 0.01, 5.0, ((0.15, 100.0), (0.3, 100.0)))
        table, ends = two.table()
        self.assertEqual(table, "[[0, 0], [5, 0.15], [105, 0.15], [110, 0], [400, 0], [405, 0.3], [505, 0.3]]")
        self.assertEqual(ends, [(0.15, 5.0, 105.0), (0.3, 405.0, 505.0)])
        trial = tst.Case("x", 0.05, 3.0, ((0.15, 600.0), (0.3, 600.0)), r=150.0, release=False)
        self.assertEqual(trial.table()[0], "[[0, 0], [5, 0.15], [605, 0.15], [610, 0.3], [1210, 0.3]]")
        # The time scales and the Bond number ρ g R²/γ (ρ = 1000 kg/m³: 9.81e-6 kPa/µm).
        self.assertAlmostEqual(trial.relaxation_time, 1.0, delta=1e-12)
        self.assertAlmostEqual(trial.capillary_time, 1000.0, delta=1e-9)
        self.assertAlmostEqual(trial.bond, 9.81e-6 * 150.0 ** 2 / 3.0, delta=1e-15)
        self.assertEqual(tst.Case("x", 0.01, 5.0, ((0.3, 1.0),), gravity=False).bond, 0.0)
        overrides = dict(tst.overrides(trial))
        self.assertEqual(overrides["mesh.params.R"], "150")
        self.assertEqual(overrides["time.t_end"], "1210")
        self.assertNotIn("material.gravity", overrides)

    def test_settled_from_is_the_start_of_the_last_stretch_within_5_percent(self):
        h = {"time": np.array([0.0, 10.0, 20.0, 30.0, 40.0, 50.0]),
             "sigma_app": 5.0 * np.array([3.0, 1.04, 0.90, 0.96, 1.049, 0.99])}
        self.assertEqual(tst.settled_from(h, 0.0, 50.0, 5.0), 30.0)     # 1.04 at 10 s does not stay
        self.assertEqual(tst.settled_from(h, 10.0, 50.0, 5.0), 20.0)    # in seconds after t0
        self.assertTrue(math.isnan(tst.settled_from(h, 0.0, 20.0, 5.0)))  # ends outside


class Rule(unittest.TestCase):
    def row(self, t5, lp, gamma, gravity=0, sy=0.0):
        case = tst.Case("x", lp, gamma, ((0.3, 1.0),), sy=sy)
        return {"within_5pct_from": t5, "relaxation_time": case.relaxation_time,
                "capillary_time": case.capillary_time, "sigma_y": sy, "gamma": gamma, "gravity": gravity,
                "mu_R_over_gamma": tst.MU * tst.R / gamma}

    def test_the_rule_is_the_tightest_pair_of_the_front(self):
        # τ_r = 5 s; τ_c = 100/(0.01 γ): γ = 50: 200 s, γ = 2: 5000 s. In (t5/τ_r, t5/τ_c):
        # (16, 0.4), (180, 0.18), (20, 0.02). The front: (180, 0), (180, 0.02), (16, 0.18), (0, 0.4);
        # the geometric means of max(a τ_r, b τ_c)/t5: 11.25·1·9, the same, 1·1·9, 1·2.2·20: (16, 0.18).
        rows = [self.row(80.0, 0.01, 50.0), self.row(900.0, 0.01, 2.0), self.row(100.0, 0.01, 2.0)]
        others = [self.row(1e6, 0.01, 2.0, gravity=1), self.row(1e6, 0.01, 5.0, sy=0.1),
                  self.row(1e6, 0.01, 200.0)]             # µR/γ = 10: outside the domain
        self.assertEqual(tst.liquid_rows(rows + others), rows)
        a, b = tst.rule(rows + others)
        self.assertEqual(a, 16.0)
        self.assertAlmostEqual(b, 0.18, delta=1e-12)
        # Every hold within its rule: t5 ≤ max(a τ_r, b τ_c).
        for r in rows:
            self.assertLessEqual(r["within_5pct_from"], max(a * r["relaxation_time"], b * r["capillary_time"]))
        self.assertEqual(tst._up(0.2468), 0.25)
        self.assertEqual(tst._up(0.25), 0.25)
        self.assertEqual(tst._up(15.5), 16.0)
        self.assertTrue(math.isnan(tst.rule(rows + [self.row(math.nan, 0.01, 2.0)])[0]))


@unittest.skipUnless(TABLE.exists(), "no committed tensiometry table")
class Claims(unittest.TestCase):
    """docs/studies.md's domain of the Laplace reading is the one the committed table gives."""

    def test_the_domain_in_the_docs_is_the_tables(self):
        rows = read_rows(TABLE)
        a, b = tst.rule(rows)
        self.assertTrue(math.isfinite(a) and math.isfinite(b))
        liquid = tst.liquid_rows(rows)
        for r in liquid:        # the claim holds on every hold it was measured on
            self.assertLessEqual(float(r["within_5pct_from"]),
                                 max(a * float(r["relaxation_time"]), b * float(r["capillary_time"])))
        text = STUDIES.read_text()
        self.assertIn(f"once t > {a:g}/(λp µ) and t > {b:g} R/(λp γ)", text)
        self.assertIn(f"over {len(liquid)} holds", text)
