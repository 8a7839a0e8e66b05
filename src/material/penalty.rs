//! Compaction penalty (33): U(J) = Φs U0 H(J_cr − J) (J − J_cr)^{2q} / (J − Φs)^r, with stress
//! S = J U'(J) C⁻¹, P = J U'(J) F⁻ᵀ and tangent ∂P/∂F.

use super::domain::{check_phi_s, domain_error};
use super::law::{Kinematics, SolidLaw, SolidResponse};
use super::tensor::{add_il_kj, add_outer, Tangent};
use crate::error::{Error, Result};
use nalgebra::Matrix3;

/// Penalty against compaction of the solid towards J = Φs; zero for J >= J_cr.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CompactionPenalty {
    /// Referential solid fraction Φs (the singular volume ratio).
    pub(crate) phi_s: f64,
    /// U0 (stress units).
    pub(crate) u0: f64,
    /// Onset J_cr ∈ (Φs, 1].
    pub(crate) j_cr: f64,
    /// Exponent q >= 1 (paper: 2): U, U' continuous and U'' bounded at J_cr.
    pub(crate) q: f64,
    /// Exponent r >= 0 of the barrier at J = Φs (paper: 0.5).
    pub(crate) r: f64,
}

impl CompactionPenalty {
    /// Validates Φs ∈ (0, 1), U0 >= 0, Φs < J_cr <= 1 (stress-free reference), q >= 1, r >= 0.
    pub(crate) fn new(phi_s: f64, u0: f64, j_cr: f64, q: f64, r: f64) -> Result<Self> {
        check_phi_s("compaction penalty", phi_s)?;
        let bad = |name: &str, v: f64, need: &str| {
            Err(Error::Material(format!("compaction penalty: {name} = {v} must be {need}")))
        };
        if !(u0 >= 0.0 && u0.is_finite()) {
            return bad("U0", u0, ">= 0");
        }
        if !(j_cr > phi_s && j_cr <= 1.0) {
            return bad("J_cr", j_cr, &format!("in (phi_s = {phi_s}, 1]"));
        }
        if !(q >= 1.0 && q.is_finite()) {
            return bad("q", q, ">= 1");
        }
        if !(r >= 0.0 && r.is_finite()) {
            return bad("r", r, ">= 0");
        }
        Ok(CompactionPenalty { phi_s, u0, j_cr, q, r })
    }

    /// (U, U', U'') at J; zeros for J >= J_cr, domain error for J <= Φs or non-finite J.
    ///
    /// With d = J_cr − J > 0 and s = J − Φs > 0, U = Φs U0 d^{2q} s^{−r}:
    /// U'  = −Φs U0 [2q d^{2q−1} s^{−r} + r d^{2q} s^{−r−1}],
    /// U'' =  Φs U0 [2q(2q−1) d^{2q−2} s^{−r} + 4qr d^{2q−1} s^{−r−1} + r(r+1) d^{2q} s^{−r−2}].
    pub(crate) fn u_and_derivatives(&self, j: f64) -> Result<(f64, f64, f64)> {
        if j.is_nan() || j <= self.phi_s {
            return Err(domain_error(
                j,
                format!("J <= phi_s = {} (solid compacted to its solid fraction)", self.phi_s),
            ));
        }
        if j >= self.j_cr {
            return Ok((0.0, 0.0, 0.0));
        }
        let (d, s, q2, r) = (self.j_cr - j, j - self.phi_s, 2.0 * self.q, self.r);
        let c = self.phi_s * self.u0 * s.powf(-r);
        let d_q2m2 = d.powf(q2 - 2.0); // q >= 1: finite at d = 0
        let (d_q2m1, d_q2) = (d_q2m2 * d, d_q2m2 * d * d);
        let u = c * d_q2;
        let du = -c * (q2 * d_q2m1 + r * d_q2 / s);
        let ddu = c * (q2 * (q2 - 1.0) * d_q2m2 + 2.0 * q2 * r * d_q2m1 / s + r * (r + 1.0) * d_q2 / (s * s));
        Ok((u, du, ddu))
    }
}

impl SolidLaw for CompactionPenalty {
    /// U(J) (B_p plays no part).
    fn energy(&self, kin: &Kinematics, _bp: &Matrix3<f64>) -> Result<f64> {
        Ok(self.u_and_derivatives(kin.j)?.0)
    }

    /// (P, S) = (J U' F⁻ᵀ, J U' C⁻¹).
    fn stresses(&self, kin: &Kinematics, _bp: &Matrix3<f64>) -> Result<(Matrix3<f64>, Matrix3<f64>)> {
        let (_, du, _) = self.u_and_derivatives(kin.j)?;
        if du == 0.0 {
            return Ok((Matrix3::zeros(), Matrix3::zeros()));
        }
        let j = kin.j;
        Ok((kin.f_inv.transpose() * (j * du), kin.c_inv * (j * du)))
    }

    /// S, P, A (index map of [`super::tensor::idx`]). With dJ = J F⁻ᵀ:dF and dF⁻ᵀ = −F⁻ᵀ dFᵀ F⁻ᵀ:
    /// A = J (U' + J U'') F⁻ᵀ_ij F⁻ᵀ_kl − J U' F⁻ᵀ_il F⁻ᵀ_kj.
    fn response(&self, kin: &Kinematics, _bp: &Matrix3<f64>) -> Result<SolidResponse> {
        let (_, du, ddu) = self.u_and_derivatives(kin.j)?;
        let mut a = Tangent::zeros();
        if du == 0.0 && ddu == 0.0 {
            return Ok(SolidResponse { p: Matrix3::zeros(), a, s: Matrix3::zeros() });
        }
        let j = kin.j;
        let f_inv_t = kin.f_inv.transpose();
        add_outer(&mut a, j * (du + j * ddu), &f_inv_t, &f_inv_t);
        add_il_kj(&mut a, -j * du, &f_inv_t, &f_inv_t);
        Ok(SolidResponse { p: f_inv_t * (j * du), a, s: kin.c_inv * (j * du) })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::{kin, Rng};
    use super::*;

    /// Table 1: Φs = 0.6, U0 = 1 MPa = 1000 kPa, J_cr = 0.7, q = 2, r = 0.5.
    fn table1() -> CompactionPenalty {
        CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap()
    }

    #[test]
    fn zero_above_onset() {
        let pen = table1();
        for j in [0.7, 0.7 + 1e-12, 0.9, 1.0, 1.5] {
            assert_eq!(pen.u_and_derivatives(j).unwrap(), (0.0, 0.0, 0.0));
        }
        let f = Rng::new(7).deformation(0.9);
        assert_eq!(pen.energy(&kin(&f), &Matrix3::identity()).unwrap(), 0.0);
        assert_eq!(pen.stresses(&kin(&f), &Matrix3::identity()).unwrap().1, Matrix3::zeros());
        let SolidResponse { p, a, .. } = pen.response(&kin(&f), &Matrix3::identity()).unwrap();
        assert_eq!((p.norm(), a.norm()), (0.0, 0.0));
    }

    #[test]
    fn closed_form_value() {
        // J = 0.65: U = 0.6 · 1000 · 0.05⁴ / 0.05^0.5.
        let (u, _, _) = table1().u_and_derivatives(0.65).unwrap();
        let expect = 0.6 * 1000.0 * 0.05f64.powi(4) / 0.05f64.sqrt();
        assert!((u - expect).abs() < 1e-14 * expect);
    }

    #[test]
    fn smooth_at_onset() {
        // Below J_cr, U' ≈ −4 Φs U0 d³/√(J_cr − Φs) and U'' ≈ 12 Φs U0 d²/√(J_cr − Φs) (2q = 4,
        // d = J_cr − J): both tend to 0, their value above J_cr, so U is C² there.
        let pen = table1();
        assert_eq!(pen.u_and_derivatives(0.7).unwrap(), (0.0, 0.0, 0.0));
        let c = 0.6 * 1000.0 / 0.1f64.sqrt();
        for d in [1e-2, 1e-3, 1e-4, 1e-5] {
            let (_, du, ddu) = pen.u_and_derivatives(0.7 - d).unwrap();
            println!("J_cr - {d:e}: U' = {du:e}, U'' = {ddu:e}");
            // Relative corrections are O(d/(J_cr − Φs)) = O(10 d).
            assert!((du / d.powi(3) + 4.0 * c).abs() < 20.0 * d * 4.0 * c);
            assert!((ddu / d.powi(2) - 12.0 * c).abs() < 20.0 * d * 12.0 * c);
        }
        // With q = 1, the smallest allowed: U' still continuous, U'' bounded.
        let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 1.0, 0.5).unwrap();
        let (_, du, ddu) = pen.u_and_derivatives(0.7 - 1e-9).unwrap();
        assert!(du.abs() < 1e-5 && ddu.is_finite());
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let pen = table1();
        let h = 1e-6;
        for j in [0.61, 0.63, 0.65, 0.69] {
            let (_, du, ddu) = pen.u_and_derivatives(j).unwrap();
            let at = |x: f64| pen.u_and_derivatives(x).unwrap();
            let du_fd = (at(j + h).0 - at(j - h).0) / (2.0 * h);
            let ddu_fd = (at(j + h).1 - at(j - h).1) / (2.0 * h);
            println!(
                "J = {j}: U' rel. err {:e}, U'' rel. err {:e}",
                (du - du_fd).abs() / du.abs(),
                (ddu - ddu_fd).abs() / ddu.abs()
            );
            assert!((du - du_fd).abs() < 1e-6 * du.abs());
            assert!((ddu - ddu_fd).abs() < 1e-6 * ddu.abs());
        }
    }

    #[test]
    fn domain_error_at_and_below_solid_fraction() {
        let pen = table1();
        for j in [0.6, 0.5, 0.0, -1.0, f64::NAN] {
            assert!(matches!(pen.u_and_derivatives(j), Err(Error::Domain { .. })), "J = {j}");
        }
        let f = Rng::new(8).deformation(0.55);
        match pen.response(&kin(&f), &Matrix3::identity()) {
            Err(Error::Domain { j, .. }) => assert!((j - 0.55).abs() < 1e-12),
            other => panic!("expected a domain error, got {other:?}"),
        }
    }

    #[test]
    fn rejects_bad_parameters() {
        for (args, name) in [
            ((0.6, -1.0, 0.7, 2.0, 0.5), "U0 = -1"),
            ((0.6, 1.0, 0.6, 2.0, 0.5), "J_cr = 0.6"),
            ((0.6, 1.0, 1.1, 2.0, 0.5), "J_cr = 1.1"),
            ((0.6, 1.0, 0.7, 0.5, 0.5), "q = 0.5"),
            ((0.6, 1.0, 0.7, 2.0, -0.5), "r = -0.5"),
            ((0.0, 1.0, 0.7, 2.0, 0.5), "phi_s = 0"),
        ] {
            let (a, b, c, d, e) = args;
            match CompactionPenalty::new(a, b, c, d, e) {
                Err(Error::Material(m)) => assert!(m.contains(name), "{m}"),
                other => panic!("expected a material error for {name}, got {other:?}"),
            }
        }
    }
}
