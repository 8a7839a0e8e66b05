"""The fit's standard errors (fit.stats) against the closed form of a straight-line fit, for the
noise models' weights, and those weights (a relative noise's of the model's value)."""
import math
import unittest

import numpy as np

from poroplast_tools.fit import Optimum, stats
from poroplast_tools.fitstats import Noise, floor_fraction, quantile, stacked_weights, weights


def line_fit(t, y, noise, dof, sigma=None):
    """Weighted least squares of y = a + b t (weights 1/`sigma`, none: unweighted) as the fit's
    optimum: the coefficients, the differences, the noise's weights and s there, the unweighted
    Jacobian (columns d/d a, d/d b)."""
    jac = np.column_stack([np.ones_like(t), t])
    shape = np.ones_like(t) if sigma is None else 1 / sigma
    coef, *_ = np.linalg.lstsq(shape[:, None] * jac, shape * y, rcond=None)
    d = coef[0] + coef[1] * t - y
    w, s = noise.weights(d, dof)
    return Optimum(coef, d, None, w, jac), s


class FitStats(unittest.TestCase):
    def setUp(self):
        rng = np.random.default_rng(7)
        self.t = np.linspace(0.0, 10.0, 21)
        self.sigma = 0.05 + 0.01 * self.t
        self.y = 1.0 + 0.3 * self.t + rng.normal(0.0, 1.0, self.t.size) * self.sigma

    def test_known_sigma_gives_the_textbook_errors(self):
        # sd(b)² = S / (S Stt − St²) with S = Σ 1/σ², St = Σ t/σ², Stt = Σ t²/σ².
        opt, s = line_fit(self.t, self.y, Noise("data", self.y, self.sigma), 19, self.sigma)
        st = stats(opt, False)
        S, St, Stt = (np.sum(self.t ** k / self.sigma ** 2) for k in (0, 1, 2))
        det = S * Stt - St ** 2
        self.assertAlmostEqual(st.rel[0], math.sqrt(Stt / det), delta=1e-12)
        self.assertAlmostEqual(st.rel[1], math.sqrt(S / det), delta=1e-12)
        self.assertAlmostEqual(st.corr[0, 1], -St / math.sqrt(S * Stt), delta=1e-12)
        self.assertEqual(s, 1.0)
        self.assertAlmostEqual(st.chi2, float(np.sum((opt.d / self.sigma) ** 2)) / 19, delta=1e-15)

    def test_absolute_noise_is_estimated_from_the_residuals(self):
        # Unweighted: sd(b)² = s² / Σ (t − t̄)², s² = Σ r² / (n − 2).
        opt, s = line_fit(self.t, self.y, Noise("absolute", self.y), 19)
        st = stats(opt, True)
        self.assertAlmostEqual(s * s, float(opt.d @ opt.d) / 19, delta=1e-15)
        self.assertAlmostEqual(st.rel[1], math.sqrt(s * s / np.sum((self.t - self.t.mean()) ** 2)), delta=1e-12)
        self.assertAlmostEqual(st.corr[1, 0], st.corr[0, 1], delta=1e-15)
        self.assertAlmostEqual(st.corr[0, 0], 1.0, delta=1e-12)

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
        st = stats(Optimum(np.zeros(2), np.zeros(5), None, np.ones(5), jac), True)
        self.assertTrue(all(math.isnan(x) for x in st.rel))

    def test_relative_weights_are_the_models_not_the_datas(self):
        # Data y, differences d = model − data: σ_i = s |y_i + d_i|, s² = Σ (d_i / model_i)² / dof.
        y, d = np.array([1.0, 2.0, 4.0]), np.array([0.1, -0.2, 0.4])
        model = y + d
        w, s = Noise("relative", y).weights(d, 2)
        self.assertAlmostEqual(s, math.sqrt(float(np.sum((d / model) ** 2)) / 2), delta=1e-15)
        np.testing.assert_allclose(w, 1 / (s * model), rtol=1e-14)
        # Not the data's: a point the noise pushed up (model below the data) would weigh less.
        self.assertGreater(abs(w[1] * y[1] - 1 / s), 0.1 / s)
        # The floor is 1e-3 of the model's largest value: a model through zero.
        w, s = Noise("relative", np.array([4.0, 0.5])).weights(np.array([0.0, -0.5]), 1)
        self.assertAlmostEqual(w[1] * s, 1 / 4e-3, delta=1e-9)

    def test_relative_noise_above_a_floor_is_estimated(self):
        # A force that falls to zero (contact lost) with σ_i = √((ρ y_i)² + f²), ρ = 3%, f = 0.02:
        # ρ recovered from 4000 points (its estimate's sd about 1.5%), the zeros weighted 1/f,
        # each point by the model's value (the truth here: d = truth − data).
        rng = np.random.default_rng(4)
        y = np.r_[np.linspace(2.0, 0.1, 2000), np.zeros(2000)]
        sigma = np.sqrt((0.03 * y) ** 2 + 0.02 ** 2)
        data = y + sigma * rng.standard_normal(y.size)
        noise = Noise("relative+floor", data, floor=0.02)
        w, rho = noise.weights(y - data, y.size)
        self.assertAlmostEqual(rho, 0.03, delta=0.03 * 0.06)
        self.assertAlmostEqual(float(np.sum((w * (y - data)) ** 2)), y.size, delta=1e-6 * y.size)
        np.testing.assert_allclose(w, 1 / np.sqrt((rho * y) ** 2 + 0.02 ** 2), rtol=1e-12)
        # Plain relative noise on the same data has no floor: the zeros get 1e3 / max|y|.
        self.assertAlmostEqual(weights("relative", y)[-1], 1 / 2e-3)
        with self.assertRaises(ValueError):
            Noise("relative+floor", y)

    def test_a_floor_that_explains_the_residuals_alone_gives_no_relative_part(self):
        self.assertEqual(floor_fraction(np.full(10, 0.01), np.ones(10), 0.02, 10), 0.0)
        # One point, y = 1, d = 0.05, f = 0.03: ρ² = 0.05² − 0.03² exactly.
        self.assertAlmostEqual(floor_fraction(np.array([0.05]), np.array([1.0]), 0.03, 1), 0.04, delta=1e-12)

    def test_stacked_curves_share_the_degrees_of_freedom(self):
        # Two absolute curves of 30 and 10 points, p = 4: dof 27 and 9; σ_e² = Σ d_e² / dof_e.
        d = np.r_[np.full(30, 0.3), np.full(10, 2.0)]
        noises = [Noise("absolute", np.ones(30)), Noise("absolute", np.ones(10))]
        w, scales = stacked_weights(noises, d, 4)
        np.testing.assert_allclose(scales, [math.sqrt(30 * 0.09 / 27), math.sqrt(10 * 4.0 / 9)])
        self.assertAlmostEqual(float(np.sum((w * d) ** 2)), 36.0, delta=1e-12)

    def test_quantiles_are_the_tables(self):
        # Student's t at 97.5% (1, 10, 30 dof), the normal 97.5% and one-σ points.
        self.assertAlmostEqual(quantile(0.95, 1), 12.7062047, delta=1e-6)
        self.assertAlmostEqual(quantile(0.95, 10), 2.2281389, delta=1e-6)
        self.assertAlmostEqual(quantile(0.95, 30), 2.0422725, delta=1e-6)
        self.assertAlmostEqual(quantile(0.95), 1.9599640, delta=1e-6)
        self.assertAlmostEqual(quantile(math.erf(1 / math.sqrt(2))), 1.0, delta=1e-12)
        self.assertAlmostEqual(quantile(0.99, 3), 5.8409093, delta=1e-6)

    def test_quantiles_of_one_and_two_degrees_of_freedom_are_the_closed_forms(self):
        # One dof: Cauchy, t_p = tan(π (p − 1/2)); two: t_p = (2p − 1)/√(2p(1 − p)); p = (1 + level)/2.
        for p in (0.6, 0.8413447460685429, 0.975, 0.995):
            self.assertAlmostEqual(quantile(2 * p - 1, 1), math.tan(math.pi * (p - 0.5)), delta=1e-9)
            self.assertAlmostEqual(quantile(2 * p - 1, 2), (2 * p - 1) / math.sqrt(2 * p * (1 - p)), delta=1e-9)
        self.assertAlmostEqual(quantile(0.95, 1e7), 1.959963984540054, delta=1e-6)    # the normal limit


if __name__ == "__main__":
    unittest.main()
