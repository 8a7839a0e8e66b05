"""Terzaghi's settlement (poroplast_tools.consolidation_refs): the two exact forms agree where both
converge, the short-time law, the textbook U–T table, the dimensional form. Pure Python."""
import math
import unittest

from poroplast_tools import consolidation_refs as cr

# The classical time factors T(U) of one-dimensional consolidation with a uniform initial excess
# pressure (three significant figures, as tabulated in soil-mechanics texts; read in the
# CEG 4012 course notes' table, "Case 1", www.coursehero.com/file/6769729).
TEXTBOOK = {0.20: 0.0314, 0.50: 0.197, 0.60: 0.286, 0.80: 0.567, 0.90: 0.848, 0.95: 1.129}


def time_factor(u):
    """T with U(T) = u, by bisection on the monotone U."""
    lo, hi = 0.0, 10.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if cr.degree(mid) < u else (lo, mid)
    return 0.5 * (lo + hi)


class Terzaghi(unittest.TestCase):
    def test_series_and_images_agree_in_the_overlap(self):
        worst = max(abs(cr.degree_fourier(t) - cr.degree_images(t))
                    for t in (0.003, 0.01, 0.03, 0.1, 0.3, 1.0, 2.0))
        self.assertLess(worst, 1e-13)

    def test_short_times_follow_two_root_tau_over_pi(self):
        # The first image is ierfc(1/√τ) ~ e^{−1/τ}: below 1e-20 at τ = 0.02.
        for tau in (1e-6, 1e-3, 0.02):
            self.assertAlmostEqual(cr.degree_fourier(tau) / (2 * math.sqrt(tau / math.pi)), 1.0,
                                   delta=1e-9 if tau > 1e-4 else 1e-6)

    def test_late_times_follow_the_first_mode(self):
        tau = 2.0
        self.assertAlmostEqual(1 - cr.degree(tau), 8 / math.pi ** 2 * math.exp(-math.pi ** 2 * tau / 4),
                               delta=1e-15)

    def test_the_textbook_time_factors(self):
        for u, t in TEXTBOOK.items():
            digits = 10 ** (math.floor(math.log10(t)) - 2)   # half a unit of the third figure
            self.assertLessEqual(abs(time_factor(u) - t), 0.5 * digits + 1e-12, (u, time_factor(u), t))

    def test_settlement_in_units_and_bad_input(self):
        # σ = 2 kPa on H = 100 µm, M = λ + 2µ = 4 kPa, k = 5e-4 µm²/(kPa·s): c = 2e-3 µm²/s.
        s_inf = 2.0 * 100.0 / 4.0
        t = 0.02 * 100.0 ** 2 / 2e-3                 # τ = 0.02: U = 2√(τ/π) to 1e-20
        self.assertAlmostEqual(cr.settlement(t, 100.0, 2.0, 4.0, 5e-4) / s_inf,
                               2 * math.sqrt(0.02 / math.pi), delta=1e-14)
        self.assertEqual(cr.settlement(0.0, 100.0, 2.0, 4.0, 5e-4), 0.0)
        self.assertAlmostEqual(cr.settlement(1e12, 100.0, 2.0, 4.0, 5e-4), s_inf, delta=1e-12)
        with self.assertRaises(ValueError):
            cr.settlement(1.0, -1.0, 2.0, 4.0, 5e-4)
        with self.assertRaises(ValueError):
            cr.degree(float("nan"))


if __name__ == "__main__":
    unittest.main()
