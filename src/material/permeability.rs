//! Referential conductivity (42)–(48): k(J) = k0 [(J − Φs)/(1 − Φs)]^κ exp(½ m0 (J² − 1)) and
//! K = J k C⁻¹ (isotropic), or K = J k C⁻¹ + J k1 B_p + J k2 B_p C B_p with k1 = k/(c J²),
//! k2 = k/(c² J⁴) (remodelling-dependent); ∂K/∂F at fixed B_p.

use super::domain::check_phi_s;
use super::law::Kinematics;
use crate::error::{Error, Result};
use nalgebra::Matrix3;

/// Which permeability tensor: spherical k g⁻¹ (42), or k g⁻¹ + k1 b_e + k2 b_e² (45) with
/// k0⁽¹⁾ = k0/c, k0⁽²⁾ = k0/c² (47).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PermeabilityModel {
    Isotropic,
    RemodellingDependent { c: f64 },
}

/// Holmes–Mow permeability and its pull-back K to the reference configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Permeability {
    /// Reference permeability k0 (at J = 1).
    pub(crate) k0: f64,
    /// Referential solid fraction Φs; k vanishes at J = Φs.
    pub(crate) phi_s: f64,
    /// Exponent κ.
    pub(crate) kappa: f64,
    /// Exponent m0.
    pub(crate) m0: f64,
    pub(crate) model: PermeabilityModel,
}

impl Permeability {
    /// Validates k0 > 0, Φs ∈ (0, 1), κ >= 0, m0 finite, c > 0.
    pub(crate) fn new(k0: f64, phi_s: f64, kappa: f64, m0: f64, model: PermeabilityModel) -> Result<Self> {
        check_phi_s("permeability", phi_s)?;
        let bad =
            |name: &str, v: f64, need: &str| Err(Error::Material(format!("permeability: {name} = {v} must be {need}")));
        if !(k0 > 0.0 && k0.is_finite()) {
            return bad("k0", k0, "> 0");
        }
        if !(kappa >= 0.0 && kappa.is_finite()) {
            return bad("kappa", kappa, ">= 0");
        }
        if !m0.is_finite() {
            return bad("m0", m0, "finite");
        }
        if let PermeabilityModel::RemodellingDependent { c } = model {
            if !(c > 0.0 && c.is_finite()) {
                return bad("c", c, "> 0");
            }
        }
        Ok(Permeability { k0, phi_s, kappa, m0, model })
    }

    /// k(J) and dk/dJ = k [κ/(J − Φs) + m0 J]. Domain error for J <= Φs or non-finite J.
    pub(crate) fn k(&self, j: f64) -> Result<(f64, f64)> {
        if !(j > self.phi_s && j.is_finite()) {
            return Err(super::domain::domain_error(j, format!("J <= phi_s = {}: permeability vanishes", self.phi_s)));
        }
        let s = j - self.phi_s;
        let ln_ratio = (s / (1.0 - self.phi_s)).ln();
        let k = self.k0 * (self.kappa * ln_ratio + 0.5 * self.m0 * (j - 1.0) * (j + 1.0)).exp();
        Ok((k, k * (self.kappa / s + self.m0 * j)))
    }

    /// K = g0 C⁻¹ + g1 B_p + g2 B_p C B_p at the kinematics of F.
    pub(crate) fn tensor(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<Matrix3<f64>> {
        let [(g0, _), (g1, _), (g2, _)] = self.coefficients(kin.j)?;
        Ok(kin.c_inv * g0 + bp * g1 + bp * kin.c * bp * g2)
    }

    /// K and dK[3k + l] = ∂K/∂F_kl (B_p held fixed: it is a qp-state variable).
    ///
    /// With ∂J/∂F_kl = J F⁻¹_lk, ∂C⁻¹_ij/∂F_kl = −(C⁻¹_il F⁻¹_jk + F⁻¹_ik C⁻¹_lj) and
    /// ∂(B C B)_ij/∂F_kl = B_il (FB)_kj + (FB)_ki B_lj:
    /// ∂K_ij/∂F_kl = (g0' C⁻¹ + g1' B + g2' BCB)_ij J F⁻¹_lk + g0 ∂C⁻¹_ij/∂F_kl + g2 ∂(BCB)_ij/∂F_kl.
    pub(crate) fn tensor_and_derivative(
        &self,
        kin: &Kinematics,
        bp: &Matrix3<f64>,
    ) -> Result<(Matrix3<f64>, [Matrix3<f64>; 9])> {
        let f = &kin.f;
        let [(g0, dg0), (g1, dg1), (g2, dg2)] = self.coefficients(kin.j)?;
        let (ci, fi) = (&kin.c_inv, &kin.f_inv);
        let bcb = bp * kin.c * bp;
        let k_tensor = ci * g0 + bp * g1 + bcb * g2;
        let dk_dj = (ci * dg0 + bp * dg1 + bcb * dg2) * kin.j;
        let fb = f * bp;
        let mut dk = [Matrix3::zeros(); 9];
        for k in 0..3 {
            for l in 0..3 {
                dk[super::tensor::idx(k, l)] = Matrix3::from_fn(|i, j| {
                    dk_dj[(i, j)] * fi[(l, k)] - g0 * (ci[(i, l)] * fi[(j, k)] + fi[(i, k)] * ci[(l, j)])
                        + g2 * (bp[(i, l)] * fb[(k, j)] + fb[(k, i)] * bp[(l, j)])
                });
            }
        }
        Ok((k_tensor, dk))
    }

    /// ∂K/∂B_p \[H\] = g1 H + g2 (H C B_p + B_p C H) for the six symmetric unit directions H of
    /// [`super::tensor::sym_basis`] (zero for the isotropic model).
    pub(crate) fn derivative_bp(&self, kin: &Kinematics, bp: &Matrix3<f64>) -> Result<[Matrix3<f64>; 6]> {
        if self.model == PermeabilityModel::Isotropic {
            return Ok([Matrix3::zeros(); 6]);
        }
        let [_, (g1, _), (g2, _)] = self.coefficients(kin.j)?;
        let cb = kin.c * bp;
        Ok(super::tensor::sym_basis().map(|h| {
            let hcb = h * cb;
            h * g1 + (hcb + hcb.transpose()) * g2
        }))
    }

    /// (g_m, dg_m/dJ) for the coefficients of C⁻¹, B_p and B_p C B_p:
    /// g0 = J k, g1 = k/(c J), g2 = k/(c² J³) (g1 = g2 = 0 for the isotropic model).
    fn coefficients(&self, j: f64) -> Result<[(f64, f64); 3]> {
        let (k, dk) = self.k(j)?;
        let g0 = (j * k, k + j * dk);
        Ok(match self.model {
            PermeabilityModel::Isotropic => [g0, (0.0, 0.0), (0.0, 0.0)],
            PermeabilityModel::RemodellingDependent { c } => {
                let (s1, s2) = (1.0 / (c * j), 1.0 / (c * c * j * j * j));
                [g0, (s1 * k, s1 * (dk - k / j)), (s2 * k, s2 * (dk - 3.0 * k / j))]
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::{kin, rel_err, Rng};
    use super::*;

    /// Table 1 in µm⁴/(nN s): k0 = 3.7729, Φs = 0.6, κ = 4.638, m0 = 0.0848.
    fn law(model: PermeabilityModel) -> Permeability {
        Permeability::new(3.7729, 0.6, 4.638, 0.0848, model).unwrap()
    }
    const MODELS: [PermeabilityModel; 2] =
        [PermeabilityModel::Isotropic, PermeabilityModel::RemodellingDependent { c: 2.0 }];

    #[test]
    fn reference_value_and_closed_form() {
        let perm = law(PermeabilityModel::Isotropic);
        assert_eq!(perm.k(1.0).unwrap().0, 3.7729);
        // J = 0.8: k = k0 (0.2/0.4)^κ exp(½ m0 (0.64 − 1)).
        let expect = 3.7729 * 0.5f64.powf(4.638) * f64::exp(0.5 * 0.0848 * (0.64 - 1.0));
        assert!((perm.k(0.8).unwrap().0 - expect).abs() < 1e-14 * expect);
        // Confined stretch F = diag(1, 1, λ): K = λ k(λ) diag(1, 1, 1/λ²).
        let lam = 0.8;
        let f = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, lam));
        let k = perm.tensor(&kin(&f), &Matrix3::identity()).unwrap();
        let want = Matrix3::from_diagonal(&nalgebra::Vector3::new(lam * expect, lam * expect, expect / lam));
        assert!(rel_err(&k, &want) < 1e-14);
    }

    #[test]
    fn dk_dj_matches_finite_difference() {
        let perm = law(PermeabilityModel::Isotropic);
        for j in [0.62, 0.7, 1.0, 1.3] {
            let h = 1e-6;
            let dk_fd = (perm.k(j + h).unwrap().0 - perm.k(j - h).unwrap().0) / (2.0 * h);
            let dk = perm.k(j).unwrap().1;
            println!("J = {j}: dk/dJ rel. err {:e}", (dk - dk_fd).abs() / dk.abs());
            assert!((dk - dk_fd).abs() < 1e-6 * dk.abs());
        }
    }

    #[test]
    fn remodelling_dependent_at_reference() {
        let id = Matrix3::identity();
        let c = 2.0;
        let k = law(PermeabilityModel::RemodellingDependent { c }).tensor(&kin(&id), &id).unwrap();
        let want = id * (3.7729 * (1.0 + 1.0 / c + 1.0 / (c * c)));
        assert!(rel_err(&k, &want) < 1e-15);
    }

    #[test]
    fn referential_tensor_is_frame_invariant() {
        let mut rng = Rng::new(12);
        for model in MODELS {
            let (f, bp, q) = (rng.deformation(0.9), rng.remodelling_metric(), rng.rotation());
            let perm = law(model);
            assert!(rel_err(&perm.tensor(&kin(&(q * f)), &bp).unwrap(), &perm.tensor(&kin(&f), &bp).unwrap()) < 1e-13);
        }
    }

    #[test]
    fn domain_error_at_and_below_solid_fraction() {
        let perm = law(PermeabilityModel::Isotropic);
        for j in [0.6, 0.3, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(perm.k(j), Err(Error::Domain { .. })), "J = {j}");
        }
        let f = Rng::new(13).deformation(0.59);
        assert!(matches!(perm.tensor_and_derivative(&kin(&f), &Matrix3::identity()), Err(Error::Domain { .. })));
    }

    #[test]
    fn rejects_bad_parameters() {
        let iso = PermeabilityModel::Isotropic;
        for (r, name) in [
            (Permeability::new(0.0, 0.6, 4.6, 0.08, iso), "k0 = 0"),
            (Permeability::new(1.0, 1.2, 4.6, 0.08, iso), "phi_s = 1.2"),
            (Permeability::new(1.0, 0.6, -1.0, 0.08, iso), "kappa = -1"),
            (Permeability::new(1.0, 0.6, 4.6, f64::NAN, iso), "m0 = NaN"),
            (Permeability::new(1.0, 0.6, 4.6, 0.08, PermeabilityModel::RemodellingDependent { c: 0.0 }), "c = 0"),
        ] {
            match r {
                Err(Error::Material(m)) => assert!(m.contains(name), "{m}"),
                other => panic!("expected a material error for {name}, got {other:?}"),
            }
        }
    }
}
