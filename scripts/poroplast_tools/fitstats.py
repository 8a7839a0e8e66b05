"""The statistics of a least-squares fit: the noise model's weights, and the parameters' standard
errors and correlations from the Jacobian at the optimum.

Noise models (the residuals are r_i = w_i (model_i − data_i)):

* `absolute`: every point has the same unknown σ (w_i = 1); σ is estimated from the residuals,
  s² = Σ r² / (n − p).
* `relative`: σ_i is an unknown fraction of the value (w_i = 1/|data_i|, floored at 1e-3 of the
  largest |data| so that points near zero do not dominate); the fraction is estimated as above.
* `data`: σ_i is given per point (w_i = 1/σ_i); s² = 1, and χ²/(n − p) = Σ r²/(n − p) tells how
  well the model and the stated σ fit (near 1; much above 1: a model error or σ too small).

The covariance of the parameters is s² (JᵀJ)⁻¹ with J the Jacobian of the weighted residuals at
the optimum; its square-rooted diagonal are the standard errors (in the fit's variables: the
calibration fits ln θ, so they are relative errors of θ) and its normalised form the correlation
matrix."""
import math

import numpy as np

MODELS = ("absolute", "relative", "data")


def weights(noise, values, sigmas=None):
    """w_i of the noise model for the data `values` (and per-point `sigmas` for `data`)."""
    v = np.asarray(values, dtype=float)
    if noise == "absolute":
        return np.ones_like(v)
    if noise == "relative":
        floor = 1e-3 * float(np.max(np.abs(v))) if v.size else 0.0
        return 1.0 / np.maximum(np.abs(v), floor if floor > 0 else 1.0)
    if noise == "data":
        if sigmas is None:
            raise ValueError("the noise model `data` needs a sigma column in the data file")
        return 1.0 / np.asarray(sigmas, dtype=float)
    raise ValueError(f"unknown noise model `{noise}`: expected one of {', '.join(MODELS)}")


def uncertainty(jac, r, noise):
    """(standard errors, correlation matrix, s², χ²/(n − p)) of a fit with Jacobian `jac` (n × p)
    of the weighted residuals `r` at the optimum. NaN where JᵀJ is singular."""
    jac, r = np.asarray(jac, dtype=float), np.asarray(r, dtype=float)
    n, p = jac.shape
    dof = max(n - p, 1)
    chi2 = float(r @ r) / dof
    s2 = 1.0 if noise == "data" else chi2
    try:
        cov = s2 * np.linalg.inv(jac.T @ jac)
    except np.linalg.LinAlgError:
        nan = np.full((p, p), math.nan)
        return np.full(p, math.nan), nan, s2, chi2
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(sd, sd)
    return sd, corr, s2, chi2
