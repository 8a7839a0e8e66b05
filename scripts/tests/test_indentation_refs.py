"""The sphere's closed forms (poroplast_tools.indentation_refs): Sneddon's exact sphere tends to
Hertz as a/R → 0 with the hand-derived correction −(a/R)²/10, the G-forms of Hertz are its E-form,
and Hu et al.'s relaxation has the published coefficients and limits. Pure Python."""
import math
import unittest

from poroplast_tools import indentation_refs as ir


class HertzAndSneddon(unittest.TestCase):
    def test_sneddon_tends_to_hertz_with_minus_a2_over_10(self):
        # Series of Sneddon's forms in x = a/R (derived by hand, not from the code):
        # δ/R = x² + x⁴/3 + …, F/(E*R²) = (4/3)x³ + (8/15)x⁵ + …, so at equal depth
        # F_S/F_H = 1 − x²/10 + O(x⁴).
        for x in (0.01, 0.02, 0.05):
            depth, f = ir.sneddon_sphere(x, 1.0, 1.0)
            self.assertAlmostEqual(depth / x ** 2, 1 + x ** 2 / 3, delta=x ** 4)
            rel = f / ir.hertz_force(depth, 1.0, 1.0) - 1
            self.assertAlmostEqual(rel / x ** 2, -0.1, delta=0.2 * x ** 2)

    def test_the_quoted_percentages(self):
        # The gaps quoted for issue 53: −0.025% at a/R = 0.05, −0.10% at 0.1, −0.41% at 0.2 (equal δ).
        for x, pct in ((0.05, -0.025), (0.1, -0.10), (0.2, -0.41)):
            depth, f = ir.sneddon_sphere(100.0 * x, 100.0, 3.0)
            rel = 100 * (f / ir.hertz_force(depth, 100.0, 3.0) - 1)
            self.assertAlmostEqual(rel, pct, delta=0.005 if x < 0.2 else 0.01, msg=(x, rel))
            self.assertAlmostEqual(ir.sneddon_force(depth, 100.0, 3.0), f, delta=1e-12 * f)

    def test_the_shear_modulus_forms(self):
        g, delta, r = 0.7, 1.0, 100.0
        a = ir.hertz_contact_radius(delta, r)
        # E* = E/(1 − ν²) with E = 2G(1 + ν): at ν = ½, E* = 4G and F₀ = (16/3) G δ a.
        for nu in (0.5, 0.3, 0.0):
            e = 2 * g * (1 + nu)
            self.assertAlmostEqual(ir.contact_modulus(g, nu), e / (1 - nu ** 2), delta=1e-14)
        f0 = ir.hertz_force(delta, r, ir.contact_modulus(g, 0.5))
        self.assertAlmostEqual(f0, 16 / 3 * g * delta * a, delta=1e-12 * f0)
        f_inf = ir.hertz_force(delta, r, ir.contact_modulus(g, 0.3))
        self.assertAlmostEqual(f_inf, f0 / (2 * (1 - 0.3)), delta=1e-12 * f0)
        self.assertAlmostEqual(ir.combined_radius(100.0, 50 * a), 100.0 * 500.0 / 600.0, delta=1e-12)

    def test_bad_input(self):
        with self.assertRaises(ValueError):
            ir.sneddon_sphere(1.0, 1.0, 1.0)
        with self.assertRaises(ValueError):
            ir.contact_modulus(1.0, 0.7)
        with self.assertRaises(ValueError):
            ir.relaxation_g(-1.0)


class PoroelasticRelaxation(unittest.TestCase):
    def test_published_coefficients_and_limits(self):
        # Hu, Zhao, Vlassak, Suo (2010), sphere: 0.491, 0.908, 0.509, 1.679; g(0) = 1, g(∞) = 0.
        self.assertEqual(ir.HZVS_SPHERE, (0.491, 0.908, 0.509, 1.679))
        self.assertAlmostEqual(ir.relaxation_g(0.0), 1.0, delta=1e-15)
        self.assertLess(ir.relaxation_g(1e4), 1e-30)
        taus = [10 ** (k / 4) for k in range(-16, 9)]
        values = [ir.relaxation_g(t) for t in taus]
        self.assertTrue(all(b < a for a, b in zip(values, values[1:])))
        # The early decay is the √τ term's: g ≈ 1 − 0.491·0.908 √τ.
        self.assertAlmostEqual((1 - ir.relaxation_g(1e-8)) / 1e-4, 0.491 * 0.908, delta=1e-3)

    def test_force_ends_and_diffusivity(self):
        g, nu, k, delta, r = 0.7, 0.3, 2e-3, 1.0, 100.0
        a = math.sqrt(r * delta)
        f0 = 16 / 3 * g * delta * a
        self.assertAlmostEqual(ir.relaxation_force(0.0, delta, r, g, nu, k), f0, delta=1e-12 * f0)
        self.assertAlmostEqual(ir.relaxation_force(1e12, delta, r, g, nu, k), f0 / (2 * (1 - nu)),
                               delta=1e-12 * f0)
        lam = 2 * g * nu / (1 - 2 * nu)
        d = ir.poroelastic_diffusivity(g, nu, k)
        self.assertAlmostEqual(d, k * (lam + 2 * g), delta=1e-15)
        # Halfway in τ = D t/a² = 1: g(1) = 0.491 e^{−0.908} + 0.509 e^{−1.679}.
        f1 = ir.relaxation_force(a * a / d, delta, r, g, nu, k)
        f_inf = f0 / (2 * (1 - nu))
        self.assertAlmostEqual((f1 - f_inf) / (f0 - f_inf),
                               0.491 * math.exp(-0.908) + 0.509 * math.exp(-1.679), delta=1e-12)


if __name__ == "__main__":
    unittest.main()
