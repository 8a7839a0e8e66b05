//! Small-strain linear poroelasticity with incompressible constituents (Biot α = 1, 1/M = 0):
//!
//! ```text
//!   P = λ tr(ε) I + 2µ ε − p I,   ε = sym Grad u
//!   ṡ = div u̇,                    W = k Grad p
//! ```
//!
//! The reference model for the Terzaghi and Cryer verification problems.

use crate::error::{Error, Result};
use crate::fem::point::{PointFields, PointFlux, PointModel, PointState, PointTangent, QpId, QpState};
use crate::material::idx;
use nalgebra::{Matrix3, SMatrix, Vector3};

/// Drained Lamé constants and isotropic conductivity.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LinearPoroelastic {
    pub(crate) lambda: f64,
    pub(crate) mu: f64,
    pub(crate) k: f64,
}

impl LinearPoroelastic {
    /// From shear modulus, Poisson ratio and conductivity.
    pub(crate) fn new(mu: f64, nu: f64, k: f64) -> Result<Self> {
        if !(mu > 0.0 && nu > -1.0 && nu < 0.5 && k > 0.0) {
            return Err(Error::Material(format!(
                "linear poroelastic: need mu > 0, -1 < nu < 0.5, k > 0 (got mu = {mu}, nu = {nu}, k = {k})"
            )));
        }
        Ok(LinearPoroelastic { lambda: 2.0 * mu * nu / (1.0 - 2.0 * nu), mu, k })
    }

    fn flux_terms(&self, s: &PointState) -> PointFlux {
        let eps = 0.5 * (s.grad_u + s.grad_u.transpose());
        let stress = Matrix3::identity() * (self.lambda * eps.trace() - s.p) + eps * (2.0 * self.mu);
        PointFlux { stress, body: Vector3::zeros(), rate: s.grad_udot.trace(), flux: s.grad_p * self.k }
    }
}

impl PointModel for LinearPoroelastic {
    fn eval(&self, _at: QpId, s: &PointState, _h: QpState) -> Result<PointFlux> {
        Ok(self.flux_terms(s))
    }

    fn eval_tangent(&self, _at: QpId, s: &PointState, _h: QpState, shift: f64) -> Result<(PointFlux, PointTangent)> {
        let mut c = SMatrix::<f64, 9, 9>::zeros();
        let d = |a: usize, b: usize| if a == b { 1.0 } else { 0.0 };
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    for l in 0..3 {
                        c[(idx(i, j), idx(k, l))] =
                            self.lambda * d(i, j) * d(k, l) + self.mu * (d(i, k) * d(j, l) + d(i, l) * d(j, k));
                    }
                }
            }
        }
        let t = PointTangent {
            dstress_du: c,
            dstress_dp: -Matrix3::identity(),
            dbody_du: SMatrix::zeros(),
            drate_du: Matrix3::identity() * shift,
            dflux_du: SMatrix::zeros(),
            dflux_dgradp: Matrix3::identity() * self.k,
        };
        Ok((self.flux_terms(s), t))
    }

    fn drained_bulk_modulus(&self) -> f64 {
        self.lambda + 2.0 * self.mu / 3.0
    }
    fn p_wave_modulus(&self) -> f64 {
        self.lambda + 2.0 * self.mu
    }
    fn conductivity(&self) -> f64 {
        self.k
    }
    fn is_linear(&self) -> bool {
        true
    }
    fn fields(&self, _at: QpId, s: &PointState, _h: QpState) -> Result<PointFields> {
        let eps = 0.5 * (s.grad_u + s.grad_u.transpose());
        let sig = Matrix3::identity() * (self.lambda * eps.trace()) + eps * (2.0 * self.mu);
        let dev = sig - Matrix3::identity() * (sig.trace() / 3.0);
        Ok(PointFields {
            j: 1.0 + eps.trace(),
            porosity: f64::NAN,
            cauchy_sc: sig,
            von_mises: 1.5f64.sqrt() * dev.norm(),
            darcy: -s.grad_p * self.k,
            pressure_stress: -Matrix3::identity() * s.p,
            norm_ep: 0.0,
            det_bp_dev: 0.0,
        })
    }
}
