"""The inverse question's objective (poroplast_tools/inverse.py): the claims as intervals, their
residuals, the observables read from histories, the runs' overrides and fit.py's model, against
hand-computed values; no solver."""
import math
import unittest

import numpy as np

from poroplast_tools import inverse as inv

CLAIM = {c.id: c for c in inv.CLAIMS}


def hist(t, **cols):
    t = np.asarray(t, dtype=float)
    return {"time": t, **{k: np.asarray(v, dtype=float) for k, v in cols.items()}}


class ClaimResiduals(unittest.TestCase):
    def test_a_printed_number_is_its_value_plus_minus_its_precision(self):
        # "the pressure equals zero at t = 40 s": [39.5, 40.5] s; 42.33 s is (42.33 - 40) / 0.5
        self.assertAlmostEqual(CLAIM["P9"].residual(42.33), 4.66, places=10)
        self.assertAlmostEqual(CLAIM["P9"].residual(39.5), -1.0, places=12)
        # "28 s": ±0.5 s; 39.54 s is 23.08 precisions late
        self.assertAlmostEqual(CLAIM["P56"].residual(39.54), 23.08, places=10)
        # "about 4 mg": 0.988 mg is (0.988 - 4) / 0.5 = -6.024
        self.assertAlmostEqual(CLAIM["P38"].residual(0.988), -6.024, places=10)

    def test_mostly_constitutive_is_the_upper_half(self):
        # [0.5, 1]: centre 0.75, half-width 0.25; the scene's 0.3136 is (0.3136 - 0.75) / 0.25
        self.assertAlmostEqual(CLAIM["P35"].residual(0.3136), -1.7456, places=10)
        self.assertAlmostEqual(CLAIM["P35"].residual(0.5), -1.0, places=12)
        self.assertAlmostEqual(CLAIM["P35"].residual(1.0), 1.0, places=12)

    def test_an_order_of_magnitude_is_a_factor_root_ten_in_log(self):
        # claims.csv's factor 3.1623 (√10 to five digits): half-width log10(3.1623) = 0.5000031;
        # log10(1.489) = 0.1728947, (0.1728947 - 1) / 0.5000031 = -1.6542004
        self.assertAlmostEqual(CLAIM["P23b"].residual(1.489), (math.log10(1.489) - 1) / math.log10(3.1623), places=12)
        self.assertAlmostEqual(CLAIM["P23b"].residual(1.489), -1.6542004, places=6)
        self.assertAlmostEqual(CLAIM["P23b"].residual(10.0), 0.0, places=12)
        self.assertAlmostEqual(CLAIM["P23b"].residual(31.623), 1.0, places=12)
        self.assertTrue(math.isnan(CLAIM["P23b"].residual(-1.0)))

    def test_about_a_quarter_is_an_eighth_either_side(self):
        self.assertAlmostEqual(CLAIM["P58"].residual(0.786), (0.786 - 0.25) / 0.125, places=12)
        self.assertAlmostEqual(CLAIM["P58"].residual(0.786), 4.288, places=10)

    def test_a_claims_interval_is_read_from_its_row_of_claims_csv(self):
        rows = [{"id": "P9", "precision_note": '"the pressure equals zero at t = 40.0 s"'},
                {"id": "P56", "precision_note": '"at t = 28 s" minus "than t = 40 s"'},
                {"id": "P23b", "precision_note": '"one order of magnitude lower"'}]
        c = inv.from_claims("P9", "crossing", "t_cross", rows=rows)      # one more digit: ±0.05 s
        self.assertEqual((c.paper, c.lo, c.hi), (40.0, 39.95, 40.05))
        c = inv.from_claims("P56", "c = 2 crossing", "t_cross_c2", rows=rows)    # the first quote
        self.assertEqual((c.paper, c.lo, c.hi), (28.0, 27.5, 28.5))
        c = inv.from_claims("P23b", "ratio", "vm_ratio", rows=rows)
        self.assertTrue(c.log)
        self.assertAlmostEqual(c.lo * c.hi, 100.0, places=9)
        with self.assertRaises(ValueError):
            inv.from_claims("P99", "nothing", "t_cross", rows=rows)
        with self.assertRaises(ValueError):
            inv.from_claims("P9", "crossing", "t_cross", quote=1, rows=rows)

    def test_the_shipped_claims_are_claims_csvs(self):
        from poroplast_tools import claims
        notes = {r["id"]: r["precision_note"] for r in claims.load()}
        for c in inv.CLAIMS:
            if c.id == "P35":
                self.assertEqual(notes[c.id], "", "P35 has a number in claims.csv now: read it there")
                continue
            self.assertIn(c.precision.split('":')[0] + '"', notes[c.id])

    def test_a_point_is_scored_again_from_its_own_observables(self):
        obs = {"share_constitutive": 0.75, "t_cross": 40.5, "t_cross_c2": 28.0, "p30_ratio": 0.25,
               "d_peak_constitutive": 4.0, "d_peak_total": 2.5, "vm_ratio": 10.0}
        [row] = inv.rescored([{k: str(v) for k, v in obs.items()} | {"cost": "999"}])
        self.assertAlmostEqual(row["r P9"], 1.0, places=10)
        self.assertAlmostEqual(row["cost"], 2.0, places=10)          # P9 and P39 at +1
        self.assertAlmostEqual(row["cost_others"], 2.0, places=10)
        self.assertEqual(row["reproduced"], 7)
        [failed] = inv.rescored([{"status": "failed", "cost": "nan"}])
        self.assertEqual(failed["cost"], "nan")

    def test_a_missing_value_is_nan(self):
        self.assertTrue(math.isnan(CLAIM["P9"].residual(math.nan)))
        self.assertTrue(math.isnan(CLAIM["P9"].residual(None)))

    def test_cost_and_count(self):
        r = [0.5, -1.0, 2.0, math.sqrt(2)]
        self.assertAlmostEqual(inv.cost(r), 0.25 + 1 + 4 + 2, places=12)
        self.assertEqual(inv.reproduced(r), 2)       # |r| <= 1: 0.5 and -1.0
        self.assertEqual(inv.reproduced([math.nan, 0.0]), 1)

    def test_weights_are_the_inverse_half_widths(self):
        w = inv.weigh(None, 3)
        self.assertEqual(len(w), len(inv.CLAIMS))
        self.assertAlmostEqual(w[[c.id for c in inv.CLAIMS].index("P9")], 1 / 0.5)
        self.assertAlmostEqual(w[[c.id for c in inv.CLAIMS].index("P56")], 1 / 0.5)
        self.assertAlmostEqual(w[[c.id for c in inv.CLAIMS].index("P23b")], 1 / math.log10(3.1623))


class Observables(unittest.TestCase):
    def test_crossing_interpolates_the_first_fall_after_the_ramp(self):
        t = [0, 2, 4, 6, 30, 40, 50]
        p = [0, -1, 3, 5, 2, 1, -3]        # a dip before 5 s does not count
        # between 40 s (1 kPa) and 50 s (-3 kPa): 40 + 10 * 1/4 = 42.5 s
        self.assertAlmostEqual(inv.crossing(np.array(t, float), np.array(p, float)), 42.5)
        self.assertTrue(math.isnan(inv.crossing(np.array([0, 10.0]), np.array([1, 2.0]))))

    def test_the_claims_observables_from_four_histories(self):
        t = [0, 5, 30, 40, 50, 60]
        iso = hist(t, force_total_mg=[0, 16, 10, 8, 7, 6], force_constitutive_mg=[0, 6, 7, 5, 4, 4],
                   force_pressure_mg=[0, 10, 3, 3, 3, 2], probe_p=[0, 10, 2, 0.5, -0.5, -1])
        c2 = hist(t, force_total_mg=[0] * 6, force_constitutive_mg=[0] * 6, force_pressure_mg=[0] * 6,
                  probe_p=[0, 9, 0.5, -1, -1, -1])
        lam = hist(t, force_total_mg=[0, 17, 12, 9, 8, 7], force_constitutive_mg=[0, 7, 8, 9, 8, 7],
                   force_pressure_mg=[0, 10, 4, 0, 0, 0], probe_p=[0] * 6)
        o = inv.observables({"iso": iso, "c2": c2, "lam": lam}, 1.5)
        self.assertAlmostEqual(o["peak_total"], 16)
        self.assertAlmostEqual(o["share_constitutive"], 6 / 16)      # at the total's peak (5 s), not 7 at 30 s
        self.assertAlmostEqual(o["share_pressure"], 10 / 16)
        self.assertAlmostEqual(o["peak_constitutive"], 7)             # the largest constitutive force
        self.assertAlmostEqual(o["t_cross"], 45.0)                   # 40 + 10 * 0.5 / 1
        self.assertAlmostEqual(o["t_cross_c2"], 30 + 10 * 0.5 / 1.5)
        self.assertAlmostEqual(o["p30_ratio"], 0.5 / 2)
        self.assertAlmostEqual(o["d_peak_total"], 1.0)                # 17 - 16
        self.assertAlmostEqual(o["d_peak_constitutive"], 2.0)         # 9 - 7
        self.assertEqual(o["vm_ratio"], 1.5)


class Runs(unittest.TestCase):
    def test_each_run_takes_its_own_share_of_the_parameters(self):
        v = {"k0": 10.0, "lambda_p": 0.002, "c": 3.0, "nu": 0.25}
        iso = dict(inv.case_values("iso", v))
        self.assertEqual(iso, {"material.k0": "10.0", "material.remodelling.lambda_p": "0.002", "material.nu": "0.25"})
        c2 = dict(inv.case_values("c2", v))
        self.assertAlmostEqual(float(c2["material.k0"]), 10.0 * 2.5779 / 3.7729)
        self.assertEqual(c2["material.permeability_c"], "3.0")
        lam = dict(inv.case_values("lam", v))
        self.assertAlmostEqual(float(lam["material.remodelling.lambda_p"]), 0.0002)
        # at Table 1 (nothing fitted) the twins still take Fig 11's k0 and c, and λp / 10
        c2 = dict(inv.case_values("c2", {}))
        self.assertAlmostEqual(float(c2["material.k0"]), 2.5779)
        self.assertEqual(float(c2["material.permeability_c"]), 2.0)
        self.assertAlmostEqual(float(dict(inv.case_values("lam", {}))["material.remodelling.lambda_p"]), 0.0001)

    def test_the_model_gives_fit_py_the_unweighted_differences(self):
        m = inv.Model(["k0"], "/nonexistent")
        obs = {"share_constitutive": 0.5, "t_cross": 42.0, "t_cross_c2": 28.0, "p30_ratio": 0.5,
               "d_peak_constitutive": 1.0, "d_peak_total": 0.5, "vm_ratio": 1.0}
        asked = []

        def run(points, replay=None, extra=None):
            asked.extend(points)
            return [(obs, {"values": {}, "histories": {}, "vm_ratio": 1.0}) for _ in points]
        m.run = run
        table1 = math.log(3.7729)
        out = m.evaluate([np.array([table1]), np.array([math.log(1000.0)])], ["a", "b"])
        self.assertEqual(len(asked), 1)             # the second point is beyond k0's bound: not run
        self.assertIsNone(out[1])
        d, state = out[0]
        # d = r × half = v − mid: share 0.5 − 0.75, crossing 42 − 40, c2 0, ratio 0.5 − 0.25,
        # λp changes 1 − 4 and 0.5 − 2, σ_VM log10(1) − 1
        np.testing.assert_allclose(d, [-0.25, 2.0, 0.0, 0.25, -3.0, -1.5, -1.0], atol=1e-12)
        # weighted: ÷ the half-widths 0.25, 0.5, 0.5, 0.125, 0.5, 0.5 and log10(3.1623)
        np.testing.assert_allclose(inv.weigh(d, 1) * d, [-1.0, 4.0, 0.0, 2.0, -6.0, -3.0, -1.0 / math.log10(3.1623)],
                                   atol=1e-12)
        self.assertAlmostEqual(state["x"][0], table1)

    def test_a_neighbour_in_c_runs_only_the_c2_case_on_the_points_steps(self):
        from unittest import mock
        t = [0.0, 5.0, 30.0, 50.0]
        h = hist(t, force_total_mg=[0, 16, 8, 6], force_constitutive_mg=[0, 6, 6, 5], force_pressure_mg=[0, 10, 2, 1],
                 probe_p=[0, 10, 1, -1])
        state = {"values": {"c": 2.0}, "histories": {r: h for r in inv.RUNS}, "vm_ratio": 1.5}
        calls = []

        def run_cases(scenes, cases, sets, root, ranks, counts=None):
            calls.append(cases)
            return [("dir", {"status": "ok"}) for _ in cases]
        with mock.patch.object(inv, "run_cases", run_cases), mock.patch.object(inv, "history", lambda d: h):
            [(obs, st)] = inv.Model(["c"], "/nonexistent").run([{"c": 2.002}], replay=[state])
        [cases] = calls
        self.assertEqual(len(cases), 1)                       # iso, lam and r40 are the state's
        case = dict(cases[0])
        self.assertEqual(case["material.permeability_c"], repr(2.002))
        self.assertEqual(case["time.steps"], "[5.0,30.0,50.0]")  # the point's own steps
        self.assertEqual(obs["vm_ratio"], 1.5)                 # from the state, not re-read
        self.assertAlmostEqual(obs["t_cross"], 40.0)

    def test_distance_from_table_1(self):
        f, far = inv.distance({"k0": 37.729, "nu": 0.1})
        self.assertAlmostEqual(f["k0"], 10.0)
        self.assertAlmostEqual(f["nu"], 0.5)
        self.assertAlmostEqual(far, 1.0)


if __name__ == "__main__":
    unittest.main()


class Page(unittest.TestCase):
    """The page's generated inverse tables (no solver: the committed CSVs)."""

    def test_the_pages_inverse_tables_are_as_the_committed_csvs_render_them(self):
        from pathlib import Path
        from poroplast_tools import inverse_report
        root = Path(__file__).resolve().parents[2]
        page = (root / "docs" / "reproduction.md").read_text(encoding="utf-8")
        for name, (begin, end, _) in inverse_report.TABLES.items():
            self.assertIn(begin, page, f"the inverse {name} table's markers are missing")
        self.assertEqual(page, inverse_report.write_tables(page, root / "scripts" / "data"),
                         "docs/reproduction.md's inverse tables are stale: python3 scripts/inverse.py --stages docs")
