//! Compressible neo-Hookean solid, in the form of FEBio's "neo-Hookean" material (and of the
//! finite-strain unconfined-compression benchmarks of biphasic codes), with the remodelling
//! metric B_p entering as in Holmes–Mow (through M = C B_p):
//!
//!   Ψ = Φs [µ/2 (I1e − 3) − µ ln J + λ/2 (ln J)²],   I1e = tr(C B_p),
//!
//! per unit reference volume of mixture: µ and λ are the solid's (Ψ/Φs) Lamé constants, so the
//! drained mixture's are Φs µ and Φs λ, as for Holmes–Mow with (µ, ν) by (56). Then
//!   S_sc = 2 ∂Ψ/∂C = Φs [µ B_p + (λ ln J − µ) C⁻¹],   P_sc = F S_sc,
//!   Σ = C S_sc = Φs [µ M + (λ ln J − µ) I],            dev Σ = Φs µ dev M.
//!
//! No closed-form ellipticity limit: for λ ≥ 0 the energy is polyconvex wherever ln J < 1 + µ/λ
//! (the volumetric part −µ ln J + λ/2 (ln J)² is convex in J there), compression included.

use crate::error::{Error, Result};
use crate::material::domain::check_phi_s;
use crate::material::dual::{m_dev, m_scale, m_trace, Scalar, M3};
use crate::material::law::{Kinematics, SkeletonLaw, SolidLaw, SolidResponse};
use crate::material::tensor::{add_ik_lj, add_il_kj, add_outer, sym_basis, Tangent};
use nalgebra::Matrix3;

/// Neo-Hookean parameters; energy per unit reference volume of mixture (hence the factor Φs).
/// B_p is kept symmetric positive definite with det 1 by the caller, as for every law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NeoHookean {
    /// Referential solid fraction Φs.
    pub(crate) phi_s: f64,
    /// The solid's shear modulus µ (kPa).
    pub(crate) mu: f64,
    /// The solid's first Lamé constant λ (kPa).
    pub(crate) lambda: f64,
}

impl NeoHookean {
    /// From the solid's Lamé constants. Requires Φs ∈ (0, 1), µ > 0 and a positive bulk modulus
    /// λ + 2µ/3 > 0.
    pub(crate) fn new(phi_s: f64, mu: f64, lambda: f64) -> Result<Self> {
        check_phi_s("neo-Hookean", phi_s)?;
        if !(mu > 0.0 && mu.is_finite()) {
            return Err(Error::Material(format!("neo-Hookean: shear modulus mu = {mu} must be > 0")));
        }
        if !(lambda.is_finite() && lambda + 2.0 * mu / 3.0 > 0.0) {
            return Err(Error::Material(format!(
                "neo-Hookean: lambda = {lambda} must be finite with lambda + 2 mu / 3 > 0 (positive bulk modulus)"
            )));
        }
        Ok(NeoHookean { phi_s, mu, lambda })
    }

    /// From the solid's shear modulus µ and Poisson ratio ν: λ = 2µν/(1 − 2ν), the linearisation
    /// of Ψ/Φs at C = B_p = I (that of Holmes–Mow with the same µ, ν by (56)).
    pub(crate) fn from_mu_nu(mu: f64, nu: f64, phi_s: f64) -> Result<Self> {
        if !(nu > -1.0 && nu < 0.5) {
            return Err(Error::Material(format!("neo-Hookean: Poisson ratio nu = {nu} outside (-1, 0.5)")));
        }
        Self::new(phi_s, mu, 2.0 * mu * nu / (1.0 - 2.0 * nu))
    }

    /// λ ln J − µ: the coefficient of C⁻¹ in S/Φs.
    fn c_inv_coefficient(&self, kin: &Kinematics) -> f64 {
        self.lambda * kin.ln_j - self.mu
    }
}

impl SolidLaw for NeoHookean {
    /// Ψ(F, B_p), with I1e − 3 = tr N, N = (C − I) B_p + (B_p − I): no O(1) cancellation near
    /// C = B_p = I.
    fn energy(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<f64> {
        let i1_m3 = (kin.c_minus_i * bp + (bp - Matrix3::identity())).trace();
        let ln_j = kin.ln_j;
        Ok(self.phi_s * (0.5 * self.mu * i1_m3 - self.mu * ln_j + 0.5 * self.lambda * ln_j * ln_j))
    }

    /// P = F S_sc and S_sc = Φs [µ B_p + (λ ln J − µ) C⁻¹].
    fn stresses(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<(Matrix3<f64>, Matrix3<f64>)> {
        let s = (bp * self.mu + kin.c_inv * self.c_inv_coefficient(kin)) * self.phi_s;
        Ok((kin.f * s, s))
    }

    /// S, P and A = ∂P/∂F. With c = λ ln J − µ, d ln J = F⁻ᵀ:dF and dC⁻¹ = −C⁻¹ dC C⁻¹,
    /// dP = dF S + F dS = Φs [µ dF B_p + λ (F⁻ᵀ:dF) F⁻ᵀ − c F⁻ᵀ dFᵀ F⁻ᵀ] (the dF C⁻¹ terms of
    /// dF S and F dS cancel), i.e.
    /// A = Φs [µ δ_ik B_lj + λ F⁻ᵀ_ij F⁻ᵀ_kl − c F⁻ᵀ_il F⁻ᵀ_kj].
    fn response(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<SolidResponse> {
        let (p, s) = self.stresses(kin, bp)?;
        let f_inv_t = kin.f_inv.transpose();
        let mut a = Tangent::zeros();
        add_ik_lj(&mut a, self.phi_s * self.mu, &Matrix3::identity(), bp);
        add_outer(&mut a, self.phi_s * self.lambda, &f_inv_t, &f_inv_t);
        add_il_kj(&mut a, -self.phi_s * self.c_inv_coefficient(kin), &f_inv_t, &f_inv_t);
        Ok(SolidResponse { p, a, s })
    }
}

/// What the mixture and the remodelling update ask of the law.
impl SkeletonLaw for NeoHookean {
    fn phi_s(&self) -> f64 {
        self.phi_s
    }

    /// Ψ = Φs [µ/2 (tr M − 3) − µ ln J + λ/2 (ln J)²] (module docs).
    fn energy_of<T: Scalar>(&self, m: &M3<T>, ln_j: T) -> T {
        let shear = (m_trace(m) - T::cst(3.0)).scale(0.5 * self.mu) - ln_j.scale(self.mu);
        (shear + (ln_j * ln_j).scale(0.5 * self.lambda)).scale(self.phi_s)
    }

    /// dev Σ = Φs µ dev M: the volumetric part of Σ is isotropic.
    fn mandel_dev<T: Scalar>(&self, m: &M3<T>, _ln_j: T) -> M3<T> {
        m_scale(&m_dev(m), T::cst(self.phi_s * self.mu))
    }

    /// ∂S_sc/∂B_p \[H\] = Φs µ H for the six symmetric unit directions H of [`sym_basis`].
    fn stress_derivative_bp(&self, _kin: &Kinematics, _bp: &Matrix3<f64>) -> Result<[Matrix3<f64>; 6]> {
        Ok(sym_basis().map(|h| h * (self.phi_s * self.mu)))
    }

    /// Φs µ.
    fn shear_modulus(&self) -> f64 {
        self.phi_s * self.mu
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::test_util::{assert_close, kin, rel_err, Rng};
    use nalgebra::Vector3;

    /// A soft aggregate (µ = 3 kPa, ν = 0.45) and Table 1's µ = 20 kPa, ν = 0.2.
    fn laws() -> [NeoHookean; 2] {
        [NeoHookean::from_mu_nu(3.0, 0.45, 0.6).unwrap(), NeoHookean::from_mu_nu(20.0, 0.2, 0.6).unwrap()]
    }

    #[test]
    fn rejects_bad_parameters() {
        let msg = |r: Result<NeoHookean>| match r {
            Err(Error::Material(m)) => m,
            other => panic!("expected a material error, got {other:?}"),
        };
        assert!(msg(NeoHookean::from_mu_nu(3.0, 0.5, 0.6)).contains("nu = 0.5"));
        assert!(msg(NeoHookean::from_mu_nu(0.0, 0.2, 0.6)).contains("mu = 0"));
        assert!(msg(NeoHookean::from_mu_nu(3.0, 0.2, 0.0)).contains("phi_s = 0"));
        assert!(msg(NeoHookean::new(0.6, 3.0, -2.0)).contains("lambda = -2"));
        assert!(msg(NeoHookean::new(0.6, 3.0, f64::INFINITY)).contains("lambda = inf"));
        assert_eq!(NeoHookean::from_mu_nu(3.0, 0.25, 0.6).unwrap().lambda, 3.0);
    }

    /// Uniaxial strain (confined compression and extension) F = diag(1, 1, s), B_p = I, by hand:
    /// J = s, C⁻¹ = diag(1, 1, 1/s²), so S_xx = Φs λ ln s, S_zz = Φs [µ + (λ ln s − µ)/s²],
    /// P_zz = s S_zz, Ψ = Φs [µ/2 (s² − 1) − µ ln s + λ/2 (ln s)²].
    #[test]
    fn uniaxial_strain_closed_form() {
        let bp = Matrix3::identity();
        for nh in laws() {
            let NeoHookean { phi_s, mu, lambda } = nh;
            for s in [0.6, 0.8, 0.95, 1.1, 1.4] {
                let ln = f64::ln(s);
                let (s_xx, s_zz) = (phi_s * lambda * ln, phi_s * (mu + (lambda * ln - mu) / (s * s)));
                let psi = phi_s * (0.5 * mu * (s * s - 1.0) - mu * ln + 0.5 * lambda * ln * ln);
                let f = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, s));
                let r = nh.response(&kin(&f), &bp).unwrap();
                println!("s = {s}: S_zz = {s_zz:.12e} (code {:.12e}), S_xx = {s_xx:.12e}", r.s[(2, 2)]);
                assert_close(r.s[(2, 2)], s_zz, 1e-13);
                assert_close(r.s[(0, 0)], s_xx, 1e-13);
                assert_close(r.s[(1, 1)], s_xx, 1e-13);
                assert_close(r.p[(2, 2)], s * s_zz, 1e-13);
                assert_close(nh.energy(&kin(&f), &bp).unwrap(), psi, 1e-13);
                let off_diagonal = r.s - Matrix3::from_diagonal(&r.s.diagonal());
                assert!(off_diagonal.norm() <= 1e-14 * r.s.norm());
            }
        }
    }

    /// Hydrostatic F = a I, B_p = I, by hand: J = a³, S = Φs [µ + (3λ ln a − µ)/a²] I, Cauchy
    /// σ = J⁻¹ F S Fᵀ = Φs [µ (a² − 1) + 3λ ln a]/a³ I, Ψ = Φs [3µ/2 (a² − 1) − 3µ ln a + 9λ/2 (ln a)²].
    #[test]
    fn hydrostatic_closed_form() {
        let bp = Matrix3::identity();
        for nh in laws() {
            let NeoHookean { phi_s, mu, lambda } = nh;
            for a in [0.8, 0.9, 1.05, 1.2] {
                let ln = f64::ln(a);
                let sigma = phi_s * (mu * (a * a - 1.0) + 3.0 * lambda * ln) / a.powi(3);
                let psi = phi_s * (1.5 * mu * (a * a - 1.0) - 3.0 * mu * ln + 4.5 * lambda * ln * ln);
                let f = Matrix3::identity() * a;
                let k = kin(&f);
                let (p, _) = nh.stresses(&k, &bp).unwrap();
                let cauchy = p * f.transpose() / k.j;
                println!("a = {a}: sigma = {sigma:.12e} (code {:.12e})", cauchy[(0, 0)]);
                assert!(rel_err(&cauchy, &(Matrix3::identity() * sigma)) < 1e-13, "a = {a}");
                assert_close(nh.energy(&k, &bp).unwrap(), psi, 1e-13);
            }
        }
    }

    /// The linearisation at C = B_p = I is isotropic elasticity with Lamé constants Φs (λ, µ),
    /// and Ψ is Φs [λ/2 (tr ε)² + µ ε:ε] at ε = 1e-7 (the cancellation-free I1e − 3).
    #[test]
    fn linearisation_is_isotropic_elasticity() {
        let id = Matrix3::identity();
        for nh in laws() {
            let NeoHookean { phi_s, mu, lambda } = nh;
            let SolidResponse { p, a, .. } = nh.response(&kin(&id), &id).unwrap();
            assert!(p.norm() < 1e-14 * mu);
            let d = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
            let expect = Tangent::from_fn(|r, c| {
                let (i, j, k, l) = (r / 3, r % 3, c / 3, c % 3);
                phi_s * (lambda * d(i, j) * d(k, l) + mu * (d(i, k) * d(j, l) + d(i, l) * d(j, k)))
            });
            let err = rel_err(&a, &expect);
            let eps = Rng::new(3).matrix(1e-7);
            let eps = 0.5 * (eps + eps.transpose());
            let psi_lin = phi_s * (0.5 * lambda * eps.trace().powi(2) + mu * eps.norm_squared());
            let e_psi = (nh.energy(&kin(&(id + eps)), &id).unwrap() - psi_lin).abs() / psi_lin;
            println!("linearisation mu = {mu}, lambda = {lambda}: tangent rel. err {err:e}, energy {e_psi:e}");
            assert!(err < 1e-14 && e_psi < 1e-6);
        }
    }
}
