"""The coverage study's pure parts (Student's t is fitstats.quantile's, tested there): the log-space
Wald intervals, the counting of covered fits against an exactly solvable fit (t intervals cover
at their nominal rate, normal ones with few points do not), Wilson's interval, the synthetic
data sets read back by the lab-format reader, and the linearised study of every noise model."""
import math
import tempfile
import unittest
from pathlib import Path

import numpy as np

from poroplast_tools import coverage as cov
from poroplast_tools import synthetic as syn
from poroplast_tools.fit import Stats
from poroplast_tools.fitstats import quantile
from poroplast_tools.measured import read_curve, write_curve


def wald(value, sigma, level, dof=None):
    """[lo, hi] of one parameter by the calibration's own Wald interval (fit.Stats.wald): Student's
    t of `dof` degrees of freedom (σ estimated), the normal one (None: σ given)."""
    st = Stats(np.array([sigma / value]), None, dof or 1, dof is not None, math.nan)
    return st.wald([math.log(value)], level)[0]


class DegreesOfFreedom(unittest.TestCase):
    def test_the_quantile_follows_the_noise_model(self):
        # n − p degrees of freedom when σ is estimated (absolute, relative), the normal when stated.
        self.assertEqual(Stats(None, None, 71, True, 0.0).z(0.95), quantile(0.95, 71))
        self.assertEqual(Stats(None, None, 73, True, 0.0).z(0.95), quantile(0.95, 73))
        self.assertEqual(Stats(None, None, 71, False, 0.0).z(0.95), quantile(0.95))


class Intervals(unittest.TestCase):
    def test_wald_interval_in_log_space(self):
        # ±1 sigma of a normal: q = 1, so the interval is value · e^(±sigma/value).
        lo, hi = wald(0.002, 5e-5, cov.LEVELS["68"])
        self.assertAlmostEqual(lo, 0.002 * math.exp(-0.025), delta=1e-15)
        self.assertAlmostEqual(hi, 0.002 * math.exp(0.025), delta=1e-15)
        lo, hi = wald(2.5, 0.05, 0.95, 10)
        self.assertAlmostEqual(math.log(hi / 2.5), 2.228138851986274 * 0.02, delta=1e-10)
        self.assertAlmostEqual(lo * hi, 2.5 ** 2, delta=1e-12)          # symmetric in ln θ

    def test_the_calibrations_own_intervals_are_judged(self):
        entry = {"value": 1.0, "sigma": 0.1, "interval68": [0.5, 1.5], "interval95": wald(1.0, 0.1, 0.95, 20)}
        iv = cov.intervals(entry)
        self.assertEqual(iv["68"], [0.5, 1.5])
        self.assertEqual(iv["95"], wald(1.0, 0.1, 0.95, 20))

    def test_covers_is_inclusive_and_normalised_error(self):
        self.assertTrue(cov.covers([1.0, 2.0], 1.0))
        self.assertTrue(cov.covers([1.0, 2.0], 2.0))
        self.assertFalse(cov.covers([1.0, 2.0], 2.0000001))
        self.assertAlmostEqual(cov.normalised_error(2.0 * math.exp(0.03), 0.01 * 2.0 * math.exp(0.03), 2.0), 3.0,
                               delta=1e-12)

    def test_counting_on_an_exact_fit(self):
        # ln y_i = ln θ + ε_i, n = 5 points, ε ~ N(0, 0.1²): the estimate is exp(mean ln y), its
        # standard error (of ln θ) the sample sd / √n with n − 1 = 4 degrees of freedom. Intervals
        # with t(4) cover at their nominal rate exactly; normal quantiles cover 2 F4(1.96) − 1 at
        # "95%" (F4, t's CDF for ν = 4, in closed form: 1/2 + (3/8) u (1 − u²/12), u = t/√(1 + t²/4))
        # — the counting must tell them apart.
        rng = np.random.default_rng(1)
        theta, n, reps = 0.002, 5, 20000
        ln = math.log(theta) + 0.1 * rng.standard_normal((reps, n))
        est = np.exp(ln.mean(axis=1))
        rel = ln.std(axis=1, ddof=1) / math.sqrt(n)
        for name, level in cov.LEVELS.items():
            flags_t = [cov.covers(wald(v, v * s, level, n - 1), theta) for v, s in zip(est, rel)]
            k, total, frac, (lo, hi) = cov.rate(flags_t)
            self.assertEqual(total, reps)
            self.assertLess(abs(frac - level), 4 * math.sqrt(level * (1 - level) / reps))
            self.assertLess(lo, level)
            self.assertGreater(hi, level)
        flags_z = [cov.covers(wald(v, v * s, 0.95), theta) for v, s in zip(est, rel)]
        u = 1.959963984540054 / math.sqrt(1 + 1.959963984540054 ** 2 / 4)
        exact = 2 * (0.5 + 0.375 * u * (1 - u * u / 12)) - 1
        self.assertAlmostEqual(quantile(exact, 4), 1.959963984540054, delta=1e-9)
        self.assertLess(abs(cov.rate(flags_z)[2] - exact), 4 * math.sqrt(exact * (1 - exact) / reps))
        self.assertFalse(cov.on_target("95", cov.rate(flags_z)[2]))
        self.assertTrue(cov.on_target("95", cov.rate(flags_t)[2]))

    def test_wilson_interval(self):
        z = 1.96
        self.assertEqual(cov.wilson(0, 10)[0], 0.0)
        self.assertAlmostEqual(cov.wilson(0, 10)[1], z * z / (10 + z * z), delta=1e-15)
        self.assertAlmostEqual(cov.wilson(10, 10)[0], 10 / (10 + z * z), delta=1e-15)
        lo, hi = cov.wilson(34, 50)
        self.assertAlmostEqual(lo, 0.5419, delta=1e-4)        # 34/50 (Wilson 1927, z = 1.96)
        self.assertAlmostEqual(hi, 0.7924, delta=1e-4)

    def test_targets(self):
        self.assertTrue(cov.on_target("68", 0.58))
        self.assertFalse(cov.on_target("68", 0.57))
        self.assertTrue(cov.on_target("95", 1.0))
        self.assertFalse(cov.on_target("95", 0.89))


class SyntheticData(unittest.TestCase):
    def test_data_times_stop_where_the_force_is_gone(self):
        t = [0.0, 10.0, 20.0, 30.0]
        f = [0.0, 10.0, 10.0, 0.0]
        times = syn.data_times(t, f, every=1.0, floor=0.05)
        self.assertEqual(list(times), [float(x) for x in range(1, 30)])    # f(29) = 1 > 0.5, f(30) = 0
        self.assertEqual(list(syn.data_times(t, f, every=5.0, floor=0.6)), [10.0, 15.0, 20.0])   # f(25) = 5 < 6

    def test_noise_is_seeded_independent_and_relative(self):
        v = np.full(20000, 3.0)
        a, b = syn.noisy(v, 0.02, 38, 0), syn.noisy(v, 0.02, 38, 1)
        np.testing.assert_array_equal(a, syn.noisy(v, 0.02, 38, 0))
        self.assertLess(abs(np.corrcoef(a, b)[0, 1]), 4 / math.sqrt(v.size))
        self.assertLess(abs(np.std(a / v - 1) / 0.02 - 1), 4 / math.sqrt(2 * v.size))

    def test_a_data_set_reads_back_in_the_lab_format(self):
        times, values = [1.0, 2.0, 3.5], [0.25, 1.0 / 3.0, 4.0]
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "set.csv"
            write_curve(path, np.array(times), np.array(values), [0.1, 0.2, 0.3], "a test")
            t, v, s = read_curve(path, syn.COLUMN)
        self.assertEqual((t, v, s), (times, values, [0.1, 0.2, 0.3]))

    def test_fits_are_on_the_cases_parameters(self):
        for case in syn.CASES.values():
            for p, (keys, truth) in case.fits.items():
                self.assertEqual(len(keys), p)
                self.assertTrue(set(keys) <= set(truth))
                for level in case.levels:
                    fixed = dict(case.sets(level, truth, keys))
                    self.assertFalse(set(keys) & set(fixed))
                    self.assertTrue(all(k in fixed for k in truth if k not in keys))
                    for own in case.experiments.values():
                        self.assertFalse({k for k, _ in own} & (set(fixed) | set(truth)))
        self.assertEqual(syn.sets("coarse", *reversed(syn.FITS[1])), syn.MERIDIAN.sets("coarse", *reversed(syn.FITS[1])))

    def test_the_meridian_data_sets_are_those_of_before(self):
        # One experiment: data set i of the seed is default_rng([seed, i]) (the study's files
        # unchanged); several: (i, j + 1), independent of each other and of the one-experiment
        # sets. (i, 0) would not be: SeedSequence ignores trailing zeros.
        v = np.full(2000, 1.0)
        rng = np.random.default_rng([41, 3])
        np.testing.assert_array_equal(syn.noisy(v, 0.02, 41, 3), v + 0.02 * rng.standard_normal(v.size))
        np.testing.assert_array_equal(syn.noisy(v, 0.02, 41, (3, 0)), syn.noisy(v, 0.02, 41, 3))
        a, b = syn.noisy(v, 0.02, 41, (3, 1)), syn.noisy(v, 0.02, 41, (3, 2))
        np.testing.assert_array_equal(a, syn.noisy(v, 0.02, 41, [3, 1]))
        for other in (b, syn.noisy(v, 0.02, 41, 3), syn.noisy(v, 0.02, 41, (1, 3))):
            self.assertLess(abs(np.corrcoef(a, other)[0, 1]), 4 / math.sqrt(v.size))

    def test_the_tensiometry_case_is_read_back_as_two_experiments(self):
        from poroplast_tools import experiments as exps
        case = syn.TST
        self.assertTrue(case.several and not syn.MERIDIAN.several)
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "experiments.toml"
            path.write_text(syn.experiments_text(case, {"c15": Path(d) / "set_000_c15.csv", "c30": "set_000_c30.csv"}))
            es = exps.read(path, {"scene": case.scene, "column": case.column, "noise": "relative"})
        self.assertEqual([e.name for e in es], ["c15", "c30"])
        self.assertEqual([e.data for e in es], [str(Path(d) / "set_000_c15.csv"), str(Path(d) / "set_000_c30.csv")])
        self.assertEqual(es[1].sets, [("plates.table", "[[0.0, 0.0], [5.0, 0.3], [1005.0, 0.3]]"),
                                      ("time.t_end", "1005.0")])
        self.assertTrue(all(e.scene == "tst_hold" and e.noise == "relative" for e in es))
        args = syn.calibrate_args(3, "coarse", 1.1, case=case)
        self.assertEqual(args[:3], ["tst_hold", "--column", "force_total_mg"])
        self.assertIn("--param=surface.tension=5.5", args)
        self.assertFalse(any(a.startswith("--set=surface.tension") for a in args))
        self.assertEqual(exps.params([a[len("--param="):] for a in args if a.startswith("--param=")], es)[0].key,
                         "surface.tension")


class Linearised(unittest.TestCase):
    """The linearised study: each noise model's data drawn from its own σ, fitted through
    fit.fit and fitstats' weights; on a model linear in its log-parameters the intervals must
    cover at their rate for every noise model, and the estimates be unbiased (the relative ones:
    because the weights are the model's; by the data's, A's mean z is −0.42 for relative and
    −0.41 for relative+floor over these draws, 7 standard errors of a mean off 0; measured)."""
    t = np.linspace(0.0, 10.0, 1000)
    e = np.exp(-t / 3.0)
    curves = [2.0 * e + 0.5]
    jac = np.column_stack([2.0 * e, 2.0 * e * t / 3.0, np.full(t.size, 0.5)])    # d/d ln (A, τ, c)
    n = 300

    def test_noise_sigmas(self):
        c = np.array([1.0, -2.0, 4.0])
        np.testing.assert_allclose(cov.noise_sigmas("absolute", c, 0.1)[0], np.full(3, 0.1 * math.sqrt(7.0)))
        np.testing.assert_allclose(cov.noise_sigmas("relative", c, 0.1)[0], [0.1, 0.2, 0.4])
        sig, floor = cov.noise_sigmas("relative+floor", c, 0.1)
        self.assertAlmostEqual(floor, cov.FLOOR * 0.4, delta=1e-15)
        np.testing.assert_allclose(sig, np.hypot([0.1, 0.2, 0.4], floor))
        with self.assertRaises(ValueError):
            cov.noise_sigmas("poisson", c, 0.1)

    def test_every_noise_models_intervals_cover_at_their_rate(self):
        se = {name: math.sqrt(level * (1 - level) / self.n) for name, level in cov.LEVELS.items()}
        for model in cov.NOISES:
            fits = cov.linearised_fits(self.curves, self.jac, model, 0.02, self.n, 51, 1.1)
            z = np.array([f["z"] for f in fits])
            # Means within 3 standard errors of a mean, spreads within 3 of an sd (1/√(2n)), rates
            # within 3 binomial standard deviations (measured: every one within 1.9).
            np.testing.assert_allclose(z.mean(axis=0), 0.0, atol=3 / math.sqrt(self.n), err_msg=model)
            np.testing.assert_allclose(z.std(axis=0), 1.0, atol=3 / math.sqrt(2 * self.n), err_msg=model)
            for name, level in cov.LEVELS.items():
                rates = np.mean([f[f"covered{name}"] for f in fits], axis=0)
                np.testing.assert_allclose(rates, level, atol=3 * se[name], err_msg=f"{model}, {name}%")
            s = np.array([f["s"][0] for f in fits])
            truth = {"absolute": cov.noise_sigmas("absolute", self.curves[0], 0.02)[0][0], "data": 1.0}.get(model, 0.02)
            self.assertAlmostEqual(s.mean() / truth, 1.0, delta=3 * s.std() / truth / math.sqrt(self.n), msg=model)


if __name__ == "__main__":
    unittest.main()
