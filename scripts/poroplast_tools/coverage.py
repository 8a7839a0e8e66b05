"""Coverage of a fit's confidence intervals: the intervals of a calibration's result, whether they
hold the truth, and how often, with the binomial uncertainty of that rate.

The calibration fits ln θ, so its intervals are Wald intervals in log space,
θ · exp(± q σ/θ), with σ the standard error of θ (σ/θ that of ln θ) and q the quantile of
Student's t with n − p degrees of freedom when σ comes from the residuals (noise models
`absolute` and `relative`), of the standard normal when the data state it (`data`).
`calibration.json` may hold them already (`interval68`, `interval95`); otherwise they are
computed here the same way.
"""
import functools
import math
from statistics import NormalDist

LEVELS = {"68": 0.6826894921370859, "95": 0.95}   # nominal levels: ±1 σ of a normal; 95%
TARGETS = {"68": 0.10, "95": 0.05}                  # issue 38: 68 ± 10% and 95 ± 5%


def _betacf(a, b, x):
    """The continued fraction of the regularised incomplete beta function (modified Lentz)."""
    tiny, c, d = 1e-300, 1.0, 1.0 - (a + b) * x / (a + 1.0)
    d = 1.0 / (d if abs(d) > tiny else tiny)
    h = d
    for m in range(1, 400):
        for num in (m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
                    -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))):
            d = 1.0 + num * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + num / c
            c = c if abs(c) > tiny else tiny
            h *= d * c
        if abs(d * c - 1.0) < 1e-15:
            break
    return h


def beta_inc(a, b, x):
    """The regularised incomplete beta function I_x(a, b)."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    front = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log1p(-x))
    if x < (a + 1.0) / (a + b + 2.0):
        return front * _betacf(a, b, x) / a
    return 1.0 - front * _betacf(b, a, 1.0 - x) / b


def t_cdf(t, dof):
    """P(T ≤ t) for Student's t with `dof` degrees of freedom."""
    tail = 0.5 * beta_inc(0.5 * dof, 0.5, dof / (dof + t * t))
    return 1.0 - tail if t >= 0 else tail


@functools.lru_cache(maxsize=None)     # a study asks for the same few quantiles many times
def t_quantile(p, dof=None):
    """The p-quantile of Student's t with `dof` degrees of freedom (None: the standard normal)."""
    if dof is None or math.isinf(dof):
        return NormalDist().inv_cdf(p)
    if p < 0.5:
        return -t_quantile(1.0 - p, dof)
    lo, hi = 0.0, 1.0
    while t_cdf(hi, dof) < p:
        hi *= 2.0
    for _ in range(200):      # bisection: t_cdf is monotone, 200 halvings reach round-off
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if t_cdf(mid, dof) < p else (lo, mid)
    return 0.5 * (lo + hi)


def dof(noise, n, p):
    """The degrees of freedom of the intervals' quantile: n − p when the noise level is estimated
    from the residuals, None (normal) when the data state each point's sigma."""
    return None if noise == "data" else n - p


def wald(value, sigma, level, dof=None):
    """[lo, hi]: the Wald interval of level `level` of a parameter fitted in log space,
    value · exp(± q σ/value)."""
    q = t_quantile(0.5 * (1.0 + level), dof)
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
    """Whether a coverage rate is within issue 38's target for the level `name` ("68", "95")."""
    nominal = 0.68 if name == "68" else 0.95
    return abs(fraction - nominal) <= TARGETS[name] + 1e-12     # the bounds included (29/50 = 0.58)
