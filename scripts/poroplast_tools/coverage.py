"""Coverage of a fit's confidence intervals: the intervals of a calibration's result, whether they
hold the truth, and how often, with the binomial uncertainty of that rate.

The intervals judged are those `calibration.json` holds (`interval68`, `interval95`): Wald
intervals in log space, θ · exp(± q σ/θ), q Student's t with n − p degrees of freedom when σ
comes from the residuals, the normal one when the data state it (fit.Stats).
"""
import math

from .fit import LEVELS          # nominal levels: ±1 σ of a normal (68.27%); 95%

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
