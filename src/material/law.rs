//! The interface of a solid law: the kinematics every law reads ([`Kinematics`]), its point
//! evaluation in f64 ([`SolidLaw`]: energy, stresses, tangent), what the mixture and the
//! remodelling update need of a skeleton law besides ([`SkeletonLaw`]: Φs, the Mandel deviator
//! generic over the scalar so that duals differentiate it, ∂S/∂B_p, an optional ellipticity
//! limit).
//!
//! The laws themselves are one per file in [`super::laws`].

use super::domain::domain_error;
use super::dual::{Scalar, M3};
use super::tensor::{cof, Tangent};
use crate::error::Result;
use nalgebra::Matrix3;
use std::fmt::Debug;

/// Kinematic quantities shared by all laws at one point, computed once per F.
#[derive(Clone, Debug)]
pub(crate) struct Kinematics {
    /// Deformation gradient F.
    pub(crate) f: Matrix3<f64>,
    /// J = det F.
    pub(crate) j: f64,
    /// ln J, from J − 1 without cancellation (J − 1 is summed from the invariants of F − I).
    pub(crate) ln_j: f64,
    /// F⁻¹.
    pub(crate) f_inv: Matrix3<f64>,
    /// cof F = J F⁻ᵀ (from the entries of F, see [`cof`]).
    pub(crate) cof_f: Matrix3<f64>,
    /// C = FᵀF.
    pub(crate) c: Matrix3<f64>,
    /// C − I = H + Hᵀ + HᵀH with H = F − I (= 2E, no cancellation near F = I).
    pub(crate) c_minus_i: Matrix3<f64>,
    /// C⁻¹ = F⁻¹F⁻ᵀ.
    pub(crate) c_inv: Matrix3<f64>,
}

impl Kinematics {
    /// Domain error when F is not finite or J <= 0.
    pub(crate) fn new(f: &Matrix3<f64>) -> Result<Self> {
        let h = f - Matrix3::identity();
        let tr = h.trace();
        // det(I + H) − 1 = I1(H) + I2(H) + I3(H): exact expansion, small when H is small.
        let j_minus_1 = tr + 0.5 * (tr * tr - (h * h).trace()) + h.determinant();
        let j = 1.0 + j_minus_1;
        if !j.is_finite() || !f.iter().all(|x| x.is_finite()) {
            return Err(domain_error(j, "non-finite deformation gradient"));
        }
        if j <= 0.0 {
            return Err(domain_error(j, "J <= 0 (inverted element)"));
        }
        // F⁻¹ = adj(F)/J = (cof F)ᵀ/J.
        let cof_f = cof(f);
        let f_inv = cof_f.transpose() * (1.0 / j);
        Ok(Kinematics {
            f: *f,
            j,
            ln_j: j_minus_1.ln_1p(),
            f_inv,
            cof_f,
            c: f.transpose() * f,
            c_minus_i: h + h.transpose() + h.transpose() * h,
            c_inv: f_inv * f_inv.transpose(),
        })
    }
}

/// Solid response at one point: first and second Piola–Kirchhoff stresses and ∂P/∂F.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SolidResponse {
    /// First Piola–Kirchhoff stress P_sc = F S_sc.
    pub(crate) p: Matrix3<f64>,
    /// Tangent ∂P_sc/∂F, index map of [`super::tensor::idx`].
    pub(crate) a: Tangent,
    /// Second Piola–Kirchhoff stress S_sc.
    pub(crate) s: Matrix3<f64>,
}

/// A hyperelastic solid law at one point, evaluated at the kinematics of F (computed once per
/// point by the caller, [`Kinematics::new`]) and the remodelling metric B_p (ignored by laws
/// without one): the energy Ψ, the stresses (P, S) and the tangent ∂P/∂F.
pub(crate) trait SolidLaw {
    /// Ψ per unit reference volume of mixture: the tests' reference, of which the stresses and
    /// the tangent are checked to be the derivatives.
    #[cfg_attr(not(test), allow(dead_code))]
    fn energy(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<f64>;

    /// (P, S) without the tangent (residuals and output fields need no more; the 9×9 tangent is
    /// most of a point's cost): the same numbers as [`response`](Self::response).
    fn stresses(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<(Matrix3<f64>, Matrix3<f64>)>;

    /// P, S and A = ∂P/∂F.
    fn response(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<SolidResponse>;
}

/// A law of the mixture's solid skeleton, with everything [`crate::physics::biphasic::Biphasic`]
/// and the remodelling update ([`super::remodelling`]) ask of it: they are generic over this
/// trait and name no law. The energy is per unit reference volume of mixture, a function of
/// C B_p and J (so the elastic part of F B_p^½ alone, det B_p = 1).
///
/// A law is one file in [`super::laws`]: it implements [`SolidLaw`] (Ψ, S, P and ∂P/∂F in closed
/// form: the hot path) and this trait.
pub(crate) trait SkeletonLaw: SolidLaw + Clone + Debug + 'static {
    /// The referential solid fraction Φs the energy is scaled by.
    fn phi_s(&self) -> f64;

    /// Ψ as a function of M = C B_p and ln J, generic over the scalar: the law's definition. Its
    /// closed forms are checked against it (the tests' `check_skeleton_law`): its value is
    /// [`SolidLaw::energy`], and [`Self::mandel_dev`] is dev(2 C ∂Ψ/∂M B_p) by duals.
    #[cfg_attr(not(test), allow(dead_code))]
    fn energy_of<T: Scalar>(&self, m: &M3<T>, ln_j: T) -> T;

    /// dev Σ of the Mandel stress Σ = C S as a function of M = C B_p and ln J, generic over the
    /// scalar so that the remodelling update differentiates it with dual numbers (its Jacobian
    /// and its consistent tangent); f64 gives the value.
    fn mandel_dev<T: Scalar>(&self, m: &M3<T>, ln_j: T) -> M3<T>;

    /// ∂S/∂B_p \[H\] for the six symmetric unit directions H of [`super::tensor::sym_basis`]:
    /// the chain term of the tangent through the remodelling update.
    fn stress_derivative_bp(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<[Matrix3<f64>; 6]>;

    /// The drained shear modulus of the mixture at the reference state (kPa): the stress scale
    /// of the remodelling update's consistency residual.
    fn shear_modulus(&self) -> f64;

    /// Where the law loses strong ellipticity in the strains of a compression experiment, if
    /// it does and a closed form says so (stretches down to `lambda_min`); None by default.
    fn ellipticity_limit(&self, _lambda_min: f64) -> Result<Option<EllipticityLimit>> {
        Ok(None)
    }
}

/// A closed-form limit of strong ellipticity ([`SkeletonLaw::ellipticity_limit`]): beyond it
/// a deformation can localise, and the solve stops converging on any mesh.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct EllipticityLimit {
    /// The law, as a warning names it ("Holmes–Mow solid").
    pub(crate) law: &'static str,
    /// Why it loses ellipticity, in its own parameters ("alpha1 = -0.636 < 0").
    pub(crate) cause: String,
    /// The elastic principal stretch below which it is not strongly elliptic.
    pub(crate) stretch: f64,
    /// The axial stretch of uniaxial-stress tension at which the lateral contraction gets
    /// there, if it does.
    pub(crate) uniaxial_tension: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::super::dual::Dual;
    use super::super::laws::{HolmesMow, NeoHookean};
    use super::super::penalty::CompactionPenalty;
    use super::super::permeability::{Permeability, PermeabilityModel};
    use super::super::solid::Solid;
    use super::super::tensor::{idx, sym_basis};
    use super::super::test_util::{fd_gradient, fd_tangent, kin, rel_err, Rng};
    use super::*;

    #[test]
    fn kinematics() {
        let mut rng = Rng::new(21);
        let f = rng.deformation(1.2);
        let kin = Kinematics::new(&f).unwrap();
        assert!((kin.j - f.determinant()).abs() < 1e-14);
        assert!((kin.f_inv * f - Matrix3::identity()).norm() < 1e-14);
        assert!((kin.c_inv * kin.c - Matrix3::identity()).norm() < 1e-14);
        assert!((kin.c_minus_i + Matrix3::identity() - kin.c).norm() < 1e-14);
        // ln J without cancellation near F = I, against the series tr H − tr H²/2 + tr H³/3.
        let f = Matrix3::identity() + rng.matrix(1e-9);
        let h = f - Matrix3::identity(); // exact (Sterbenz)
        let series = h.trace() - (h * h).trace() / 2.0 + (h * h * h).trace() / 3.0;
        let ln_j = Kinematics::new(&f).unwrap().ln_j;
        let naive = f.determinant().ln();
        println!(
            "ln J rel. err: {:e} (naive ln det F: {:e})",
            (ln_j - series).abs() / series.abs(),
            (naive - series).abs() / series.abs()
        );
        assert!((ln_j - series).abs() < 1e-14 * series.abs());
    }

    /// A solid law against central differences in F at deformations of volume ratio `js`
    /// (random otherwise) and random remodelling metrics: P = ∂Ψ/∂F, A = ∂P/∂F, P = F S, and the
    /// stress-only path gives the response's numbers.
    fn check_solid_law(name: &str, law: &impl SolidLaw, js: &[f64], rng: &mut Rng) {
        for &j in js {
            let (f, bp) = (rng.deformation(j), rng.remodelling_metric());
            let r = law.response(&kin(&f), &bp).unwrap();
            let p_fd = fd_gradient(|g| law.energy(&kin(g), &bp).unwrap(), &f);
            let a_fd = fd_tangent(|g| law.response(&kin(g), &bp).unwrap().p, &f);
            let (ep, ea) = (rel_err(&r.p, &p_fd), rel_err(&r.a, &a_fd));
            println!("{name}, J = {j}: P rel. err {ep:e}, A rel. err {ea:e}");
            assert!(ep < 1e-6 && ea < 1e-6, "{name}, J = {j}");
            assert!(rel_err(&(f * r.s), &r.p) < 1e-14, "{name}, J = {j}: P = F S");
            assert_eq!(law.stresses(&kin(&f), &bp).unwrap(), (r.p, r.s), "{name}, J = {j}");
        }
    }

    /// A skeleton law against its generic energy Ψ(M, ln J) and against finite differences, at
    /// deformations of volume ratio `js` and random remodelling metrics: [`SolidLaw::energy`] is
    /// Ψ; the Mandel deviator is dev Σ with Σ = 2 C (∂Ψ/∂M) B_p + ∂Ψ/∂ln J I, ∂Ψ/∂M by duals;
    /// ∂S/∂B_p against central differences of S in B_p; the shear modulus is A_xyxy at F = B_p = I.
    fn check_skeleton_law(name: &str, law: &impl SkeletonLaw, js: &[f64], rng: &mut Rng) {
        let m3 = |a: &Matrix3<f64>| -> [[f64; 3]; 3] { std::array::from_fn(|i| std::array::from_fn(|j| a[(i, j)])) };
        for &j in js {
            let (f, bp) = (rng.deformation(j), rng.remodelling_metric());
            let k = kin(&f);
            let m = k.c * bp;
            let psi = law.energy_of(&m3(&m), k.ln_j);
            let e_psi = (law.energy(&k, &bp).unwrap() - psi).abs() / psi.abs();
            let md: M3<Dual<9>> = std::array::from_fn(|a| std::array::from_fn(|b| Dual::var(m[(a, b)], 3 * a + b)));
            let dpsi = law.energy_of(&md, Dual::cst(k.ln_j)).d;
            let sigma = k.c * Matrix3::from_fn(|a, b| dpsi[3 * a + b]) * bp * 2.0;
            let dev = sigma - Matrix3::identity() * (sigma.trace() / 3.0);
            let e_dev = rel_err(&Matrix3::from(law.mandel_dev(&m3(&m), k.ln_j)).transpose(), &dev);
            let ds = law.stress_derivative_bp(&k, &bp).unwrap();
            let h = 1e-6;
            let e_ds = sym_basis().iter().zip(&ds).fold(0.0f64, |worst, (dir, d)| {
                let s_at = |t: f64| law.stresses(&k, &(bp + dir * t)).unwrap().1;
                worst.max(rel_err(d, &((s_at(h) - s_at(-h)) / (2.0 * h))))
            });
            println!("{name}, J = {j}: Psi rel. err {e_psi:e}, dev Sigma {e_dev:e}, dS/dB_p {e_ds:e}");
            assert!(e_psi < 1e-12 && e_dev < 1e-12 && e_ds < 1e-6, "{name}, J = {j}");
        }
        let id = Matrix3::identity();
        let a0 = law.response(&kin(&id), &id).unwrap().a;
        let g = law.shear_modulus();
        assert!((a0[(idx(0, 1), idx(0, 1))] - g).abs() < 1e-12 * g, "{name}: shear modulus {g}");
    }

    /// The skeleton laws by [`check_skeleton_law`]: Holmes–Mow with α1 > 0 and < 0, neo-Hookean
    /// with λ > 0 and < 0.
    #[test]
    fn every_skeleton_law_matches_its_energy() {
        let mut rng = Rng::new(24);
        for hm in [HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap(), HolmesMow::from_mu_nu(3.0, 0.45, 0.6).unwrap()] {
            check_skeleton_law(&format!("Holmes–Mow, alpha1 = {}", hm.alpha1), &hm, &[0.7, 1.0, 1.3], &mut rng);
        }
        for nh in [NeoHookean::from_mu_nu(3.0, 0.45, 0.6).unwrap(), NeoHookean::from_mu_nu(20.0, -0.3, 0.6).unwrap()] {
            check_skeleton_law(&format!("neo-Hookean, lambda = {}", nh.lambda), &nh, &[0.7, 1.0, 1.3], &mut rng);
        }
    }

    /// Every law against finite differences: the solids (Holmes–Mow with α1 > 0 and < 0,
    /// neo-Hookean alone and with the penalty, the
    /// compaction penalty inside its range J < J_cr = 0.7, the two together inside and outside
    /// that range) by [`check_solid_law`], the permeability's ∂K/∂F (both models) likewise.
    #[test]
    fn every_law_matches_finite_differences() {
        let mut rng = Rng::new(4);
        let hms = [HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap(), HolmesMow::from_mu_nu(3.0, 0.45, 0.6).unwrap()];
        let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
        for hm in &hms {
            check_solid_law(&format!("Holmes–Mow, alpha1 = {}", hm.alpha1), hm, &[0.7, 0.85, 1.0, 1.2, 1.4], &mut rng);
        }
        let nh = NeoHookean::from_mu_nu(3.0, 0.45, 0.6).unwrap();
        check_solid_law("neo-Hookean", &nh, &[0.7, 0.85, 1.0, 1.2, 1.4], &mut rng);
        check_solid_law(
            "neo-Hookean + penalty",
            &Solid { law: &nh, penalty: Some(&pen) },
            &[0.63, 0.68, 0.9],
            &mut rng,
        );
        check_solid_law("penalty", &pen, &[0.62, 0.65, 0.68], &mut rng);
        let solid = Solid { law: &hms[0], penalty: Some(&pen) };
        check_solid_law("Holmes–Mow + penalty", &solid, &[0.63, 0.68, 0.9], &mut rng);
        for model in [PermeabilityModel::Isotropic, PermeabilityModel::RemodellingDependent { c: 2.0 }] {
            let perm = Permeability::new(3.7729, 0.6, 4.638, 0.0848, model).unwrap();
            for j in [0.65, 0.8, 1.0, 1.4] {
                let (f, bp) = (rng.deformation(j), rng.remodelling_metric());
                let (k, dk) = perm.tensor_and_derivative(&kin(&f), &bp).unwrap();
                assert_eq!(k, perm.tensor(&kin(&f), &bp).unwrap());
                assert!(rel_err(&k.transpose(), &k) < 1e-15, "K symmetric");
                // dk[idx(k, l)] = ∂K/∂F_kl as a tangent: A[(idx(i, j), idx(k, l))] = ∂K_ij/∂F_kl.
                let a = Tangent::from_fn(|r, c| dk[c][(r / 3, r % 3)]);
                let err = rel_err(&a, &fd_tangent(|g| perm.tensor(&kin(g), &bp).unwrap(), &f));
                println!("permeability {model:?}, J = {j}: dK/dF rel. err {err:e}");
                assert!(err < 1e-6, "{model:?}, J = {j}");
            }
        }
    }
}
