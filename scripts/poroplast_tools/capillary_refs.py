"""A liquid drop (surface tension γ, volume V₀ = 4πR₀³/3, no gravity) held at a pipette by a
suction Δp below its threshold: the static shape and the threshold, computed independently of the
solver (issue 53's verification).

Meridian (ρ, z), the pipette's axis along z, its bore towards −z, its mouth plane z = 0. The rim
is a circle of radius r (the rounded wall end; r = 0: a sharp edge) centred at (ρ_r, ζ_r) =
(Rp + r, −r). The drop's surface is three arcs:
  * the outer sphere, radius R_o, centre (0, z_o), its pressure P = 2γ/R_o;
  * the rim circle between the two points where the spheres touch it;
  * the cap in the bore, radius R_c, centre (0, z_c), with P + Δp = 2γ/R_c (Young–Laplace
    across the suction), i.e. 1/R_c = 1/R_o + Δp/(2γ).
Both spheres touch the rim from outside: √(ρ_r² + (z − ζ_r)²) = R + r, z = ζ_r + √((R+r)² − ρ_r²)
(the root with the centre above the rim's: the cap is at most a hemisphere). The tip is at
z_c − R_c, so L = R_c − z_c (r = 0: L = R_c − √(R_c² − Rp²)). R_o follows from V = V₀, the
volume of revolution of the three arcs (each in closed form), by bisection.

The threshold: a cap can touch the rim only while R_c ≥ Rp. Along the volume-conserving shapes
the suction Δp(R_c) peaks just above R_c = Rp (the saddle-node where the static drop is lost;
below it in R_c the shapes are the unstable branch), at 2γ(1/R_c − 1/R_o) within ~1e-7 of the
hemispherical cap's 2γ(1/Rp − 1/R_o) (R₀ = 5Rp), with L within ~1e-3 Rp of Rp + r.
Guevorkian et al. (PRL 104, 218101 (2010)) write Δp_c = 2γ(1/Rp − 1/R₀), R₀ the drop's radius
before the suction: 0.03% above the exact value at R₀ = 5Rp, since the tongue's
volume shrinks the outer sphere.
"""
import math
from dataclasses import dataclass


def guevorkian_threshold(gamma, rp, r0):
    """Δp_c = 2γ(1/Rp − 1/R₀) (Guevorkian et al. 2010)."""
    _positive(gamma=gamma, rp=rp, r0=r0)
    return 2.0 * gamma * (1.0 / rp - 1.0 / r0)


def _positive(**values):
    for name, v in values.items():
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v} must be positive and finite")


def _segment_volume(radius, centre, z1, z2):
    """π∫ρ² dz of a sphere (centre (0, centre)) between the heights z1 ≤ z2."""
    u1, u2 = z1 - centre, z2 - centre
    return math.pi * (radius ** 2 * (u2 - u1) - (u2 ** 3 - u1 ** 3) / 3.0)


def _rim_volume(rho_r, zeta_r, r, z1, z2):
    """π∫ρ² dz under the rim circle's inner half ρ = ρ_r − √(r² − (z − ζ_r)²), z1 ≤ z2."""
    if r == 0.0:
        return 0.0

    def prim(z):
        u = max(-r, min(r, z - zeta_r))
        root = math.sqrt(max(r * r - u * u, 0.0))
        return (rho_r ** 2 + r * r) * u - u ** 3 / 3.0 - rho_r * (u * root + r * r * math.asin(u / r))
    return math.pi * (prim(z2) - prim(z1))


@dataclass(frozen=True)
class Shape:
    """The static drop: its spheres, the rim, the points of contact, the aspirated length."""
    rp: float
    r_rim: float
    r_outer: float
    z_outer: float
    r_cap: float
    z_cap: float

    @property
    def rim_centre(self):
        return self.rp + self.r_rim, -self.r_rim

    def _touch(self, centre_z):
        """The point where a sphere centred at (0, centre_z) touches the rim circle."""
        rho_r, zeta_r = self.rim_centre
        d = math.hypot(rho_r, centre_z - zeta_r)
        return rho_r - self.r_rim * rho_r / d, zeta_r + self.r_rim * (centre_z - zeta_r) / d

    @property
    def outer_contact(self):
        return self._touch(self.z_outer)

    @property
    def cap_contact(self):
        return self._touch(self.z_cap)

    @property
    def tip(self):
        return self.z_cap - self.r_cap

    @property
    def top(self):
        return self.z_outer + self.r_outer

    @property
    def aspirated_length(self):
        """L: the tip's depth below the mouth plane z = 0."""
        return -self.tip

    def volume(self):
        """The volume of revolution of the three arcs, in closed form."""
        rho_r, zeta_r = self.rim_centre
        z_oc, z_cc = self.outer_contact[1], self.cap_contact[1]
        return (_segment_volume(self.r_cap, self.z_cap, self.tip, z_cc)
                + _rim_volume(rho_r, zeta_r, self.r_rim, z_cc, z_oc)
                + _segment_volume(self.r_outer, self.z_outer, z_oc, self.top))

    def radius_at(self, z):
        """ρ of the profile at height z (tip ≤ z ≤ top; it is single-valued in z)."""
        if not self.tip <= z <= self.top:
            raise ValueError(f"z = {z} outside the drop [{self.tip}, {self.top}]")
        rho_r, zeta_r = self.rim_centre
        if z <= self.cap_contact[1]:
            return math.sqrt(max(self.r_cap ** 2 - (z - self.z_cap) ** 2, 0.0))
        if z >= self.outer_contact[1]:
            return math.sqrt(max(self.r_outer ** 2 - (z - self.z_outer) ** 2, 0.0))
        return rho_r - math.sqrt(max(self.r_rim ** 2 - (z - zeta_r) ** 2, 0.0))

    def distance(self, rho, z):
        """The distance of the meridian point (ρ ≥ 0, z) from the profile (the nearest arc)."""
        rho_r, zeta_r = self.rim_centre
        (po, zo), (pc, zc) = self.outer_contact, self.cap_contact
        arcs = (  # centre, radius, and the arc's ends as angles about its centre
            ((0.0, self.z_outer), self.r_outer, math.atan2(zo - self.z_outer, po), math.pi / 2),
            ((0.0, self.z_cap), self.r_cap, -math.pi / 2, math.atan2(zc - self.z_cap, pc)),
            ((rho_r, zeta_r), self.r_rim, math.atan2(zo - zeta_r, po - rho_r),
             math.atan2(zc - zeta_r, pc - rho_r)),
        )
        best = math.inf
        for (cx, cz), radius, t1, t2 in arcs:
            lo, hi = min(t1, t2), max(t1, t2)
            theta = math.atan2(z - cz, rho - cx)
            if lo <= theta <= hi:
                best = min(best, abs(math.hypot(rho - cx, z - cz) - radius))
            else:
                for t in (t1, t2):
                    best = min(best, math.hypot(rho - cx - radius * math.cos(t),
                                                z - cz - radius * math.sin(t)))
        return best


def _centre(radius, rp, r_rim):
    """Height of the centre of a sphere of `radius` touching the rim circle from outside."""
    rho_r = rp + r_rim
    return -r_rim + math.sqrt(max((radius + r_rim) ** 2 - rho_r ** 2, 0.0))


def _shape(r_outer, r_cap, rp, r_rim):
    return Shape(rp, r_rim, r_outer, _centre(r_outer, rp, r_rim), r_cap, _centre(r_cap, rp, r_rim))


def _outer_for_cap(volume, r_cap, rp, r_rim):
    """The shape with the cap's radius `r_cap` whose volume is `volume` (V increases with R_o)."""
    vol = lambda ro: _shape(ro, r_cap, rp, r_rim).volume()
    lo, hi = rp, 2.0 * (3.0 * volume / (4.0 * math.pi)) ** (1.0 / 3.0) + rp
    if vol(lo) > volume:
        raise ValueError("the drop is too small to fill the pipette's mouth")
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if vol(mid) < volume else (lo, mid)
    return _shape(0.5 * (lo + hi), r_cap, rp, r_rim)


def _suction(shape, gamma):
    return 2.0 * gamma * (1.0 / shape.r_cap - 1.0 / shape.r_outer)


def _critical(gamma, rp, r0, r_rim):
    """The largest static suction and its cap radius: Δp(R_c) along the volume-conserving shapes
    rises steeply from R_c = Rp (the tongue's volume has a √(R_c − Rp) term), peaks just above
    it, then falls; the peak is the saddle-node where the static drop is lost (golden section)."""
    volume = 4.0 * math.pi * r0 ** 3 / 3.0
    f = lambda rc: _suction(_outer_for_cap(volume, rc, rp, r_rim), gamma)
    lo, hi = rp, r0
    k = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = hi - k * (hi - lo), lo + k * (hi - lo)
    fa, fb = f(a), f(b)
    for _ in range(70):
        if fa > fb:
            hi, b, fb = b, a, fa
            a = hi - k * (hi - lo)
            fa = f(a)
        else:
            lo, a, fa = a, b, fb
            b = lo + k * (hi - lo)
            fb = f(b)
    rc = 0.5 * (lo + hi)
    return f(rc), rc


def static_shape(gamma, rp, r0, suction, r_rim=0.0):
    """The static drop under `suction` Δp (0 ≤ Δp < the threshold) at a pipette of inner radius
    `rp` with a rim of radius `r_rim`; the drop's volume is 4πR₀³/3 (units: γ in force/length,
    Δp in force/length², the same length unit throughout). Of the two shapes near the threshold,
    the stable one (the shallower cap, R_c above the critical one)."""
    _positive(gamma=gamma, rp=rp, r0=r0)
    if not (math.isfinite(r_rim) and r_rim >= 0):
        raise ValueError(f"rim radius {r_rim} must be ≥ 0 and finite")
    if not (math.isfinite(suction) and suction >= 0):
        raise ValueError(f"suction {suction} must be ≥ 0 and finite")
    if r0 <= rp:
        raise ValueError(f"the drop (R₀ = {r0}) must be wider than the pipette (Rp = {rp})")
    limit, rc_critical = _critical(gamma, rp, r0, r_rim)
    if suction >= limit:
        raise ValueError(f"suction {suction} at or above the threshold {limit}: no static shape")
    volume = 4.0 * math.pi * r0 ** 3 / 3.0
    lo, hi = rc_critical, 2.0 * r0          # Δp falls from the threshold to < 0 (R_c > R_o)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _suction(_outer_for_cap(volume, mid, rp, r_rim), gamma) > suction else (lo, mid)
    return _outer_for_cap(volume, 0.5 * (lo + hi), rp, r_rim)


def threshold(gamma, rp, r0, r_rim=0.0):
    """The largest suction with a static drop (see `_critical`): 2γ(1/R_c − 1/R_o) at its peak,
    within ~1e-7 (relative, R₀ = 5Rp) of 2γ(1/Rp − 1/R_o) with a hemispherical cap."""
    _positive(gamma=gamma, rp=rp, r0=r0)
    return _critical(gamma, rp, r0, r_rim)[0]


def hemisphere_threshold(gamma, rp, r0, r_rim=0.0):
    """2γ(1/Rp − 1/R_o), R_o the outer sphere of the drop whose cap is a hemisphere."""
    _positive(gamma=gamma, rp=rp, r0=r0)
    return _suction(_outer_for_cap(4.0 * math.pi * r0 ** 3 / 3.0, rp, rp, r_rim), gamma)
