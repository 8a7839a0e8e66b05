"""The fit's standard errors against the closed form of a straight-line fit, for each noise model,
and the weights of the noise models."""
import math
import unittest

import numpy as np

from poroplast_tools.fitstats import uncertainty, weights


def line_fit(t, y, w):
    """Weighted least squares of y = a + b t: the optimum, the weighted residuals and their
    Jacobian (columns d r/d a, d r/d b)."""
    jac = np.column_stack([w, w * t])
    coef, *_ = np.linalg.lstsq(jac, w * y, rcond=None)
    return coef, w * (coef[0] + coef[1] * t - y), jac


class FitStats(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(7)
        self.t = np.linspace(0.0, 10.0, 21)
        self.sigma = 0.05 + 0.01 * self.t
        self.y = 1.0 + 0.3 * self.t + rng.normal(0.0, 1.0, self.t.size) * self.sigma

    def test_known_sigma_gives_the_textbook_errors(self):
        # sd(b)² = S / (S Stt − St²) with S = Σ 1/σ², St = Σ t/σ², Stt = Σ t²/σ².
        w = weights("data", self.y, self.sigma)
        _, r, jac = line_fit(self.t, self.y, w)
        sd, corr, s2, chi2 = uncertainty(jac, r, "data")
        S, St, Stt = (np.sum(self.t ** k / self.sigma ** 2) for k in (0, 1, 2))
        det = S * Stt - St ** 2
        self.assertAlmostEqual(sd[0], math.sqrt(Stt / det), delta=1e-12)
        self.assertAlmostEqual(sd[1], math.sqrt(S / det), delta=1e-12)
        self.assertAlmostEqual(corr[0, 1], -St / math.sqrt(S * Stt), delta=1e-12)
        self.assertEqual(s2, 1.0)
        self.assertAlmostEqual(chi2, float(r @ r) / 19, delta=1e-15)

    def test_absolute_noise_is_estimated_from_the_residuals(self):
        # Unweighted: sd(b)² = s² / Σ (t − t̄)², s² = Σ r² / (n − 2).
        _, r, jac = line_fit(self.t, self.y, weights("absolute", self.y))
        sd, corr, s2, _ = uncertainty(jac, r, "absolute")
        self.assertAlmostEqual(s2, float(r @ r) / 19, delta=1e-15)
        self.assertAlmostEqual(sd[1], math.sqrt(s2 / np.sum((self.t - self.t.mean()) ** 2)), delta=1e-12)
        self.assertAlmostEqual(corr[1, 0], corr[0, 1], delta=1e-15)
        self.assertAlmostEqual(corr[0, 0], 1.0, delta=1e-12)

    def test_weights_of_the_noise_models(self):
        y = np.array([2.0, -4.0, 0.0])
        np.testing.assert_array_equal(weights("absolute", y), [1.0, 1.0, 1.0])
        # Relative: 1/|y|, floored at 1e-3 of the largest |y|.
        np.testing.assert_allclose(weights("relative", y), [0.5, 0.25, 1.0 / 4e-3])
        np.testing.assert_allclose(weights("data", y, [0.5, 2.0, 4.0]), [2.0, 0.5, 0.25])
        with self.assertRaises(ValueError):
            weights("data", y)
        with self.assertRaises(ValueError):
            weights("poisson", y)

    def test_singular_jacobian_gives_nan(self):
        jac = np.column_stack([np.ones(5), np.ones(5)])
        sd, corr, _, _ = uncertainty(jac, np.zeros(5), "absolute")
        self.assertTrue(all(math.isnan(x) for x in sd))


if __name__ == "__main__":
    unittest.main()
