"""The fit over pure Python models with known answers: an exponential decay recovered, the
standard errors and the Wald and profile intervals of a linear model against their closed form,
the 68% and 95% intervals' coverage by Monte Carlo, and two curves of different noise re-weighted."""
import math
import unittest

import numpy as np

from poroplast_tools.fit import FitError, fit, stats
from poroplast_tools.profile import profile
from poroplast_tools.fitstats import Noise, quantile, stacked_weights

QUIET = dict(say=lambda *_: None)
EXACT = dict(QUIET, ftol=1e-14, xtol=1e-12, max_it=50)   # converged to rounding


def model_of(curve, data):
    """evaluate() of a model curve(x) -> values at the data points (None: a failed run)."""
    def evaluate(points, what, replay=None):
        out = []
        for x in points:
            v = curve(np.asarray(x))
            out.append(None if v is None else (v - data, None))
        return out
    return evaluate


def absolute(data):
    return lambda d, p: stacked_weights([Noise("absolute", data)], d, p)[0]


class Decay(unittest.TestCase):
    """y = A exp(−t/τ), fitted in (ln A, ln τ)."""
    t = np.linspace(0.2, 10.0, 50)

    def curve(self, x):
        return math.exp(x[0]) * np.exp(-self.t / math.exp(x[1]))

    def test_recovers_the_parameters_of_noise_free_data(self):
        truth = np.log([2.0, 3.0])
        data = self.curve(truth)
        # Data exactly on the model: the weights estimated from ~0 residuals would be
        # meaningless; a stated σ instead.
        opt = fit(model_of(self.curve, data), lambda d, p: np.full(len(d), 100.0), np.log([1.0, 1.0]),
                  ["A", "tau"], ftol=1e-12, xtol=1e-10, max_it=50, **QUIET)
        np.testing.assert_allclose(np.exp(opt.x), [2.0, 3.0], rtol=1e-6)

    def test_a_failed_trial_run_only_damps_the_step(self):
        truth = np.log([2.0, 3.0])
        data = self.curve(truth)
        # The model fails for τ above 5: the first undamped step from τ = 1 overshoots there.
        curve = lambda x: None if math.exp(x[1]) > 5 else self.curve(x)
        opt = fit(model_of(curve, data), lambda d, p: np.full(len(d), 100.0), np.log([1.0, 1.0]),
                  ["A", "tau"], ftol=1e-12, xtol=1e-10, max_it=60, **QUIET)
        np.testing.assert_allclose(np.exp(opt.x), [2.0, 3.0], rtol=1e-6)
        with self.assertRaises(FitError):
            fit(model_of(lambda x: None, data), absolute(data), [0.0, 0.0], ["A", "tau"], **QUIET)

    def test_profile_interval_matches_the_exact_profile(self):
        # Against the profile computed exactly (the other parameter minimised by Newton
        # iterations at each value, the crossing by bisection), on 2% noise and on 20%.
        self.check_profile(0.02, 2e-4)
        # At 20% the curve is nonlinear over the interval: the Wald interval is off (by 6% of
        # the width, measured), the profile is not.
        self.assertGreater(self.check_profile(0.2, 5e-3), 0.02)

    def check_profile(self, level, tol):
        t = self.t[::3]
        curve = lambda x: math.exp(x[0]) * np.exp(-t / math.exp(x[1]))
        rng = np.random.default_rng(3)
        data = curve(np.log([2.0, 3.0])) * (1 + level * rng.standard_normal(t.size))
        noise = Noise("relative", data)
        weigh = lambda d, p: stacked_weights([noise], d, p)[0]
        evaluate = model_of(curve, data)
        opt = fit(evaluate, weigh, np.log([1.0, 1.0]), ["A", "tau"], **EXACT)
        st = stats(opt, True)
        prof = profile(evaluate, opt, st, ["A", "tau"], multiples=(0.5, 1, 1.5, 2, 2.5, 3), **QUIET)
        w, wald_off = opt.w, 0.0

        def cost(x):
            r = w * (curve(x) - data)
            return float(r @ r)

        def profiled(k, v):
            x = opt.x.copy()
            x[k] = v
            j = 1 - k
            for _ in range(12):   # Newton on the other variable, derivatives by central differences
                h = 1e-5
                c0, cp, cm = cost(x), cost(x + h * np.eye(2)[j]), cost(x - h * np.eye(2)[j])
                x[j] -= (cp - cm) / (2 * h) / ((cp - 2 * c0 + cm) / h ** 2)
            return cost(x)

        for k, key in enumerate(["A", "tau"]):
            for name, lev in (("68", math.erf(1 / math.sqrt(2))), ("95", 0.95)):
                z2 = quantile(lev, st.dof) ** 2
                ends = []
                for sign in (-1, 1):
                    lo, hi = 0.0, 6 * st.rel[k]
                    for _ in range(40):
                        mid = (lo + hi) / 2
                        lo, hi = (mid, hi) if profiled(k, opt.x[k] + sign * mid) - opt.cost < z2 else (lo, mid)
                    ends.append(math.exp(opt.x[k] + sign * lo))
                got = prof[key][f"interval{name}"]
                width = ends[1] - ends[0]
                # Left: the linearised conditional optimum and the grid's linear interpolation of
                # the signed root (measured: 5e-5 of the width at 2% noise, 1.6e-3 at 20%).
                for a, b in zip(got, ends):
                    self.assertLess(abs(a - b) / width, tol, (level, key, name, got, ends))
                wald_off = max(wald_off, max(abs(a - b) / width for a, b in zip(st.wald(opt.x, lev)[k], ends)))
        return wald_off


class Linear(unittest.TestCase):
    """d = X x − y: the fit's statistics against the textbook's."""
    t = np.linspace(0.0, 1.0, 12)
    X = np.column_stack([np.ones(12), t])
    truth = np.array([0.3, -0.7])

    def evaluate_for(self, y):
        return model_of(lambda x: self.X @ x, y)

    def test_standard_errors_and_wald_intervals_are_the_closed_form(self):
        rng = np.random.default_rng(11)
        y = self.X @ self.truth + 0.05 * rng.standard_normal(12)
        opt = fit(self.evaluate_for(y), absolute(y), [0.0, 0.0], ["a", "b"], **EXACT)
        st = stats(opt, True)
        coef, *_ = np.linalg.lstsq(self.X, y, rcond=None)
        res = self.X @ coef - y
        s2 = float(res @ res) / 10
        sd = np.sqrt(np.diag(s2 * np.linalg.inv(self.X.T @ self.X)))
        np.testing.assert_allclose(opt.x, coef, atol=1e-9)
        np.testing.assert_allclose(st.rel, sd, rtol=1e-6)
        t975 = 2.228138851986274        # Student's t, 10 degrees of freedom, 97.5%
        lo, hi = st.wald(opt.x, 0.95)[1]
        self.assertAlmostEqual(math.log(lo), coef[1] - t975 * sd[1], delta=1e-6)
        self.assertAlmostEqual(math.log(hi), coef[1] + t975 * sd[1], delta=1e-6)

    def test_profile_intervals_of_a_linear_model_are_the_wald_ones(self):
        rng = np.random.default_rng(5)
        y = self.X @ self.truth + 0.05 * rng.standard_normal(12)
        evaluate = self.evaluate_for(y)
        opt = fit(evaluate, absolute(y), [0.0, 0.0], ["a", "b"], **EXACT)
        st = stats(opt, True)
        prof = profile(evaluate, opt, st, ["a", "b"], **QUIET)
        for k, key in enumerate(["a", "b"]):
            for name, level in (("68", math.erf(1 / math.sqrt(2))), ("95", 0.95)):
                np.testing.assert_allclose(prof[key][f"interval{name}"], st.wald(opt.x, level)[k], rtol=1e-6)

    def test_the_intervals_cover_the_truth_at_their_rate(self):
        # 2000 data sets: the binomial standard deviation of the rate is 0.5% (95%), 1.0% (68%);
        # the bounds are 3 of them.
        rng = np.random.default_rng(2026)
        hits, n = {"68": np.zeros(2), "95": np.zeros(2)}, 2000
        for _ in range(n):
            y = self.X @ self.truth + 0.05 * rng.standard_normal(12)
            opt = fit(self.evaluate_for(y), absolute(y), [0.0, 0.0], ["a", "b"], **EXACT)
            st = stats(opt, True)
            for name, level in (("68", math.erf(1 / math.sqrt(2))), ("95", 0.95)):
                for k, (lo, hi) in enumerate(st.wald(opt.x, level)):
                    hits[name][k] += math.log(lo) <= self.truth[k] <= math.log(hi)
        np.testing.assert_allclose(hits["95"] / n, [0.95, 0.95], atol=0.015)
        np.testing.assert_allclose(hits["68"] / n, [0.6827, 0.6827], atol=0.03)

    def test_two_curves_of_different_noise_are_weighted_by_their_own_sigma(self):
        # The same line measured twice, with σ 0.01 and 0.2: each σ estimated, and the standard
        # errors those of the weighted least squares with the true σ (to their estimate's error).
        rng = np.random.default_rng(8)
        t = np.linspace(0.0, 1.0, 200)
        X = np.column_stack([np.ones(200), t])
        X2 = np.vstack([X, X])
        sig = np.r_[np.full(200, 0.01), np.full(200, 0.2)]
        y = X2 @ self.truth + sig * rng.standard_normal(400)
        noises = [Noise("absolute", y[:200]), Noise("absolute", y[200:])]
        opt = fit(model_of(lambda x: X2 @ x, y), lambda d, p: stacked_weights(noises, d, p)[0], [0.0, 0.0],
                  ["a", "b"], **QUIET)
        _, scales = stacked_weights(noises, opt.d, 2)
        np.testing.assert_allclose(scales, [0.01, 0.2], rtol=0.15)     # 200 points: ±5% (1 sd)
        exact = np.sqrt(np.diag(np.linalg.inv(X2.T @ (X2 / sig[:, None] ** 2))))
        np.testing.assert_allclose(stats(opt, True).rel, exact, rtol=0.15)
        # The unweighted fit's error of b would be ~10x the weighted one's.
        self.assertLess(stats(opt, True).rel[1], 3 * exact[1])


if __name__ == "__main__":
    unittest.main()
