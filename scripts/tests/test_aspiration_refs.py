"""Theret's aspiration of an incompressible half-space (poroplast_tools.aspiration_refs): the
elliptic integrals and the ring kernel against closed forms, the wall function's exact limits
(penny-shaped crack: Φ → 2; no wall: Φ = π), its monotony, its convergence, Betti's reciprocity
between two different annulus solutions. Pure Python + numpy."""
import math
import unittest

from poroplast_tools import aspiration_refs as ar


class Kernel(unittest.TestCase):
    def test_elliptic_integrals_at_one_half(self):
        # K(½) = Γ(¼)²/(4√π); Legendre's relation at m = ½: 2EK − K² = π/2.
        k = math.gamma(0.25) ** 2 / (4 * math.sqrt(math.pi))
        self.assertAlmostEqual(float(ar.ellipk(0.5)), k, delta=1e-14)
        self.assertAlmostEqual(float(ar.ellipe(0.5)), (math.pi / 2 + k * k) / (2 * k), delta=1e-14)
        self.assertAlmostEqual(float(ar.ellipk(0.0)), math.pi / 2, delta=1e-15)
        self.assertEqual(ar.ellipe(1.0), 1.0)

    def test_ring_kernel_integrates_to_johnsons_disc(self):
        # Johnson §3.4: 2pa at the centre, 4pa/π at the edge, in units (1 − ν²)/E.
        self.assertAlmostEqual(ar.disc_displacement(0.0), 2.0, delta=1e-15)
        self.assertAlmostEqual(ar.disc_displacement(1.0), 4 / math.pi, delta=1e-15)
        for r in (0.3, 1.0, 1.01, 2.0):
            self.assertAlmostEqual(float(ar.disc_displacement_by_kernel(r)), ar.disc_displacement(r),
                                   delta=1e-7, msg=r)
        # Far away the disc is a point force πa²p: (1 − ν²)/(πE) · F/r.
        self.assertAlmostEqual(ar.disc_displacement(100.0) * 100.0, 1.0, delta=1e-4)


def _bore_rule():
    """Nodes and weights on (0, 1), graded towards the rim r = 1 (w₂ has a √ edge there)."""
    import numpy as np
    u, w = np.polynomial.legendre.leggauss(40)
    u, w = 0.5 * (u + 1), 0.5 * w
    return 1 - u ** 3, 3 * u ** 2 * w


class WallFunction(unittest.TestCase):
    def test_limits_and_monotony(self):
        values = [ar.wall_function(eta) for eta in (0.1, 0.5, 2.0, 10.0)]
        self.assertTrue(all(b < a for a, b in zip(values, values[1:])), values)
        self.assertTrue(2.0 < values[-1] < 2.0 + 5e-4, values)    # penny-shaped crack: 2
        self.assertTrue(values[0] < math.pi)                       # a free disc: π
        # The range quoted for Theret's Φ in the literature, 2.0–2.1, for usual walls.
        self.assertTrue(2.0 < ar.wall_function(0.2) < 2.1 < ar.wall_function(0.1))

    def test_a_balanced_pipette(self):
        # Pressing with the suction force and moving: larger L, the same limit 2 as η → ∞.
        self.assertGreater(ar.wall_function(0.1, pipette="balanced"), ar.wall_function(0.1) + 0.4)
        self.assertTrue(2.0 < ar.wall_function(10.0, pipette="balanced") < 2.0 + 1e-3)
        coef, _ = ar.solve_annulus(0.5, 16, pipette="balanced")
        self.assertAlmostEqual(ar.annulus_force(coef, 0.5), -math.pi, delta=1e-12)
        with self.assertRaises(ValueError):
            ar.wall_function(0.5, pipette="free")

    def test_betti_reciprocity(self):
        # Held pipette under unit suction (force F₁ on the annulus, no displacement there) and
        # the same pipette pushed by a unit displacement without suction (w₂ in the bore):
        # Betti's theorem gives F₁ = −∫_bore w₂ dA. Two different solves, one identity.
        eta = 0.3
        coef1, _ = ar.solve_annulus(eta)
        coef2, _ = ar.solve_annulus(eta, suction=0.0, displacement=1.0)
        bore = sum(w * 2 * math.pi * r * ar.annulus_displacement(coef2, eta, r)
                   for r, w in zip(*_bore_rule()))
        self.assertAlmostEqual(ar.annulus_force(coef1, eta) / -bore, 1.0, delta=1e-5)

    def test_converged(self):
        # Third-order convergence in the series length (measured: n = 16, 32, 64, 128 differ by
        # 1.3e-5, 1.6e-6, 2.0e-7 at η = 0.5): n = 16 within 2e-5 of the default n = 32.
        self.assertLess(abs(ar.wall_function(0.5, 16) - ar.wall_function(0.5)), 2e-5)

    def test_aspirated_length_and_bad_input(self):
        # ν = ½, E = 3G: L = Rp Δp Φ/(2πG).
        g, rp, dp, eta = 0.7, 35.0, 0.01, 0.3
        self.assertAlmostEqual(ar.aspirated_length(rp, dp, 3 * g, eta),
                               rp * dp * ar.wall_function(eta) / (2 * math.pi * g), delta=1e-15)
        with self.assertRaises(ValueError):
            ar.wall_function(0.0)
        with self.assertRaises(ValueError):
            ar.aspirated_length(-1.0, dp, 1.0, eta)


if __name__ == "__main__":
    unittest.main()
