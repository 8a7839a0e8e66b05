"""Coverage of a fit's confidence intervals: the intervals of a calibration's result, whether they
hold the truth, and how often, with the binomial uncertainty of that rate.

The calibration fits ln θ, so its intervals are Wald intervals in log space,
θ · exp(± q σ/θ), with σ the standard error of θ (σ/θ that of ln θ) and q the quantile of
Student's t with n − p degrees of freedom when σ comes from the residuals (noise models
`absolute` and `relative`), of the standard normal when the data state it (`data`).
`calibration.json` may hold them already (`interval68`, `interval95`); otherwise they are
computed here the same way.
"""
import math

from .fit import LEVELS          # nominal levels: ±1 σ of a normal (68.27%); 95%
from .fitstats import quantile   # Student's t (dof) or the normal (None), two-sided

TARGETS = {"68": 0.10, "95": 0.05}                  # the aim: 68 ± 10% and 95 ± 5%


def dof(noise, n, p):
    """The degrees of freedom of the intervals' quantile: n − p when the noise level is estimated
    from the residuals, None (normal) when the data state each point's sigma."""
    return None if noise == "data" else n - p


def wald(value, sigma, level, dof=None):
    """[lo, hi]: the Wald interval of level `level` of a parameter fitted in log space,
    value · exp(± q σ/value)."""
    q = quantile(level, dof)
    half = q * sigma / value
    return [value * math.exp(-half), value * math.exp(half)]


def intervals(entry, dof=None):
    """{"68": [lo, hi], "95": [lo, hi]} of one parameter's entry of calibration.json: its own
    `interval68`/`interval95` when it has them, else `wald` of its value and sigma."""
    return {name: list(entry[f"interval{name}"]) if f"interval{name}" in entry
            else wald(entry["value"], entry["sigma"], level, dof) for name, level in LEVELS.items()}


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
