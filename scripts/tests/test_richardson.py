"""Observed orders and Richardson extrapolation recover known errors."""
import math
import unittest

from poroplast_tools.richardson import converge, correction, extrapolate, solve_order


class Richardson(unittest.TestCase):
    def test_order_and_correction_of_a_known_power(self):
        q = [1 + 2 * h ** 1.5 for h in (3.0, 2.0, 1.5)]
        p = solve_order(q, (1.5, 2 / 1.5))
        self.assertAlmostEqual(p, 1.5, delta=1e-9)
        self.assertAlmostEqual(q[2] + correction(q[1], q[2], 2 / 1.5, p), 1.0, delta=1e-9)
        self.assertTrue(math.isnan(correction(1.0, 2.0, 2.0, math.nan)))

    def test_no_order_when_differences_do_not_shrink(self):
        self.assertTrue(math.isnan(solve_order([1.0, 2.0, 1.5], (2.0, 2.0))))
        self.assertTrue(math.isnan(solve_order([1.0, 1.5, 2.5], (2.0, 2.0))))

    def test_order_against_a_known_limit(self):
        q = [1 + 0.5 * h ** 2 for h in (0.4, 0.2)]
        self.assertAlmostEqual(solve_order(q, (2.0,), limit=1.0), 2.0, delta=1e-12)

    def test_cross_design_recovers_additive_errors(self):
        # Q(h, s) = 1 + 2e-3 h² + 0.3 s: mesh levels at s = 0.5, step levels on h = 10.
        hs, ss = [20.0, 15.0, 10.0, 5.0], [1.0, 0.5, 0.25, 0.125]
        Q = lambda h, s: 1 + 2e-3 * h ** 2 + 0.3 * s
        r = extrapolate([Q(h, 0.5) for h in hs], [Q(10.0, s) for s in ss], Q(10.0, 0.5), hs, ss, 2, 1)
        self.assertAlmostEqual(r["extrapolated"], 1.0, delta=1e-12)
        self.assertAlmostEqual(r["p_h"], 2.0, delta=1e-6)
        self.assertAlmostEqual(r["p_t"], 1.0, delta=1e-6)
        self.assertEqual((r["order_h"], r["order_t"]), ("observed", "observed"))
        values = {(h, 0.5): Q(h, 0.5) for h in hs} | {(10.0, s): Q(10.0, s) for s in ss}
        self.assertAlmostEqual(converge(values, hs, ss, 10.0, 0.5)["extrapolated"], 1.0, delta=1e-12)

    def test_formal_order_and_a_wider_bar_where_none_is_observed(self):
        # The mesh sequence oscillates: the formal order 2, safety factor 3, at least the spread.
        hs, ss = [20.0, 10.0, 5.0], [1.0, 0.5, 0.25]
        qh, qt = [1.0, 1.2, 1.1], [1.3, 1.2, 1.15]
        r = extrapolate(qh, qt, 1.1, hs, ss, 2.0, 1.0)
        self.assertEqual(r["order_h"], "formal")
        c_h = (1.1 - 1.2) / (2 ** 2 - 1)
        c_t = (1.15 - 1.2) / (2 ** 1 - 1)
        self.assertAlmostEqual(r["extrapolated"], 1.1 + c_h + 1.15 + c_t - 1.1, delta=1e-12)
        self.assertGreaterEqual(r["error_bar"], 0.1 - 1e-12)


if __name__ == "__main__":
    unittest.main()
