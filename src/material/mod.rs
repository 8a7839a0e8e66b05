//! Constitutive laws of the aggregate, per unit reference volume of mixture: P_sc = F S_sc with
//! S_sc = 2 ∂(Ψ + U)/∂C (Holmes–Mow solid Ψ plus compaction penalty U(J)), and the referential
//! conductivity K of Darcy's law Q = −K (Grad p − ϱf Fᵀ a_g).
//!
//! Fourth-order tangents and the other tensor helpers are in [`tensor`].

pub mod dual;
pub mod ellipticity;
pub mod holmes_mow;
pub mod penalty;
pub mod permeability;
pub mod remodelling;
#[cfg(test)]
mod remodelling_tests;
pub mod tensor;

#[cfg(test)]
pub(crate) mod test_util;

use crate::error::{Error, Result};
use nalgebra::Matrix3;

pub use holmes_mow::HolmesMow;
pub use penalty::CompactionPenalty;
pub use permeability::{Permeability, PermeabilityModel};
pub use remodelling::{FlowForm, Integrator, Remodelling};
use tensor::{add_ik_lj, add_il_kj, add_outer};
pub use tensor::{cof, idx, Tangent};

/// A state outside a law's domain. The material code does not know where it is evaluated, so
/// cell and point are 0; the caller fills them in with [`locate`] or [`AtPoint::at_point`].
pub fn domain_error(j: f64, msg: impl Into<String>) -> Error {
    Error::Domain { cell: 0, point: 0, j, msg: msg.into() }
}

/// Puts the element and quadrature point into a [`Error::Domain`]; other errors pass unchanged.
pub fn locate(err: Error, cell: usize, point: usize) -> Error {
    match err {
        Error::Domain { j, msg, .. } => Error::Domain { cell, point, j, msg },
        other => other,
    }
}

/// `material_call(..).at_point(cell, q)?` fills in where a domain error happened.
pub trait AtPoint {
    fn at_point(self, cell: usize, point: usize) -> Self;
}

impl<T> AtPoint for Result<T> {
    fn at_point(self, cell: usize, point: usize) -> Self {
        self.map_err(|e| locate(e, cell, point))
    }
}

/// Kinematic quantities shared by all laws at one point, computed once per F.
#[derive(Clone, Debug)]
pub struct Kinematics {
    /// Deformation gradient F.
    pub f: Matrix3<f64>,
    /// J = det F.
    pub j: f64,
    /// ln J, from J − 1 without cancellation (J − 1 is summed from the invariants of F − I).
    pub ln_j: f64,
    /// F⁻¹.
    pub f_inv: Matrix3<f64>,
    /// cof F = J F⁻ᵀ (from the entries of F, see [`cof`]).
    pub cof_f: Matrix3<f64>,
    /// C = FᵀF.
    pub c: Matrix3<f64>,
    /// C − I = H + Hᵀ + HᵀH with H = F − I (= 2E, no cancellation near F = I).
    pub c_minus_i: Matrix3<f64>,
    /// C⁻¹ = F⁻¹F⁻ᵀ.
    pub c_inv: Matrix3<f64>,
}

impl Kinematics {
    /// Domain error when F is not finite or J <= 0.
    pub fn new(f: &Matrix3<f64>) -> Result<Self> {
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
pub struct SolidResponse {
    /// First Piola–Kirchhoff stress P_sc = F S_sc.
    pub p: Matrix3<f64>,
    /// Tangent ∂P_sc/∂F, index map of [`idx`].
    pub a: Tangent,
    /// Second Piola–Kirchhoff stress S_sc.
    pub s: Matrix3<f64>,
}

/// A hyperelastic solid law at one point, evaluated at the kinematics of F (computed once per
/// point by the caller, [`Kinematics::new`]) and the remodelling metric B_p (ignored by laws
/// without one): the energy Ψ, the stresses (P, S) and the tangent ∂P/∂F.
pub trait SolidLaw {
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

/// The mixture's solid: Holmes–Mow plus, if given, the compaction penalty (model.md (39) in full).
#[derive(Clone, Copy, Debug)]
pub struct Solid<'a> {
    pub hm: &'a HolmesMow,
    pub penalty: Option<&'a CompactionPenalty>,
}

impl SolidLaw for Solid<'_> {
    fn energy(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<f64> {
        let mut psi = self.hm.energy(kin, bp)?;
        if let Some(pen) = self.penalty {
            psi += pen.energy(kin, bp)?;
        }
        Ok(psi)
    }

    fn stresses(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<(Matrix3<f64>, Matrix3<f64>)> {
        let (mut p, mut s) = self.hm.stresses(kin, bp)?;
        if let Some(pen) = self.penalty {
            let (pp, ps) = pen.stresses(kin, bp)?;
            p += pp;
            s += ps;
        }
        Ok((p, s))
    }

    fn response(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<SolidResponse> {
        let mut r = self.hm.response(kin, bp)?;
        if let Some(pen) = self.penalty {
            let u = pen.response(kin, bp)?;
            r.p += u.p;
            r.a += u.a;
            r.s += u.s;
        }
        Ok(r)
    }
}

/// Φs must lie in (0, 1); shared by all laws.
pub(crate) fn check_phi_s(law: &str, phi_s: f64) -> Result<()> {
    if phi_s > 0.0 && phi_s < 1.0 {
        Ok(())
    } else {
        Err(Error::Material(format!("{law}: solid fraction phi_s = {phi_s} outside (0, 1)")))
    }
}

#[cfg(test)]
mod tests {
    use super::test_util::{fd_gradient, fd_tangent, kin, rel_err, Rng};
    use super::*;

    #[test]
    fn caller_fills_in_location() {
        let r: Result<()> = Err(domain_error(-0.5, "J <= 0"));
        match r.at_point(12, 3) {
            Err(Error::Domain { cell: 12, point: 3, j, msg }) => {
                assert!(j == -0.5 && msg == "J <= 0")
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(locate(Error::Material("x".into()), 1, 2), Error::Material(_)));
    }

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

    /// Every law against finite differences: the solids (Holmes–Mow with α1 > 0 and < 0, the
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
        check_solid_law("penalty", &pen, &[0.62, 0.65, 0.68], &mut rng);
        let solid = Solid { hm: &hms[0], penalty: Some(&pen) };
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

    /// The solid is the sum of its parts, and Holmes–Mow alone without the penalty.
    #[test]
    fn combined_response_is_the_sum_of_its_parts() {
        let hm = HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap();
        let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
        let (with, alone) = (Solid { hm: &hm, penalty: Some(&pen) }, Solid { hm: &hm, penalty: None });
        let mut rng = Rng::new(22);
        for j in [0.63, 0.68, 0.9] {
            let (f, bp) = (rng.deformation(j), rng.remodelling_metric());
            let k = kin(&f);
            let r = with.response(&k, &bp).unwrap();
            let (s_hm, s_pen) = (hm.stresses(&k, &bp).unwrap().1, pen.stresses(&k, &bp).unwrap().1);
            assert!(rel_err(&r.s, &(s_hm + s_pen)) < 1e-14);
            let psi = hm.energy(&k, &bp).unwrap() + pen.energy(&k, &bp).unwrap();
            assert_eq!(with.energy(&k, &bp).unwrap(), psi);
            assert_eq!(alone.response(&k, &bp).unwrap(), hm.response(&k, &bp).unwrap());
            assert_eq!(alone.stresses(&k, &bp).unwrap(), hm.stresses(&k, &bp).unwrap());
        }
    }

    #[test]
    fn combined_response_is_frame_invariant() {
        let hm = HolmesMow::from_mu_nu(3.0, 0.45, 0.6).unwrap();
        let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
        let mut rng = Rng::new(23);
        let (f, bp, q) = (rng.deformation(0.65), rng.remodelling_metric(), rng.rotation());
        let solid = Solid { hm: &hm, penalty: Some(&pen) };
        let r = solid.response(&kin(&f), &bp).unwrap();
        let rq = solid.response(&kin(&(q * f)), &bp).unwrap();
        assert!(rel_err(&rq.p, &(q * r.p)) < 1e-13);
        assert!(rel_err(&rq.s, &r.s) < 1e-13);
    }
}
