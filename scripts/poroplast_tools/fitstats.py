"""The statistics of a least-squares fit: the noise models' weights and the intervals' quantiles
(the standard errors and correlations from the Jacobian at the optimum: `fit.stats`).

Noise models (the residuals are r_i = w_i (model_i − data_i)):

* `absolute`: every point has the same unknown σ (w_i = 1); σ is estimated from the residuals,
  s² = Σ r² / (n − p).
* `relative`: σ_i is an unknown fraction of the value (w_i = 1/|model_i|, floored at 1e-3 of the
  largest |model| so that points near zero do not dominate); the fraction is estimated as above.
* `data`: σ_i is given per point (w_i = 1/σ_i); s² = 1, and χ²/(n − p) = Σ r²/(n − p) tells how
  well the model and the stated σ fit (near 1; much above 1: a model error or σ too small).
* `relative+floor`: σ_i = √((ρ model_i)² + f²), a relative noise ρ above an instrument's floor f
  (given, in the value's unit): force data that reach zero after contact loss keep a finite σ. ρ
  is estimated: the root of Σ (d_i/σ_i(ρ))² = n − p (`Noise.weights`; ρ = 0 when the floor alone
  explains the residuals).

The relative models' σ_i are a fraction of the model's value, model_i = data_i + d_i, not of the
data's: weights 1/|data_i| give a point the noise pushed up less weight than one pushed down, and
the fitted curve comes out low by about 2ρ² of its value (0.08% at ρ = 2%), more than a standard
error on a curve of thousands of points. The model's value is not known before the fit, so the
fit holds the weights fixed in its Levenberg–Marquardt steps and estimates them anew at each
optimum until they settle (fit.fit's rounds: iteratively re-weighted least squares). Its fixed
point solves Σ (model_i − data_i) ∂model_i/∂θ / σ_i² = 0, which is zero on average at the truth
(quasi-likelihood): unbiased to first order. Not the alternatives: minimising Σ ((model − data) /
model)² with the weights' own derivative in the Jacobian biases the curve high by ρ², and the
log residual ln data − ln model low by ρ²/2 (E ln(1 + ρε) = −ρ²/2), and it cannot take data at or
below zero.

`Noise` holds one curve's model and turns its differences d = model − data into the weights
that give the weighted residuals unit variance, from the degrees of freedom the curve is granted
(a fit over several curves grants each n_e − p n_e / n: the parameters' share). `quantile` gives
the two-sided z of a level: Student's t with n − p degrees of freedom when σ is estimated from the
residuals, the normal one when it is given.
"""
import functools
import math

import numpy as np

MODELS = ("absolute", "relative", "data", "relative+floor")


def weights(noise, values, sigmas=None):
    """w_i of the noise model for the curve `values` (the model's: see the module; and per-point
    `sigmas` for `data`), before the estimated scale."""
    v = np.asarray(values, dtype=float)
    if noise == "absolute":
        return np.ones_like(v)
    if noise in ("relative", "relative+floor"):
        floor = 1e-3 * float(np.max(np.abs(v))) if v.size else 0.0
        return 1.0 / np.maximum(np.abs(v), floor if floor > 0 else 1.0)
    if noise == "data":
        if sigmas is None:
            raise ValueError("the noise model `data` needs a sigma column in the data file")
        return 1.0 / np.asarray(sigmas, dtype=float)
    raise ValueError(f"unknown noise model `{noise}`: expected one of {', '.join(MODELS)}")


class Noise:
    """One curve's noise model (`MODELS`) over its data `values` (with per-point `sigmas` for
    `data`, the `floor` for `relative+floor`)."""

    def __init__(self, model, values, sigmas=None, floor=None):
        if model == "relative+floor" and not (floor is not None and floor > 0):
            raise ValueError("the noise model `relative+floor` needs a positive floor (--noise-floor)")
        if model not in MODELS:
            raise ValueError(f"unknown noise model `{model}`: expected one of {', '.join(MODELS)}")
        self.model, self.y, self.floor = model, np.asarray(values, dtype=float), floor
        self.given = weights(model, values, sigmas) if model == "data" else None
        self.estimated = model != "data"

    def weights(self, d, dof):
        """(w, s): the weights that give w d unit variance at the model data + d, s estimated
        from the differences `d` with `dof` degrees of freedom (the σ of absolute, the fraction
        of relative and of relative+floor); s = 1 for `data`."""
        d = np.asarray(d, dtype=float)
        if self.model == "data":
            return self.given, 1.0
        model = self.y + d
        if self.model == "relative+floor":
            rho = floor_fraction(d, model, self.floor, dof)
            return 1.0 / np.sqrt((rho * model) ** 2 + self.floor ** 2), rho
        shape = weights(self.model, model)
        s = math.sqrt(float(np.sum((shape * d) ** 2)) / dof)
        return shape / (s if s > 0 else 1.0), s


def floor_fraction(d, y, floor, dof):
    """ρ ≥ 0 with Σ d_i² / ((ρ y_i)² + floor²) = dof, y the model's values (bisection in log ρ;
    the sum falls with ρ); 0 when the floor alone leaves the sum below dof."""
    def excess(rho):
        return float(np.sum(d ** 2 / ((rho * y) ** 2 + floor ** 2))) - dof
    if excess(0.0) <= 0 or not np.any(y):
        return 0.0
    lo, hi = 1e-12, 1.0
    while excess(hi) > 0:
        lo, hi = hi, hi * 10
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if excess(mid) > 0 else (lo, mid)
        if hi / lo < 1 + 1e-12:
            break
    return math.sqrt(lo * hi)


@functools.lru_cache(maxsize=None)
def quantile(level, dof=None):
    """z of a two-sided interval of probability `level`: Student's t with `dof` degrees of
    freedom (σ estimated), the normal one (dof None: σ given)."""
    from statistics import NormalDist
    p = 0.5 + level / 2
    z = NormalDist().inv_cdf(p)
    if dof is None:
        return z
    lo, hi = 0.0, max(2 * z, 1.0)
    while _t_cdf(hi, dof) < p:
        hi *= 2
    for _ in range(200):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if _t_cdf(mid, dof) < p else (lo, mid)
    return (lo + hi) / 2


def _t_cdf(t, dof):
    """Student's t distribution function, through the regularised incomplete beta function."""
    x = dof / (dof + t * t)
    tail = 0.5 * _betainc(dof / 2, 0.5, x)
    return 1 - tail if t > 0 else tail


def _betainc(a, b, x):
    """I_x(a, b) by its continued fraction (Numerical Recipes' betacf, Lentz's method)."""
    if x <= 0 or x >= 1:
        return float(x >= 1)
    front = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log1p(-x))
    if x > (a + 1) / (a + b + 2):
        return 1 - _betainc(b, a, 1 - x)
    tiny = 1e-300
    c, d = 1.0, 1 - (a + b) * x / (a + 1)
    d = 1 / (d if abs(d) > tiny else tiny)
    f = d
    for m in range(1, 500):
        for num in (m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
                    -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))):
            d = 1 + num * d
            d = 1 / (d if abs(d) > tiny else tiny)
            c = 1 + num / c
            c = c if abs(c) > tiny else tiny
            f *= c * d
        if abs(c * d - 1) < 1e-15:
            break
    return front * f / a


def stacked_weights(noises, d, p):
    """(w, [s per curve]) of curves stacked in `d` (each `Noise` over its own stretch of d, in
    order) for a fit of p parameters shared among them: each curve estimates its σ from its
    own residuals with n_e − p n_e / n degrees of freedom (the parameters' share), so that the
    stacked weighted residuals have unit variance and the sum of their squares n − p."""
    n, out, scales, at = len(d), [], [], 0
    for noise in noises:
        ne = len(noise.y)
        w, s = noise.weights(d[at:at + ne], ne - p * ne / n)
        out.append(w)
        scales.append(s)
        at += ne
    return np.concatenate(out), scales
