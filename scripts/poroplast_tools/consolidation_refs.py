"""Terzaghi's one-dimensional consolidation under a constant total stress: the settlement of a
laterally confined column (the creep check of a force-controlled plate, issue 53), computed
here independently of the solver (its Rust twin is src/observe/analytic/terzaghi.rs; this one
serves the study scripts and their tests).

Column of height H, one drained face, incompressible constituents, oedometric modulus
M = λ + 2µ, consolidation coefficient c = k M, τ = c t / H². Degree of consolidation
U(τ) = s(t) / s(∞), s(∞) = σ H / M:

    Fourier series   U = 1 − Σ_m (2/M_m²) e^{−M_m² τ},  M_m = (2m + 1)π/2   (fast for large τ)
    images (short)   U = 2√τ [1/√π + 2 Σ_{n≥1} (−1)^n ierfc(n/√τ)]           (fast for small τ)

Both are exact; each converges for every τ > 0, so their agreement is a check of either.
U = 2√(τ/π) up to exponentially small terms for τ ≲ 0.1 (the first image is ierfc(1/√τ)).
"""
import math

SHORT_TIME = 0.1   # below it `degree` sums the images, above it the Fourier series
_TINY = 1e-18


def _check_tau(tau):
    if not math.isfinite(tau):
        raise ValueError(f"dimensionless time τ = {tau} is not finite")


def degree_fourier(tau):
    """U(τ) by the Fourier series (τ ≤ 0: 0, the state just after loading)."""
    _check_tau(tau)
    if tau <= 0.0:
        return 0.0
    total, m = 0.0, 0
    while True:
        big_m = (2 * m + 1) * math.pi / 2
        amp = 2.0 / big_m ** 2 * math.exp(-big_m ** 2 * tau)
        total += amp
        if amp < _TINY:
            return 1.0 - total
        m += 1


def ierfc(x):
    """∫_x^∞ erfc(s) ds = e^{−x²}/√π − x erfc(x)."""
    return math.exp(-x * x) / math.sqrt(math.pi) - x * math.erfc(x)


def degree_images(tau):
    """U(τ) by the method of images, the short-time form (τ ≤ 0: 0)."""
    _check_tau(tau)
    if tau <= 0.0:
        return 0.0
    r = math.sqrt(tau)
    total, n, sign = 1.0 / math.sqrt(math.pi), 1, -1.0
    while True:
        term = ierfc(n / r)
        total += 2.0 * sign * term
        if term < _TINY:
            return 2.0 * r * total
        sign, n = -sign, n + 1


def degree(tau):
    """U(τ), each form where it converges fast."""
    return degree_images(tau) if tau < SHORT_TIME else degree_fourier(tau)


def settlement(t, height, stress, oedometric_modulus, conductivity):
    """Settlement s(t) of the column [length of `height`] under the total stress `stress`
    applied at t = 0⁺ (s(0⁺) = 0, s(∞) = stress·height/oedometric_modulus); conductivity k is
    the code's k/η, so c = k·(λ + 2µ)."""
    for name, v in (("height", height), ("oedometric_modulus", oedometric_modulus),
                    ("conductivity", conductivity)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"Terzaghi settlement: {name} = {v} must be positive and finite")
    tau = conductivity * oedometric_modulus * t / height ** 2
    return stress * height / oedometric_modulus * degree(tau)
