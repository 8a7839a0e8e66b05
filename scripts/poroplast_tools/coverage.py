"""Coverage of a fit's confidence intervals: the intervals of a calibration's result, whether they
hold the truth, and how often, with the binomial uncertainty of that rate.

The intervals judged are those `calibration.json` holds (`interval68`, `interval95`): Wald
intervals in log space, θ · exp(± q σ/θ), q Student's t with n − p degrees of freedom when σ
comes from the residuals, the normal one when the data state it (fit.Stats). And the same
statistics on a case's linearised model, for every noise model (`linearised_fits`).
"""
import math

import numpy as np

from .fit import LEVELS, fit, stats     # LEVELS: ±1 σ of a normal (68.27%); 95%
from .fitstats import Noise, stacked_weights

TARGETS = {"68": 0.10, "95": 0.05}                  # the aim: 68 ± 10% and 95 ± 5%


def intervals(entry):
    """{"68": [lo, hi], "95": [lo, hi]} of one parameter's entry of calibration.json (the Wald
    intervals calibrate.py writes: fit.Stats.wald)."""
    return {name: list(entry[f"interval{name}"]) for name in LEVELS}


def covers(interval, truth):
    lo, hi = interval
    return lo <= truth <= hi


def normalised_error(value, sigma, truth):
    """(ln value − ln truth) / (σ/value): the error in units of its standard error, in the fit's
    (log) variable; standard normal for an honest σ and a linear model."""
    return math.log(value / truth) / (sigma / value)


def wilson(k, n, z=1.96):
    """The Wilson score interval [lo, hi] of a binomial proportion k/n (z = 1.96: 95%)."""
    if n == 0:
        return [math.nan, math.nan]
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return [max(centre - half, 0.0), min(centre + half, 1.0)]     # within [0, 1] but for round-off


def rate(flags):
    """(k, n, k/n, Wilson 95% interval) of a list of covered flags."""
    k, n = sum(bool(f) for f in flags), len(flags)
    return k, n, (k / n if n else math.nan), wilson(k, n)


def on_target(name, fraction):
    """Whether a coverage rate is within the target for the level `name` ("68", "95")."""
    nominal = 0.68 if name == "68" else 0.95
    return abs(fraction - nominal) <= TARGETS[name] + 1e-12     # the bounds included (29/50 = 0.58)


# The linearised study: the coverage of the fit's own statistics on a model without solver runs,
# F(x) = F0 + J (x − x0) in the log-parameters x, with the Jacobian J of the case's jitter runs
# at the truth x0. Thousands of fits cost seconds, so a rate's binomial error is a fraction of a
# percent, and every noise model can be judged: the data are drawn from the model's own noise,
# fitted by fit.fit with fitstats' weights, as calibrate.py does.
NOISES = ("absolute", "relative", "relative+floor", "data")
FLOOR = 0.1      # relative+floor: the floor is this fraction of the relative noise at a curve's largest value


def noise_sigmas(model, curve, level):
    """(σ_i of one curve's data under the noise `model` at `level`, the floor given to the fit or
    None): absolute level × the curve's rms; relative and data level |F_i|; relative+floor
    √((level F_i)² + f²), f = FLOOR level max |F|."""
    f = np.abs(np.asarray(curve, dtype=float))
    if model == "absolute":
        return np.full(f.size, level * math.sqrt(float(np.mean(f * f)))), None
    if model == "relative+floor":
        floor = FLOOR * level * float(np.max(f))
        return np.hypot(level * f, floor), floor
    if model in ("relative", "data"):
        return level * f, None
    raise ValueError(f"unknown noise model `{model}`: expected one of {', '.join(NOISES)}")


def linearised_fits(curves, jac, model, level, sets, seed, start_factor, ftol=1e-3, max_it=15):
    """`sets` fits of the linearised model (curves: each experiment's true values F0, stacked in
    that order; jac: dF/d ln θ at the truth, the stacked rows × the parameters) to data with the
    noise `model` at `level` (data set i from the seed [seed, NOISES.index(model), i]), each from
    the truth × start_factor, stopping as calibrate.py's fit does (`ftol`, `max_it`): per fit the
    normalised errors z (ln estimate / truth over σ), the
    68% and 95% Wald intervals' covered flags, and each experiment's estimated noise scale s."""
    f0 = np.concatenate(curves)
    jac = np.asarray(jac, dtype=float)
    parts = np.cumsum([0] + [len(c) for c in curves])
    sig, floors = zip(*(noise_sigmas(model, c, level) for c in curves))
    sig = np.concatenate(sig)
    x0 = np.zeros(jac.shape[1])             # ln θ − ln truth
    keys = [f"p{k}" for k in range(jac.shape[1])]
    out = []
    for i in range(sets):
        rng = np.random.default_rng([seed, NOISES.index(model), i])
        data = f0 + sig * rng.standard_normal(f0.size)
        noises = [Noise(model, data[a:b], sig[a:b] if model == "data" else None, fl)
                  for a, b, fl in zip(parts[:-1], parts[1:], floors)]

        def evaluate(points, what, replay=None):
            return [(f0 + jac @ (np.asarray(x) - x0) - data, None) for x in points]

        opt = fit(evaluate, lambda d, p: stacked_weights(noises, d, p)[0], x0 + math.log(start_factor), keys,
                  max_it=max_it, ftol=ftol, say=lambda *_: None)
        st = stats(opt, model != "data")
        one = {"z": (opt.x - x0) / st.rel, "s": stacked_weights(noises, opt.d, len(keys))[1]}
        for name, lev in LEVELS.items():
            one[f"covered{name}"] = [lo <= 1.0 <= hi for lo, hi in st.wald(opt.x, lev)]
        out.append(one)
    return out
