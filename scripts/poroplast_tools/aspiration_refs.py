"""Micropipette aspiration of an incompressible elastic half-space (Theret, Levesque, Sato, Nerem
& Wheeler, J. Biomech. Eng. 110, 190 (1988)): a rigid pipette, inner radius Rp, wall ratio
η = wall thickness / Rp, its flat end the annulus Rp ≤ r ≤ Rp(1 + η) on the surface, suction Δp
over the bore r < Rp. The aspirated length, the surface's displacement on the axis relative to
the pipette end, is

    L = 3 Rp Δp Φ(η) / (2π E),

the wall function Φ computed here (Theret's own table was not available to us) as an
axisymmetric Boussinesq problem, for the two ways to hold the pipette:

* "held": the pipette end does not move (zero displacement; the force it takes is what it
  takes: 65% (η = 0.1) to 98% (η = 10) of the suction force πRp²Δp, the rest reaches infinity,
  a finite body's base);
* "balanced": the pipette presses with exactly the suction force (no net force on the body, as
  on a free cell) and moves with the surface; L is measured from its end.
Which of the two Theret tabulated is not known here; both tend to Φ = 2 as η → ∞; the "2.0–2.1"
quoted in the literature holds for η ≥ 0.2 held (2.096 at 0.2) but only for η ≳ 0.7 balanced
(2.36 at 0.2, 2.14 at 0.5); at η = 0.1: 2.157 held, 2.602 balanced. In a finite body on a fixed
base, a held pipette leaves a net force that shifts the annulus at O(Rp/H) (first order in L);
a balanced one leaves none, and its L (tip minus pipette) drops a near-rigid base shift.

Method:
* surface displacement of a ring load: w(r) = ((1 − ν²)/(πE)) ∫ p(s) 4s/(r + s) K(4rs/(r + s)²) ds
  (K the complete elliptic integral, parameter m = k²);
* the suction's own displacement in closed form (Johnson, Contact Mechanics, §3.4);
* the annulus' unknown pressure q(s) = φ(s)/√((s − a)(b − s)) (the square-root edges of a flat
  punch), φ a Chebyshev series, collocated so that the displacement on the annulus is the
  pipette's (0 held; unknown, with the force condition, balanced);
  L = w_suction(0) + 2((1 − ν²)/E) ∫ q ds − w_pipette.

At ν = ½ a normal surface load moves the surface only normally, so a frictionless and a bonded
pipette end give the same L (whether Theret's contact was bonded does not matter in the linear
half-space). Exact limits: a free disc (no wall) Φ = π; a wall filling the plane (η → ∞) is half
a pressurised penny-shaped crack, w(0) = 4(1 − ν²)Δp Rp/(πE), Φ = 2. The contact pressure is
compressive all over the annulus (held, checked η = 0.1–10), so unilateral contact stays closed.
Accuracy of Φ, held or balanced (default n = 32, against n = 64, 128 extrapolated): 3e-7 at
η = 0.1, 2e-6 at 0.5, 1.4e-5 at 2, 1.6e-4 at 10.
"""
import functools
import math

import numpy as np

C = 1.0    # (1 − ν²)/E, Rp and Δp: the computation is dimensionless, Φ = (π/2) L / (C Rp Δp)


def _agm_k_e(m, k_prime=None):
    """Complete elliptic integrals K(m), E(m) (parameter m = k², 0 ≤ m < 1) by the AGM; near
    m = 1 pass the complementary modulus k' = √(1 − m) itself (it is not recoverable from m)."""
    m = np.asarray(m, dtype=float)
    b = np.sqrt(1.0 - m) if k_prime is None else np.asarray(k_prime, dtype=float)
    a = np.ones_like(b)
    c = np.sqrt(np.maximum(1.0 - b * b, 0.0))
    total, power = 0.5 * c * c, 0.5
    for _ in range(40):
        a, b, c = 0.5 * (a + b), np.sqrt(a * b), 0.5 * (a - b)
        power *= 2.0
        total = total + power * c * c
        if np.all(np.abs(c) < 1e-17):
            break
    k = math.pi / (2.0 * a)
    return k, k * (1.0 - total)


def ellipk(m):
    return _agm_k_e(m)[0]


def ellipe(m):
    return 1.0 if m == 1.0 else _agm_k_e(m)[1]


def disc_displacement(r, a=1.0, pressure=1.0):
    """Normal surface displacement at radius r under a uniform pressure over the disc r < a, in
    units of (1 − ν²)/E (Johnson §3.4): (4pa/π) E((r/a)²) inside, (4pr/π)[E − (1 − a²/r²)K]((a/r)²)
    outside."""
    if r <= a:
        return 4.0 * pressure * a / math.pi * float(ellipe((r / a) ** 2))
    m = (a / r) ** 2
    return 4.0 * pressure * r / math.pi * float(ellipe(m) - (1.0 - m) * ellipk(m))


def ring_kernel(r, s):
    """Displacement at r per unit pressure on the ring (s, s + ds), per ds, units (1 − ν²)/E."""
    # k' = |r − s|/(r + s) directly: 4rs/(r + s)² rounds to 1 within ~1e-8 of the ring.
    k_prime = np.abs(r - s) / (r + s)
    return 4.0 / math.pi * s / (r + s) * _agm_k_e(1.0 - k_prime ** 2, k_prime)[0]


_GL_U, _GL_W = np.polynomial.legendre.leggauss(16)
_GL_U, _GL_W = 0.5 * (_GL_U + 1.0), 0.5 * _GL_W     # on (0, 1)


def _graded(f, lo, hi, at, panels=8):
    """∫_lo^hi f, f log-singular at `at` (an end or inside): `panels` equal panels on each side
    of `at`, 16-point Gauss–Legendre on each in u with x − (the panel's end nearer `at`) ∝ u³,
    which smooths the logarithm (and costs nothing on smooth panels). f may return an array of
    integrands (shape (len(x), k)): then the k integrals."""
    nodes, weights = [], []
    for end in (lo, hi):
        if end == at:
            continue
        edges = at + (end - at) * np.arange(panels + 1) / panels
        near, span = edges[:-1, None], np.diff(edges)[:, None]
        nodes.append((near + span * _GL_U ** 3).ravel())
        weights.append((np.abs(span) * _GL_W * 3.0 * _GL_U ** 2).ravel())
    x, w = np.concatenate(nodes), np.concatenate(weights)    # one call of f for all panels
    return np.tensordot(w, f(x), axes=(0, 0))


def disc_displacement_by_kernel(r, a=1.0):
    """The uniform disc's displacement by integrating ring_kernel (a check of the kernel)."""
    return _graded(lambda s: ring_kernel(r, s), 0.0, a, min(r, a))


def _radius_of(eta):
    """s(θ) = (a + b)/2 + (b − a)/2 cos θ on the annulus a = 1 ≤ s ≤ b = 1 + η."""
    if not (math.isfinite(eta) and eta > 0):
        raise ValueError(f"wall ratio η = {eta} must be positive and finite")
    return lambda th: 1.0 + 0.5 * eta + 0.5 * eta * np.cos(th)


def _annulus(eta, n):
    """The annulus' collocation matrix (displacement at the n Chebyshev points per Chebyshev
    coefficient of φ), the points, and s(θ)."""
    s_of = _radius_of(eta)
    thetas = (np.arange(n) + 0.5) * math.pi / n
    orders = np.arange(n)
    panels = max(4, n // 4)        # panels resolve cos(jθ) up to j = n − 1 on each side
    matrix = np.array([C * _graded(lambda th: np.cos(np.outer(th, orders))
                                   * ring_kernel(s_of(ti), s_of(th))[:, None], 0.0, math.pi, ti,
                                   panels)
                       for ti in thetas])
    return matrix, thetas, s_of


def annulus_force(coef, eta):
    """2π∫q s ds of the annulus pressure with Chebyshev coefficients `coef` (s = (a+b)/2 +
    (b−a)/2 cos θ, ds/√((s−a)(b−s)) = dθ: only the first two terms survive)."""
    a, b = 1.0, 1.0 + eta
    return 2.0 * math.pi * (coef[0] * math.pi * 0.5 * (a + b) + coef[1] * 0.25 * math.pi * (b - a))


def annulus_displacement(coef, eta, r):
    """The displacement at r (units (1 − ν²)/E) of the annulus pressure `coef`."""
    a, b = 1.0, 1.0 + eta
    s_of = _radius_of(eta)
    orders = np.arange(len(coef))
    at = math.acos(max(-1.0, min(1.0, (2.0 * r - a - b) / (b - a)))) if a <= r <= b else 0.0
    return C * float(_graded(lambda th: (np.cos(np.outer(th, orders)) @ coef) * ring_kernel(r, s_of(th)),
                             0.0, math.pi, at, max(4, len(coef) // 4)))


def solve_annulus(eta, n=32, pipette="held", suction=1.0, displacement=0.0):
    """The annulus pressure's Chebyshev coefficients and the pipette's displacement, for a
    suction over the bore and a pipette "held" at `displacement` or "balanced" (its force
    −π·suction, pressing; its displacement unknown). Units: Rp = 1, (1 − ν²)/E = 1."""
    matrix, thetas, s_of = _annulus(eta, n)
    rhs = np.array([-C * disc_displacement(s_of(t), pressure=suction) for t in thetas])
    if pipette == "held":
        return np.linalg.solve(matrix, rhs + displacement), displacement
    if pipette != "balanced":
        raise ValueError(f'pipette "{pipette}": "held" or "balanced"')
    bordered = np.zeros((n + 1, n + 1))
    bordered[:n, :n], bordered[:n, n] = matrix, -1.0
    bordered[n, :2] = annulus_force(np.eye(n)[0], eta), annulus_force(np.eye(n)[1], eta)
    x = np.linalg.solve(bordered, np.append(rhs, -math.pi * suction))
    return x[:n], x[n]


@functools.lru_cache(maxsize=256)     # ~0.03 s each at n = 32, 0.5 s at 128
def wall_function(eta, n=32, pipette="held"):
    """Φ(η) with an n-term Chebyshev series for the annulus' pressure (pipette "held" or
    "balanced", see the module's docstring)."""
    coef, w_pipette = solve_annulus(eta, n, pipette)
    length = C * disc_displacement(0.0) + 2.0 * C * math.pi * coef[0] - w_pipette
    return 0.5 * math.pi * length / C


def aspirated_length(rp, suction, young, eta, n=32, pipette="held"):
    """Theret's L = 3 Rp Δp Φ(η)/(2πE) (incompressible half-space)."""
    for name, v in (("rp", rp), ("young", young)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v} must be positive and finite")
    return 3.0 * rp * suction * wall_function(eta, n, pipette) / (2.0 * math.pi * young)
