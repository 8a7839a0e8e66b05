//! The pointwise interface between assembly and constitutive physics.
//!
//! The weak forms (reference configuration, test functions w, q) are
//!
//! ```text
//!   R_u(w) = ∫ P : Grad w dV − ∫ b · w dV − ∫_Γt t̄ · w dA
//!   R_p(q) = ∫ ṡ q dV + ∫ W · Grad q dV + ∫_Γq q̄ q dA
//! ```
//!
//! with P the total first Piola stress (solid minus pore pressure), b the body force, ṡ the
//! rate of fluid content per reference volume (J̇, or div u̇ at small strain) and W = −Q the
//! negative Darcy flux. A [`PointModel`] computes (P, b, ṡ, W) at one quadrature point from
//! Grad u, Grad u̇, p and Grad p, and on request their derivatives; the assembler does the rest.
//! Models with qp state (remodelling) receive their committed state at the point as a read-only
//! [`QpState`] slice; the end-of-step state is a pure function of (committed state, Grad u, dt),
//! evaluated inside every call and stored only when a step is accepted
//! ([`PointModel::advance_qp_state`], kept by [`super::qp_store::QpStore`]).
//! [`QpId`] names the point in error messages.

use crate::error::Result;
use nalgebra::{Matrix3, SMatrix, Vector3};

/// The committed qp state of a model at one point and whether it evolves over the step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct QpState<'a> {
    /// State at the start of the step ([`PointModel::qp_state_len`] values; empty without qp state).
    pub(crate) committed: &'a [f64],
    /// false: hold the state at its committed value (settling before t = 0, and post-processing
    /// of a step whose end state has already been committed).
    pub(crate) evolve: bool,
}

impl QpState<'_> {
    /// No qp state (models without state).
    #[cfg(test)]
    pub(crate) const NONE: QpState<'static> = QpState { committed: &[], evolve: false };
}

/// Which quadrature point is being evaluated (the element's index in the mesh file, the point
/// within it): what a domain error names (`material::locate`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct QpId {
    pub(crate) elem: usize,
    pub(crate) point: usize,
}

/// Kinematic input at one point. `grad_u[(i, j)] = ∂u_i/∂X_j`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointState {
    pub(crate) grad_u: Matrix3<f64>,
    pub(crate) grad_udot: Matrix3<f64>,
    pub(crate) p: f64,
    pub(crate) grad_p: Vector3<f64>,
    /// Size of the current time step (backward Euler): the rate uses the end-of-step values.
    pub(crate) dt: f64,
}

/// The four pointwise terms of the residual.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointFlux {
    /// P: total first Piola–Kirchhoff stress (tested against Grad w).
    pub(crate) stress: Matrix3<f64>,
    /// b: body force per reference volume (tested against w, enters with a minus sign).
    pub(crate) body: Vector3<f64>,
    /// ṡ: rate of fluid content per reference volume (tested against q).
    pub(crate) rate: f64,
    /// W = −Q: negative referential Darcy flux (tested against Grad q).
    pub(crate) flux: Vector3<f64>,
}

/// Derivatives of [`PointFlux`] with respect to the unknowns. Indices of Grad u are flattened
/// row-major with [`crate::material::idx`] (the constitutive tangents' map); `drate` already
/// includes the time-derivative shift.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointTangent {
    /// ∂P_ij/∂(Grad u)_kl
    pub(crate) dstress_du: SMatrix<f64, 9, 9>,
    /// ∂P_ij/∂p
    pub(crate) dstress_dp: Matrix3<f64>,
    /// ∂b_i/∂(Grad u)_kl
    pub(crate) dbody_du: SMatrix<f64, 3, 9>,
    /// d ṡ/d(Grad u)_kl, total (∂/∂Grad u + shift ∂/∂Grad u̇)
    pub(crate) drate_du: Matrix3<f64>,
    /// ∂W_i/∂(Grad u)_kl
    pub(crate) dflux_du: SMatrix<f64, 3, 9>,
    /// ∂W_i/∂(Grad p)_j
    pub(crate) dflux_dgradp: Matrix3<f64>,
}

/// Post-processing quantities at a point: output fields and experiment observables.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointFields {
    /// J = det F (1 + div u at small strain).
    pub(crate) j: f64,
    /// Porosity φf = 1 − Φs/J (NaN for models without a solid fraction).
    pub(crate) porosity: f64,
    /// Constitutive (effective) Cauchy stress of the solid σ_sc = J⁻¹ P_sc Fᵀ (kPa).
    pub(crate) cauchy_sc: Matrix3<f64>,
    /// Von Mises stress √(3/2)‖dev σ_sc‖ (kPa).
    pub(crate) von_mises: f64,
    /// Spatial Darcy flux q (µm/s).
    pub(crate) darcy: Vector3<f64>,
    /// ‖E_p‖ (Frobenius), E_p = ½(B_p⁻¹ − I): the remodelling strain (0 without remodelling).
    pub(crate) norm_ep: f64,
    /// |det B_p − 1|: drift of the isochoric remodelling (0 without remodelling).
    pub(crate) det_bp_dev: f64,
    /// Pore-pressure part of the total first Piola stress (−p J F⁻ᵀ; −p I at small strain):
    /// splits contact forces exactly into pressure and constitutive parts.
    pub(crate) pressure_stress: Matrix3<f64>,
}

/// Constitutive physics at a quadrature point.
pub(crate) trait PointModel {
    /// The residual terms.
    fn eval(&self, at: QpId, s: &PointState, h: QpState) -> Result<PointFlux>;
    /// The residual terms and their derivatives (through the qp-state update too); `shift` =
    /// ∂U̇/∂U of the time integrator.
    fn eval_tangent(&self, at: QpId, s: &PointState, h: QpState, shift: f64) -> Result<(PointFlux, PointTangent)>;
    /// Drained bulk modulus of the skeleton (kPa), for the fixed-stress Schur approximation.
    fn drained_bulk_modulus(&self) -> f64;
    /// Drained P-wave modulus λ + 2µ (kPa): sets the scale of constraint rows.
    fn p_wave_modulus(&self) -> f64;
    /// Reference conductivity (µm⁴/(nN s)): sets the scale of pressure constraint rows.
    fn conductivity(&self) -> f64;
    /// Output quantities at a point.
    fn fields(&self, at: QpId, s: &PointState, h: QpState) -> Result<PointFields>;
    /// Values of qp state per point (0: the model has none, and nothing is stored).
    fn qp_state_len(&self) -> usize {
        0
    }
    /// The qp state before the first step (`qp_state_len` values).
    fn initial_qp_state(&self, _out: &mut [f64]) {}
    /// The end-of-step qp state at the state `s` of an accepted step (the value every
    /// evaluation of that step used), into `out`.
    fn advance_qp_state(&self, _at: QpId, _s: &PointState, h: QpState, out: &mut [f64]) -> Result<()> {
        out.copy_from_slice(h.committed);
        Ok(())
    }
    /// Referential solid fraction Φs, if the model has one (for porosity).
    fn solid_fraction(&self) -> Option<f64> {
        None
    }
    /// True if the terms are linear in the unknowns: then the Jacobian depends only on the
    /// time-step shift, and an unchanged shift means an unchanged matrix (and preconditioner).
    fn is_linear(&self) -> bool {
        false
    }
    /// Scales the model's gravity to `factor` times the scene's (a load continuation for the
    /// settling under gravity); nothing for models without gravity.
    fn set_gravity_factor(&mut self, _factor: f64) {}
}
