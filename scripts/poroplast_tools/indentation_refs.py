"""A rigid sphere pressed, frictionless, into a linear (poro)elastic half-space: closed forms to
check the solver's sphere tool against, computed independently of it.

* Hertz (paraboloid; Johnson, Contact Mechanics, 1985, ch. 4): F = (4/3) E* √R δ^{3/2},
  a = √(R δ), E* = E/(1 − ν²) for a rigid indenter, R the combined radius
  1/R = 1/R_indenter + 1/R_body. With the shear modulus G: E* = 2G/(1 − ν), so
  instantaneous (undrained, incompressible constituents, ν = ½) F₀ = (16/3) G δ a and drained
  (ν the drained ratio) F∞ = F₀ / (2(1 − ν)).
* Sneddon's exact sphere (Sneddon 1965), in the contact radius a:
  F = (E*/2) [(a² + R²) ln((R + a)/(R − a)) − 2aR],  δ = (a/2) ln((R + a)/(R − a)).
  At equal depth F_Sneddon/F_Hertz = 1 − (a/R)²/10 + O((a/R)⁴): −0.025% at a/R = 0.05,
  −0.100% at 0.1, −0.41% at 0.2.
* Poroelastic relaxation under a sphere held at depth δ after a step (Hu, Zhao, Vlassak, Suo,
  Appl. Phys. Lett. 96, 121904 (2010)): (F(t) − F∞)/(F₀ − F∞) = g(τ), τ = D t/a²,
  g(τ) = 0.491 e^{−0.908√τ} + 0.509 e^{−1.679τ}, D = 2(1 − ν) G k/(1 − 2ν) = k(λ + 2µ) (k the
  code's k/η). g is their fit to finite-element results, independent of ν; it assumes a step
  (no ramp) and a half-space (√(Dt) ≪ the body). Its stated accuracy is not known here
  (not found in what we could read); its coefficients sum to exactly 1 (g(0) = 1).
"""
import math

# Hu, Zhao, Vlassak & Suo (2010), spherical indenter: g = A e^{−α√τ} + B e^{−βτ}.
HZVS_SPHERE = (0.491, 0.908, 0.509, 1.679)


def _positive(**values):
    for name, v in values.items():
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v} must be positive and finite")


def combined_radius(r_indenter, r_body=math.inf):
    """R = (1/R_i + 1/R_b)⁻¹ (a flat body: R_b = ∞)."""
    _positive(r_indenter=r_indenter, r_body=r_body)
    return 1.0 / (1.0 / r_indenter + 1.0 / r_body)


def contact_modulus(shear_modulus, poisson):
    """E* = E/(1 − ν²) = 2G/(1 − ν) against a rigid indenter."""
    _positive(shear_modulus=shear_modulus)
    if not -1.0 < poisson <= 0.5:
        raise ValueError(f"Poisson ratio {poisson} outside (−1, ½]")
    return 2.0 * shear_modulus / (1.0 - poisson)


def hertz_force(depth, radius, e_star):
    """Hertz's F(δ) = (4/3) E* √R δ^{3/2}."""
    _positive(radius=radius, e_star=e_star)
    return 4.0 / 3.0 * e_star * math.sqrt(radius) * max(depth, 0.0) ** 1.5


def hertz_contact_radius(depth, radius):
    """Hertz's a(δ) = √(R δ)."""
    return math.sqrt(radius * max(depth, 0.0))


def sneddon_sphere(a, radius, e_star):
    """Sneddon's exact rigid sphere at contact radius a < R: (depth δ, force F)."""
    _positive(a=a, radius=radius, e_star=e_star)
    if a >= radius:
        raise ValueError(f"contact radius {a} must be below the sphere's radius {radius}")
    log = math.log((radius + a) / (radius - a))
    return 0.5 * a * log, 0.5 * e_star * ((a * a + radius * radius) * log - 2.0 * a * radius)


def sneddon_force(depth, radius, e_star):
    """Sneddon's F at the depth δ (the contact radius found by bisection: δ(a) is increasing)."""
    _positive(depth=depth)
    lo, hi = 0.0, radius * (1.0 - 1e-15)
    if sneddon_sphere(hi, radius, e_star)[0] < depth:
        raise ValueError(f"depth {depth} beyond the sphere's exact solution (a → R)")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if sneddon_sphere(mid, radius, e_star)[0] < depth else (lo, mid)
    return sneddon_sphere(0.5 * (lo + hi), radius, e_star)[1]


def relaxation_g(tau, coefficients=HZVS_SPHERE):
    """Hu et al.'s normalised force g(τ) = (F − F∞)/(F₀ − F∞) after a step indentation."""
    if not math.isfinite(tau) or tau < 0:
        raise ValueError(f"dimensionless time τ = {tau} must be ≥ 0 and finite")
    a, alpha, b, beta = coefficients
    return a * math.exp(-alpha * math.sqrt(tau)) + b * math.exp(-beta * tau)


def poroelastic_diffusivity(shear_modulus, poisson, conductivity):
    """D = 2(1 − ν) G k/(1 − 2ν) (= k(λ + 2µ), the code's consolidation coefficient)."""
    _positive(shear_modulus=shear_modulus, conductivity=conductivity)
    if not -1.0 < poisson < 0.5:
        raise ValueError(f"drained Poisson ratio {poisson} outside (−1, ½)")
    return 2.0 * (1.0 - poisson) * shear_modulus * conductivity / (1.0 - 2.0 * poisson)


def relaxation_force(t, depth, radius, shear_modulus, poisson, conductivity):
    """F(t) under a sphere (combined radius `radius`) held at `depth` from t = 0⁺: F₀ at 0⁺
    (undrained Hertz), F∞ (drained Hertz) as t → ∞, Hu et al.'s g in between."""
    a = hertz_contact_radius(depth, radius)
    f0 = hertz_force(depth, radius, contact_modulus(shear_modulus, 0.5))
    f_inf = hertz_force(depth, radius, contact_modulus(shear_modulus, poisson))
    tau = poroelastic_diffusivity(shear_modulus, poisson, conductivity) * max(t, 0.0) / a ** 2
    return f_inf + (f0 - f_inf) * relaxation_g(tau)
