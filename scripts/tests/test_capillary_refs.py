"""The liquid drop at a pipette below its threshold (poroplast_tools.capillary_refs): the shape
meets its defining conditions (tangency, Young–Laplace, volume by an independent quadrature), its
limits (no suction: the sphere through the bore; the threshold: a hemispherical cap; a sharp
rim), and the threshold's first-order departure from Guevorkian et al.'s. Pure Python."""
import math
import unittest

from poroplast_tools import capillary_refs as cr

GAMMA, RP, R0 = 1.0, 35.0, 175.0          # the lab's scale: Rp = 35 µm, R₀ = 175 µm


def polyline_volume(shape, n=20000):
    """π∮ρ² dz along the profile sampled by angle on each arc (trapezoids), tip to top:
    independent of the closed-form segment volumes."""
    rho_r, zeta_r = shape.rim_centre
    (po, zo), (pc, zc) = shape.outer_contact, shape.cap_contact
    arcs = (((0.0, shape.z_cap), shape.r_cap, -math.pi / 2, math.atan2(zc - shape.z_cap, pc)),
            ((rho_r, zeta_r), shape.r_rim, math.atan2(zc - zeta_r, pc - rho_r),
             math.atan2(zo - zeta_r, po - rho_r)),
            ((0.0, shape.z_outer), shape.r_outer, math.atan2(zo - shape.z_outer, po), math.pi / 2))
    total = 0.0
    for (cx, cz), radius, t1, t2 in arcs:
        pts = [(cx + radius * math.cos(t1 + (t2 - t1) * i / n), cz + radius * math.sin(t1 + (t2 - t1) * i / n))
               for i in range(n + 1)]
        total += sum(math.pi * 0.5 * (a[0] ** 2 + b[0] ** 2) * (b[1] - a[1]) for a, b in zip(pts, pts[1:]))
    return total


class StaticShape(unittest.TestCase):
    def test_defining_conditions(self):
        dp_c = cr.threshold(GAMMA, RP, R0, 2.0)
        for r_rim in (0.0, 2.0):
            for frac in (0.2, 0.5, 0.9):
                dp = frac * dp_c
                s = cr.static_shape(GAMMA, RP, R0, dp, r_rim)
                rho_r, zeta_r = s.rim_centre
                for radius, z in ((s.r_outer, s.z_outer), (s.r_cap, s.z_cap)):
                    self.assertAlmostEqual(math.hypot(rho_r, z - zeta_r), radius + r_rim, delta=1e-9)
                self.assertAlmostEqual(1 / s.r_cap - 1 / s.r_outer, dp / (2 * GAMMA), delta=1e-12)
                v0 = 4 * math.pi * R0 ** 3 / 3
                self.assertAlmostEqual(polyline_volume(s) / v0, 1.0, delta=1e-7)
                self.assertAlmostEqual(s.volume() / v0, 1.0, delta=1e-12)
                # The profile passes through its contact points, tip and top; a point off it by d
                # is at distance d.
                for p in (s.outer_contact, s.cap_contact, (0.0, s.tip), (0.0, s.top)):
                    self.assertLess(s.distance(*p), 1e-9)
                self.assertAlmostEqual(s.distance(0.0, s.tip - 0.3), 0.3, delta=1e-9)
                self.assertAlmostEqual(s.radius_at(s.z_outer), s.r_outer, delta=1e-9)

    def test_no_suction_is_the_sphere_through_the_bore(self):
        for r_rim in (0.0, 2.0):
            s = cr.static_shape(GAMMA, RP, R0, 0.0, r_rim)
            self.assertAlmostEqual(s.r_outer, R0, delta=1e-9)
            self.assertAlmostEqual(s.r_cap, R0, delta=1e-9)
        s = cr.static_shape(GAMMA, RP, R0, 0.0)
        self.assertAlmostEqual(s.aspirated_length, R0 - math.sqrt(R0 ** 2 - RP ** 2), delta=1e-9)

    def test_a_sharp_rim_is_the_limit_of_rounded_ones(self):
        dp = 0.5 * cr.guevorkian_threshold(GAMMA, RP, R0)
        s = cr.static_shape(GAMMA, RP, R0, dp, 1e-9 * RP)
        self.assertAlmostEqual(s.aspirated_length, s.r_cap - math.sqrt(s.r_cap ** 2 - RP ** 2), delta=1e-6)
        lengths = [cr.static_shape(GAMMA, RP, R0, dp, r).aspirated_length for r in (0.0, 0.25, 0.5)]
        # L(r) is smooth in r: first differences nearly equal (second difference ≪ first).
        self.assertLess(abs(lengths[2] - 2 * lengths[1] + lengths[0]), 0.05 * abs(lengths[1] - lengths[0]))

    def test_the_threshold_is_a_hemispherical_cap(self):
        for r_rim in (0.0, 2.0):
            dp_c = cr.threshold(GAMMA, RP, R0, r_rim)
            # The largest static suction: not below the hemispherical cap's, and within 1e-6 of it.
            hemi = cr.hemisphere_threshold(GAMMA, RP, R0, r_rim)
            self.assertGreaterEqual(dp_c, hemi * (1 - 1e-12))
            self.assertLess(dp_c / hemi - 1, 1e-6)
            s = cr.static_shape(GAMMA, RP, R0, dp_c * (1 - 1e-9), r_rim)
            self.assertAlmostEqual(s.r_cap / RP, 1.0, delta=1e-5)
            # L − (Rp + r) ~ √(2 Rp (R_c − Rp)).
            self.assertAlmostEqual(s.aspirated_length, RP + r_rim, delta=3e-3 * RP)
            with self.assertRaises(ValueError):
                cr.static_shape(GAMMA, RP, R0, dp_c * (1 + 1e-9), r_rim)
        # The stable branch: below the threshold, the deeper the tongue the larger the suction.
        lengths = [cr.static_shape(GAMMA, RP, R0, f * dp_c).aspirated_length for f in (0.5, 0.9, 0.99)]
        self.assertTrue(lengths[0] < lengths[1] < lengths[2] < RP)

    def test_guevorkians_threshold_to_first_order(self):
        # Sharp rim: at the threshold the drop loses the outer sphere's cap below the mouth,
        # π h²(3R − h)/3 with h = R − √(R² − Rp²), and gains the hemisphere 2πRp³/3; to first
        # order R_o = R₀ − ΔV/(4πR₀²), so Δp_G − Δp_c = 2γ(1/R_o − 1/R₀) ≈ 2γ ΔV/(4πR₀⁴).
        h = R0 - math.sqrt(R0 ** 2 - RP ** 2)
        dv = 2 * math.pi * RP ** 3 / 3 - math.pi * h * h * (3 * R0 - h) / 3
        first_order = 2 * GAMMA * dv / (4 * math.pi * R0 ** 4)
        gap = cr.guevorkian_threshold(GAMMA, RP, R0) - cr.hemisphere_threshold(GAMMA, RP, R0)
        self.assertAlmostEqual(gap / first_order, 1.0, delta=3 * dv / (4 * math.pi * R0 ** 3 / 3))
        self.assertAlmostEqual(cr.guevorkian_threshold(GAMMA, RP, R0), 2 * (1 / 35 - 1 / 175), delta=1e-15)

    def test_bad_input(self):
        with self.assertRaises(ValueError):
            cr.static_shape(GAMMA, RP, RP / 2, 0.0)
        with self.assertRaises(ValueError):
            cr.static_shape(GAMMA, RP, R0, -1.0)
        with self.assertRaises(ValueError):
            cr.static_shape(GAMMA, RP, R0, 0.01, r_rim=-1.0)


if __name__ == "__main__":
    unittest.main()
