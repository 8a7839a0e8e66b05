//! Holmes–Mow solid (36): Ψ = Φs α0 {exp[α1 (I1e − 3) + α2 (I2e − 3) − α3 ln I3e] − 1},
//! I1e = tr(C B_p), I2e = ½[I1e² − tr((C B_p)²)], I3e = det C; S_sc = 2 ∂Ψ/∂C (39) without the
//! penalty, P_sc = F S_sc, and the exact tangent ∂P_sc/∂F.
//!
//! # Strong ellipticity
//!
//! Strong ellipticity of a solid law: the acoustic tensor Q_ik(N) = A_iJkL N_J N_L (A = ∂P/∂F)
//! is positive definite for every unit direction N.
//!
//! Where it is not, the equilibrium equations lose ellipticity: a deformation can localise in
//! a band normal to N at no cost, discrete solutions then depend on the mesh (the finer, the
//! earlier they localise), and Newton stops converging whatever the time step. The pore
//! pressure adds nothing to Q (its term −pJF⁻ᵀ contributes n̂ ⊗ n̂ − n̂ ⊗ n̂ = 0), so the
//! solid's law alone decides, drained or undrained.
//!
//! Holmes–Mow has a closed form. With B_p = I, e = 2 Φs α0 e^f, b = FFᵀ, G = ∂f/∂C and unit
//! m, N, the tangent of `HolmesMow::response` gives
//!   m·Q(N)m = e [α1 + α2 q] + e [α3 (m·F⁻ᵀN)² + 2 (m·FGN)²],
//!   q = I1 − m·bm − |FN|² + (m·FN)² = I1 − m·bm − |P FN|²  (P: projector normal to m).
//! q is at least the smallest eigenvalue of b on the plane normal to m, hence at least the
//! smallest eigenvalue c_min of C; it equals c_c when N = e_a and m = F e_b/|F e_b| for
//! principal axes a ≠ b ≠ c of C, where the last two terms vanish. So for α2 ≥ 0 the smallest
//! acoustic eigenvalue is exactly e (α1 + α2 c_min), reached by a shear in the plane normal to
//! the least-stretched axis: the law is strongly elliptic iff c_min > −α1/α2. With α's from
//! (µ, ν) by (56) that is λ² > (3ν − 1)/ν: 11.8% compression for ν = 0.45 (λ² = 7/9), 29.3%
//! for 0.4, 2.1% for 0.49, whatever µ, and never for ν ≤ 1/3 (α1 ≥ 0). In uniaxial-stress
//! tension the lateral contraction gets there, at axial λ² = −α3/α1 (1.254 for ν = 0.45).
//! For α2 < 0 (ν < 0) only bounds follow: e (α1 + α2 (I1 − c_min)) ≤ min ≤ e (α1 + α2 c_max).
//! With a remodelling metric, Ψ(F, B_p) = Ψ(F B_p^½, I) (det B_p = 1), so Q(N) = Q_e(B_p^½ N):
//! the same criterion holds for the eigenvalues of C_e = B_p^½ C B_p^½ (those of C B_p).
//! A volumetric penalty U(J) adds J² U'' (F⁻ᵀN)⊗(F⁻ᵀN), zero on that shear: it cannot cure it.
//!
//! The sampled minimum over directions of Q's eigenvalues stays as the independent reference,
//! with the closed form's own test version, in `ellipticity_tests`.

#[cfg(test)]
mod ellipticity_tests;

use crate::error::{Error, Result};
use crate::material::domain::{check_phi_s, domain_error};
use crate::material::dual::{m_add, m_dev, m_mul, m_scale, m_trace, m_trace_mul, Scalar, M3};
use crate::material::law::{EllipticityLimit, Kinematics, SkeletonLaw, SolidLaw, SolidResponse};
use crate::material::tensor::{add_ik_lj, add_il_kj, add_outer, sym_basis, Tangent};
use nalgebra::Matrix3;

/// Holmes–Mow parameters; energy per unit reference volume of mixture (hence the factor Φs).
/// Every method takes the remodelling metric B_p, which the caller keeps symmetric positive
/// definite with det 1 (not checked here: it is a qp-state variable, checked where updated).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct HolmesMow {
    /// Referential solid fraction Φs.
    pub(crate) phi_s: f64,
    /// α0 (stress units).
    pub(crate) alpha0: f64,
    pub(crate) alpha1: f64,
    pub(crate) alpha2: f64,
    pub(crate) alpha3: f64,
}

/// What stress, energy and tangent share: the exponent f = α1 (I1e − 3) + α2 (I2e − 3) − α3 ln I3e,
/// exp f, and G = ∂f/∂C = (α1 + α2 I1e) B_p − α2 B_p C B_p − α3 C⁻¹ (so S = 2 Φs α0 e^f G).
struct Core {
    #[cfg_attr(not(test), allow(dead_code))] // Ψ only
    exponent: f64,
    exp_f: f64,
    g: Matrix3<f64>,
}

impl HolmesMow {
    /// Direct α's. Requires Φs ∈ (0, 1), α0 > 0, α3 = α1 + 2 α2 (stress-free reference, to a
    /// relative 1e-6 so printed tables pass) and a positive-definite linearisation: µ/Φs =
    /// 2 α0 (α3 − α2) > 0 and bulk modulus/Φs = 4 α0 (α3 + 2 α2)/3 > 0.
    pub(crate) fn new(phi_s: f64, alpha0: f64, alpha1: f64, alpha2: f64, alpha3: f64) -> Result<Self> {
        check_phi_s("Holmes–Mow", phi_s)?;
        let all = [alpha0, alpha1, alpha2, alpha3];
        if !all.iter().all(|a| a.is_finite()) {
            return Err(Error::Material(format!("Holmes–Mow: non-finite alpha (alpha0..3 = {all:?})")));
        }
        if alpha0 <= 0.0 {
            return Err(Error::Material(format!("Holmes–Mow: alpha0 = {alpha0} must be > 0")));
        }
        let mismatch = alpha1 + 2.0 * alpha2 - alpha3;
        if mismatch.abs() > 1e-6 * (alpha1.abs() + 2.0 * alpha2.abs() + alpha3.abs()) {
            return Err(Error::Material(format!(
                "Holmes–Mow: alpha3 = {alpha3} must equal alpha1 + 2 alpha2 = {} \
                 (stress-free reference)",
                alpha1 + 2.0 * alpha2
            )));
        }
        if alpha3 <= alpha2 {
            return Err(Error::Material(format!(
                "Holmes–Mow: alpha3 = {alpha3} must exceed alpha2 = {alpha2} (positive shear modulus)"
            )));
        }
        if alpha3 + 2.0 * alpha2 <= 0.0 {
            return Err(Error::Material(format!(
                "Holmes–Mow: alpha3 + 2 alpha2 = {} must be > 0 (positive bulk modulus)",
                alpha3 + 2.0 * alpha2
            )));
        }
        Ok(HolmesMow { phi_s, alpha0, alpha1, alpha2, alpha3 })
    }

    /// α's from the shear modulus µ and Poisson ratio ν of the solid (56), α3 = 1:
    /// α0 = (1−ν) µ / (2 (1−2ν)), α1 = (1−3ν)/(1−ν), α2 = ν/(1−ν). The linearisation of Ψ/Φs at
    /// C = B_p = I then has Lamé constants µ and 2µν/(1−2ν).
    pub(crate) fn from_mu_nu(mu: f64, nu: f64, phi_s: f64) -> Result<Self> {
        if !(mu > 0.0 && mu.is_finite()) {
            return Err(Error::Material(format!("Holmes–Mow: shear modulus mu = {mu} must be > 0")));
        }
        if !(nu > -1.0 && nu < 0.5) {
            return Err(Error::Material(format!("Holmes–Mow: Poisson ratio nu = {nu} outside (-1, 0.5)")));
        }
        let alpha3 = 1.0;
        Self::new(
            phi_s,
            (1.0 - nu) * mu / (2.0 * (1.0 - 2.0 * nu) * alpha3),
            alpha3 * (1.0 - 3.0 * nu) / (1.0 - nu),
            alpha3 * nu / (1.0 - nu),
            alpha3,
        )
    }

    /// (tr M, f) with f = α1 (tr M − 3) + α2 (I2(M) − 3) − 2 α3 ln J: the exponent as a function
    /// of M = C B_p, generic (the remodelling update's; [`Self::core`] is the f64 one without the
    /// cancellation near M = I).
    fn exponent_of<T: Scalar>(&self, m: &M3<T>, ln_j: T) -> (T, T) {
        let (a1, a2, a3) = (self.alpha1, self.alpha2, self.alpha3);
        let tr = m_trace(m);
        let tr2 = m_trace_mul(m, m);
        let i2 = (tr * tr - tr2).scale(0.5);
        (tr, (tr - T::cst(3.0)).scale(a1) + (i2 - T::cst(3.0)).scale(a2) - ln_j.scale(2.0 * a3))
    }

    fn core(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<Core> {
        let (a1, a2, a3) = (self.alpha1, self.alpha2, self.alpha3);
        let id = Matrix3::identity();
        // N = C B_p − I from C − I and B_p − I, so f has no O(1) cancellation near C = B_p = I:
        // I1e − 3 = tr N, I2e − 3 = 2 tr N + ½[(tr N)² − tr N²].
        let n = kin.c_minus_i * bp + (bp - id);
        let tr_n = n.trace();
        let i1_m3 = tr_n;
        let i2_m3 = 2.0 * tr_n + 0.5 * (tr_n * tr_n - (n * n).trace());
        // ln I3e = 2 ln J.
        let exponent = a1 * i1_m3 + a2 * i2_m3 - 2.0 * a3 * kin.ln_j;
        let exp_f = exponent.exp();
        if !exp_f.is_finite() {
            return Err(domain_error(kin.j, format!("Holmes–Mow: exp of exponent {exponent} is not finite")));
        }
        let g = bp * (a1 + a2 * (3.0 + i1_m3)) - bp * kin.c * bp * a2 - kin.c_inv * a3;
        Ok(Core { exponent, exp_f, g })
    }
}

impl SolidLaw for HolmesMow {
    /// Ψ(F, B_p). Domain error if exp overflows.
    fn energy(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<f64> {
        let core = self.core(kin, bp)?;
        // exp_m1 keeps Ψ = O(strain²) accurate near the reference state.
        Ok(self.phi_s * self.alpha0 * core.exponent.exp_m1())
    }

    /// P = F S_sc and S_sc = 2 ∂Ψ/∂C of the solid (no penalty).
    fn stresses(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<(Matrix3<f64>, Matrix3<f64>)> {
        let core = self.core(kin, bp)?;
        let s = core.g * (2.0 * self.phi_s * self.alpha0 * core.exp_f);
        Ok((kin.f * s, s))
    }

    /// S, P and A = ∂P/∂F (index map of [`super::tensor::idx`]).
    ///
    /// With e = 2 Φs α0 e^f, S = e G and dS = e (2 FG:dF) G + e dG, where
    /// dG = α2 (2 F B_p:dF) B_p − α2 B_p dC B_p + α3 C⁻¹ dC C⁻¹ and dC = dFᵀF + FᵀdF. Then
    /// dP = dF S + F dS, i.e.
    /// A = δ_ik (S + e α3 C⁻¹)_lj + 2e (FG)_ij (FG)_kl + 2e α2 (FB)_ij (FB)_kl
    ///     − e α2 (FB)_il (FB)_kj − e α2 (F B Fᵀ)_ik B_lj + e α3 F⁻ᵀ_il F⁻ᵀ_kj,   B = B_p.
    fn response(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<SolidResponse> {
        let core = self.core(kin, bp)?;
        let (a2, a3) = (self.alpha2, self.alpha3);
        let e = 2.0 * self.phi_s * self.alpha0 * core.exp_f;
        let s = core.g * e;
        let f = &kin.f;
        let fg = f * core.g;
        let fb = f * bp;
        let f_inv_t = kin.f_inv.transpose();

        let mut a = Tangent::zeros();
        add_ik_lj(&mut a, 1.0, &Matrix3::identity(), &(s + kin.c_inv * (e * a3)));
        add_outer(&mut a, 2.0 * e, &fg, &fg);
        add_outer(&mut a, 2.0 * e * a2, &fb, &fb);
        add_il_kj(&mut a, -e * a2, &fb, &fb);
        add_ik_lj(&mut a, -e * a2, &(fb * f.transpose()), bp);
        add_il_kj(&mut a, e * a3, &f_inv_t, &f_inv_t);
        Ok(SolidResponse { p: f * s, a, s })
    }
}

/// −α1/α2 when α1 < 0 (then α2 = (α3 − α1)/2 > 0): the Holmes–Mow solid is strongly elliptic
/// exactly where every eigenvalue of the elastic C_e exceeds it (module docs, strong ellipticity). None when
/// α1 ≥ 0: no small stretch makes it lose ellipticity (with α2 ≥ 0 nothing does; with α2 < 0,
/// ν < 0 by (56), large stretches can: the module's bounds).
pub(crate) fn critical_stretch_squared(law: &HolmesMow) -> Option<f64> {
    (law.alpha1 < 0.0 && law.alpha2 > 0.0).then(|| -law.alpha1 / law.alpha2)
}

/// The stretch λ of isochoric uniaxial compression F = diag(λ^−½, λ^−½, λ), B_p = I, below
/// which the law is not strongly elliptic, if that happens for some λ in [`lambda_min`, 1].
/// Along the path C has eigenvalues λ² < 1 < 1/λ, so for α2 ≥ 0 it is √(−α1/α2) exactly. For
/// α2 < 0 the lower bound α1 + 2 α2/λ (module docs, strong ellipticity) proves ellipticity for
/// λ > 2|α2|/α1, which is below ½ for every admissible law (α1 = α3 + 2|α2| > 4|α2|); an error
/// if `lambda_min` is not above it (the closed form does not decide there).
pub(crate) fn isochoric_compression_limit(law: &HolmesMow, lambda_min: f64) -> Result<Option<f64>> {
    if law.alpha2 >= 0.0 {
        return Ok(critical_stretch_squared(law).map(f64::sqrt).filter(|&lam| lam >= lambda_min));
    }
    let proven_to = -2.0 * law.alpha2 / law.alpha1;
    if lambda_min > proven_to {
        Ok(None)
    } else {
        Err(Error::Material(format!(
            "Holmes–Mow with alpha2 = {} < 0: strong ellipticity in isochoric compression below \
             lambda = {proven_to:.4} is not decided by the closed form",
            law.alpha2
        )))
    }
}

/// The axial stretch of uniaxial-stress tension (F = diag(l, l, λ), B_p = I, P_xx = P_yy = 0)
/// beyond which the law is not strongly elliptic: √(−α3/α1) when α1 < 0, else None. Why: the
/// zero lateral stress S_xx = e G_xx = 0 reads α1 + α2 (l² + λ²) − α3/l² = 0, whose root l²
/// falls from 1 as λ grows; l² is then the smallest eigenvalue of C, and putting l² = −α1/α2
/// into that equation gives λ² = −α3/α1 (> 1 since α1 + α3 = 2 (α3 − α2) > 0).
pub(crate) fn uniaxial_stress_tension_limit(law: &HolmesMow) -> Option<f64> {
    critical_stretch_squared(law).map(|_| (-law.alpha3 / law.alpha1).sqrt())
}

/// What the mixture and the remodelling update ask of the law.
impl SkeletonLaw for HolmesMow {
    fn phi_s(&self) -> f64 {
        self.phi_s
    }

    /// Deviatoric Mandel stress dev Σ, Σ = C S_sc, as a function of M = C B_p and ln J (generic,
    /// for the remodelling update and its derivatives). With S = e G:
    /// Σ = e [(α1 + α2 tr M) M − α2 M² − α3 I], so dev Σ = e dev[(α1 + α2 tr M) M − α2 M²],
    /// e = 2 Φs α0 exp[α1 (tr M − 3) + α2 (I2(M) − 3) − 2 α3 ln J]. (The compaction penalty adds
    /// J U'(J) I to Σ: no deviator.)
    fn mandel_dev<T: Scalar>(&self, m: &M3<T>, ln_j: T) -> M3<T> {
        let (a1, a2) = (self.alpha1, self.alpha2);
        let (tr, f) = self.exponent_of(m, ln_j);
        let e = f.exp().scale(2.0 * self.phi_s * self.alpha0);
        let m2 = m_mul(m, m);
        let inner = m_add(&m_scale(m, T::cst(a1) + tr.scale(a2)), &m_scale(&m2, T::cst(-a2)));
        m_scale(&m_dev(&inner), e)
    }

    /// Ψ = Φs α0 (e^f − 1) (module docs).
    fn energy_of<T: Scalar>(&self, m: &M3<T>, ln_j: T) -> T {
        (self.exponent_of(m, ln_j).1.exp() - T::cst(1.0)).scale(self.phi_s * self.alpha0)
    }

    /// ∂S_sc/∂B_p \[H\] for the six symmetric unit directions H of [`sym_basis`]:
    /// with S = e G, ∂f\[H\] = (α1 + α2 I1e) tr(C H) − α2 tr(C B C H) and
    /// ∂G\[H\] = α2 tr(C H) B + (α1 + α2 I1e) H − α2 (H C B + B C H), ∂S\[H\] = e (∂f\[H\] G + ∂G\[H\]).
    fn stress_derivative_bp(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<[Matrix3<f64>; 6]> {
        let core = self.core(kin, bp)?;
        let (a1, a2) = (self.alpha1, self.alpha2);
        let e = 2.0 * self.phi_s * self.alpha0 * core.exp_f;
        let c = &kin.c;
        let i1 = (c * bp).trace();
        let cbc = c * bp * c;
        let cb = c * bp;
        Ok(sym_basis().map(|h| {
            let tr_ch = (c * h).trace();
            let df = (a1 + a2 * i1) * tr_ch - a2 * (cbc * h).trace();
            let hcb = h * cb;
            let dg = bp * (a2 * tr_ch) + h * (a1 + a2 * i1) - (hcb + hcb.transpose()) * a2;
            (core.g * df + dg) * e
        }))
    }

    /// Φs 2 α0 (α3 − α2): Φs µ by (56).
    fn shear_modulus(&self) -> f64 {
        self.phi_s * 2.0 * self.alpha0 * (self.alpha3 - self.alpha2)
    }

    /// The closed form (module docs, strong ellipticity): for α1 < 0 the law loses strong ellipticity where an
    /// elastic principal stretch falls below √(−α1/α2).
    fn ellipticity_limit(&self, lambda_min: f64) -> Result<Option<EllipticityLimit>> {
        let Some(stretch) = isochoric_compression_limit(self, lambda_min)? else { return Ok(None) };
        Ok(Some(EllipticityLimit {
            law: "Holmes–Mow solid",
            cause: format!("alpha1 = {:.3} < 0", self.alpha1),
            stretch,
            uniaxial_tension: uniaxial_stress_tension_limit(self),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::tensor::idx;
    use crate::material::test_util::{assert_close, kin, rel_err, Rng};

    /// Table 1 (µ = 20 kPa, ν = 0.2) and the soft Forgacs case (µ = 3 kPa, ν = 0.45, α1 < 0).
    fn laws() -> [HolmesMow; 2] {
        [HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap(), HolmesMow::from_mu_nu(3.0, 0.45, 0.6).unwrap()]
    }

    #[test]
    fn alphas_from_mu_nu() {
        let hm = HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap();
        assert_close(hm.alpha0, 40.0 / 3.0, 1e-15);
        assert_close(hm.alpha1, 0.5, 1e-15);
        assert_close(hm.alpha2, 0.25, 1e-15);
        assert_eq!(hm.alpha3, 1.0);
    }

    #[test]
    fn rejects_bad_parameters() {
        let msg = |r: Result<HolmesMow>| match r {
            Err(Error::Material(m)) => m,
            other => panic!("expected a material error, got {other:?}"),
        };
        assert!(msg(HolmesMow::from_mu_nu(20.0, 0.5, 0.6)).contains("nu = 0.5"));
        assert!(msg(HolmesMow::from_mu_nu(20.0, -1.0, 0.6)).contains("nu = -1"));
        assert!(msg(HolmesMow::from_mu_nu(0.0, 0.2, 0.6)).contains("mu = 0"));
        assert!(msg(HolmesMow::from_mu_nu(20.0, 0.2, 1.0)).contains("phi_s = 1"));
        assert!(msg(HolmesMow::from_mu_nu(20.0, f64::NAN, 0.6)).contains("nu = NaN"));
        assert!(msg(HolmesMow::new(0.6, -1.0, 0.5, 0.25, 1.0)).contains("alpha0 = -1"));
        assert!(msg(HolmesMow::new(0.6, 1.0, 0.5, 0.3, 1.0)).contains("alpha3 = 1"));
        assert!(msg(HolmesMow::new(0.6, 1.0, -2.0, 1.0, 0.0)).contains("alpha2 = 1"));
        assert!(msg(HolmesMow::new(0.6, 1.0, 3.0, -1.0, 1.0)).contains("alpha3 + 2 alpha2 = -1"));
        // Table 1 of the paper: α0 = 0.125 kPa, α1 = 0.78, α2 = 0.11, α3 = 1.
        assert!(HolmesMow::new(0.6, 0.125, 0.78, 0.11, 1.0).is_ok());
    }

    /// The law's own domain error: an exponent whose exp overflows (an F with J <= 0 or not
    /// finite is refused by `Kinematics::new` already).
    #[test]
    fn domain_errors() {
        let hm = laws()[0];
        let (bp, k) = (Matrix3::identity(), kin(&(Matrix3::identity() * 100.0)));
        assert!(matches!(hm.energy(&k, &bp), Err(Error::Domain { .. })));
        assert!(matches!(hm.stresses(&k, &bp), Err(Error::Domain { .. })));
        assert!(matches!(hm.response(&k, &bp), Err(Error::Domain { .. })));
    }

    #[test]
    fn reference_state_is_stress_free_and_energy_accurate_at_small_strain() {
        let hm = laws()[0];
        let id = Matrix3::identity();
        assert_eq!(hm.energy(&kin(&id), &id).unwrap(), 0.0);
        assert!(hm.stresses(&kin(&id), &id).unwrap().1.norm() < 1e-15);
        // Ψ ≈ Φs [λ/2 (tr ε)² + µ ε:ε] at ε = 1e-7: tests the cancellation-free exponent.
        let eps = Rng::new(3).matrix(1e-7);
        let eps = 0.5 * (eps + eps.transpose());
        let (mu, lambda) = (20.0, 2.0 * 20.0 * 0.2 / 0.6);
        let psi_lin = 0.6 * (0.5 * lambda * eps.trace().powi(2) + mu * eps.norm_squared());
        let psi = hm.energy(&kin(&(id + eps)), &id).unwrap();
        println!("small-strain energy: {psi:e} vs linear {psi_lin:e}");
        assert!((psi - psi_lin).abs() < 1e-6 * psi_lin);
    }

    #[test]
    fn second_pk_matches_energy_derivative_in_c() {
        // Ψ as a function of C: F = Lᵀ with C = L Lᵀ (Cholesky) has FᵀF = C.
        let mut rng = Rng::new(2);
        let mut worst: f64 = 0.0;
        for hm in laws() {
            for j in [0.7, 1.0, 1.4] {
                let (f, bp) = (rng.deformation(j), rng.remodelling_metric());
                let c = f.transpose() * f;
                let psi = |c: &Matrix3<f64>| {
                    let ft = c.cholesky().unwrap().l().transpose();
                    hm.energy(&kin(&ft), &bp).unwrap()
                };
                let h = 1e-5 * c.norm();
                let s_fd = Matrix3::from_fn(|a, b| {
                    let mut dc = Matrix3::zeros();
                    dc[(a, b)] += 0.5 * h;
                    dc[(b, a)] += 0.5 * h;
                    2.0 * (psi(&(c + dc)) - psi(&(c - dc))) / (2.0 * h)
                });
                let err = rel_err(&hm.stresses(&kin(&f), &bp).unwrap().1, &s_fd);
                assert!(err < 1e-6, "J = {j}: rel. error {err:e}");
                worst = worst.max(err);
            }
        }
        println!("S vs 2 dPsi/dC: worst relative error {worst:e}");
    }

    #[test]
    fn linearisation_is_isotropic_elasticity() {
        let id = Matrix3::identity();
        for (mu, nu) in [(20.0, 0.2), (3.0, 0.45), (1.0, -0.5)] {
            let phi_s = 0.6;
            let hm = HolmesMow::from_mu_nu(mu, nu, phi_s).unwrap();
            let SolidResponse { p, a, .. } = hm.response(&kin(&id), &id).unwrap();
            assert!(p.norm() < 1e-14 * mu);
            let lambda = 2.0 * mu * nu / (1.0 - 2.0 * nu);
            let d = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
            let expect = Tangent::from_fn(|r, c| {
                let (i, j, k, l) = (r / 3, r % 3, c / 3, c % 3);
                phi_s * (lambda * d(i, j) * d(k, l) + mu * (d(i, k) * d(j, l) + d(i, l) * d(j, k)))
            });
            let err = rel_err(&a, &expect);
            println!("linearisation mu = {mu}, nu = {nu}: rel. error {err:e}");
            assert!(err < 1e-14);
        }
    }

    #[test]
    fn confined_compression_closed_form() {
        // F = diag(1, 1, λ), B_p = I: C = diag(1, 1, λ²), I1 = 2 + λ², I2 = 1 + 2λ², I3 = λ²,
        // f = (α1 + 2α2)(λ² − 1) − 2 α3 ln λ,
        // S_zz = 2 Φs α0 e^f (α1 + 2α2 − α3/λ²), S_xx = S_yy = 2 Φs α0 e^f (α1 + α2 (1 + λ²) − α3),
        // P_zz = λ S_zz, P_xx = S_xx, Ψ = Φs α0 (e^f − 1).
        let bp = Matrix3::identity();
        for hm in laws().into_iter().chain([HolmesMow::new(0.6, 0.125, 0.78, 0.11, 1.0).unwrap()]) {
            let HolmesMow { phi_s, alpha0: a0, alpha1: a1, alpha2: a2, alpha3: a3 } = hm;
            for lam in [0.75, 0.9, 1.1, 1.3] {
                let f_exp = (a1 + 2.0 * a2) * (lam * lam - 1.0) - 2.0 * a3 * f64::ln(lam);
                let pre = 2.0 * phi_s * a0 * f_exp.exp();
                let s_zz = pre * (a1 + 2.0 * a2 - a3 / (lam * lam));
                let s_xx = pre * (a1 + a2 * (1.0 + lam * lam) - a3);
                let f = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, lam));
                let s = hm.stresses(&kin(&f), &bp).unwrap().1;
                let p = hm.response(&kin(&f), &bp).unwrap().p;
                println!("lambda = {lam}: S_zz = {s_zz:.12e} (code {:.12e}), S_xx = {s_xx:.12e}", s[(2, 2)]);
                assert_close(s[(2, 2)], s_zz, 1e-12);
                assert_close(s[(0, 0)], s_xx, 1e-12);
                assert_close(s[(1, 1)], s_xx, 1e-12);
                assert_close(p[(2, 2)], lam * s_zz, 1e-12);
                assert_close(hm.energy(&kin(&f), &bp).unwrap(), phi_s * a0 * f_exp.exp_m1(), 1e-12);
                let off_diagonal = s - Matrix3::from_diagonal(&s.diagonal());
                assert!(off_diagonal.norm() <= 1e-14 * s.norm());
            }
        }
    }

    #[test]
    fn frame_invariance() {
        let mut rng = Rng::new(5);
        let hm = laws()[1];
        for j in [0.75, 1.3] {
            let (f, bp, q) = (rng.deformation(j), rng.remodelling_metric(), rng.rotation());
            let SolidResponse { p, a, .. } = hm.response(&kin(&f), &bp).unwrap();
            let SolidResponse { p: pq, a: aq, .. } = hm.response(&kin(&(q * f)), &bp).unwrap();
            assert!(rel_err(&pq, &(q * p)) < 1e-13);
            assert!(
                rel_err(&hm.stresses(&kin(&(q * f)), &bp).unwrap().1, &hm.stresses(&kin(&f), &bp).unwrap().1) < 1e-13
            );
            // A(QF)_ijkl = Q_ia Q_kb A(F)_ajbl.
            let rotated = Tangent::from_fn(|r, c| {
                let (i, j, k, l) = (r / 3, r % 3, c / 3, c % 3);
                let mut sum = 0.0;
                for a_ in 0..3 {
                    for b in 0..3 {
                        sum += q[(i, a_)] * q[(k, b)] * a[(idx(a_, j), idx(b, l))];
                    }
                }
                sum
            });
            assert!(rel_err(&aq, &rotated) < 1e-13);
        }
    }

    #[test]
    fn newton_uniaxial_stress_converges_quadratically() {
        // F = diag(λ, λ, λ_a), B_p = I: find the lateral stretch λ with P_xx = 0 (P_yy = 0 by
        // symmetry); dP_xx/dλ = A[xx, xx] + A[xx, yy].
        let bp = Matrix3::identity();
        for hm in laws() {
            for lam_a in [0.7, 1.3] {
                let mut lam: f64 = 1.0;
                let mut iterates = vec![];
                for _ in 0..20 {
                    let f = Matrix3::from_diagonal(&nalgebra::Vector3::new(lam, lam, lam_a));
                    let SolidResponse { p, a, .. } = hm.response(&kin(&f), &bp).unwrap();
                    iterates.push((lam, p[(0, 0)]));
                    if p[(0, 0)].abs() < 1e-13 * hm.alpha0 {
                        break;
                    }
                    lam -= p[(0, 0)] / (a[(idx(0, 0), idx(0, 0))] + a[(idx(0, 0), idx(1, 1))]);
                }
                let lam_star = iterates.last().unwrap().0;
                println!(
                    "nu = {:.3}, lambda_a = {lam_a}: lateral stretch {lam_star:.15}",
                    hm.alpha2 / (1.0 + hm.alpha2)
                );
                let errs: Vec<f64> = iterates.iter().map(|(l, _)| (l - lam_star).abs()).collect();
                for (k, ((l, r), e)) in iterates.iter().zip(&errs).enumerate() {
                    println!("  it {k}: lambda = {l:.15}, |P_xx| = {:.3e}, |error| = {e:.3e}", r.abs());
                }
                assert!(iterates.len() <= 7, "too many iterations: {}", iterates.len());
                for w in errs.windows(2) {
                    if w[0] > 1e-7 {
                        let ratio = w[1] / (w[0] * w[0]);
                        println!("  e_(k+1)/e_k^2 = {ratio:.3}");
                        assert!(ratio < 10.0, "not quadratic: {ratio}");
                    }
                }
            }
        }
    }
}
