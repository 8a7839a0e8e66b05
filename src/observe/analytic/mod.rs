//! Exact series solutions of Terzaghi's (1-D column) and Cryer's (sphere) consolidation
//! problems for linear poroelasticity with incompressible constituents (Biot α = 1, 1/M = 0):
//! the exact-solution columns of the verification scenes ([`super::verification`]).
//!
//! The two problems are in `terzaghi.rs` and `cryer.rs`, the special functions they need in
//! `special.rs`. What the verification scenes read is public ([`Drained`],
//! [`terzaghi_pressure`], [`terzaghi_settlement`], [`CryerSeries::center_pressure`]); the other
//! forms (the pressure profile, the mean pressure, the surface displacement, the Mandel–Cryer
//! peak) are test oracles, compiled with the tests, which check every form against the others
//! and against independent numerical solutions (`reference.rs`: a Crank–Nicolson column and a
//! radial finite-volume sphere).
//!
//! # Model and sign conventions
//! * Drained isotropic skeleton: shear modulus µ, Poisson ratio ν, λ = 2µν/(1 − 2ν),
//!   bulk modulus K = λ + 2µ/3, oedometric (P-wave) modulus λ + 2µ.
//! * Total stress σ = λ tr(ε) I + 2µ ε − p I (tension positive); pore pressure p is positive in
//!   compression. Darcy: q = −k ∇p; incompressible constituents: ∂(div u)/∂t = div(k ∇p).
//! * Consolidation coefficient c = k (λ + 2µ).
//! * Loads P are the magnitude of a COMPRESSIVE normal traction applied as a step at t = 0⁺
//!   (σ·n = −P n on the loaded boundary); compressive loads are positive.
//! * With incompressible constituents the undrained response is rigid in volume (undrained
//!   Poisson ratio 1/2): at t = 0⁺ there is no volume change and the pressure carries the load.
//!
//! Times are also used in dimensionless form τ = c t / L² with L = H (Terzaghi) or a (Cryer).
//! For t ≤ 0 the functions return the t = 0⁺ state (just after loading). Invalid parameters
//! (µ ≤ 0, ν outside (−1, 1/2), k ≤ 0, non-positive lengths, non-finite numbers) give NaN, never
//! a panic; [`Drained::new`] reports them as [`Error::Material`].

mod cryer;
#[cfg(test)]
mod reference;
mod special;
mod terzaghi;

pub use cryer::CryerSeries;
pub use terzaghi::{terzaghi_pressure, terzaghi_settlement};

use crate::error::{Error, Result};

/// Drained skeleton and permeability of a linear poroelastic medium with incompressible constituents.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drained {
    /// Drained shear modulus µ (> 0).
    pub mu: f64,
    /// Drained Poisson ratio ν, −1 < ν < 1/2.
    pub nu: f64,
    /// Permeability / hydraulic conductivity k in Darcy's law q = −k ∇p (> 0).
    pub k: f64,
}

impl Drained {
    /// Validated parameters: µ > 0, −1 < ν < 1/2, k > 0, all finite.
    pub fn new(mu: f64, nu: f64, k: f64) -> Result<Self> {
        let m = Drained { mu, nu, k };
        if m.is_valid() {
            Ok(m)
        } else {
            Err(Error::Material(format!(
                "poroelastic reference solution needs mu > 0, -1 < nu < 0.5, k > 0 \
                 (got mu = {mu}, nu = {nu}, k = {k})"
            )))
        }
    }

    /// True when the parameters are admissible (see [`Drained::new`]).
    fn is_valid(&self) -> bool {
        self.mu.is_finite()
            && self.mu > 0.0
            && self.nu.is_finite()
            && self.nu > -1.0
            && self.nu < 0.5
            && self.k.is_finite()
            && self.k > 0.0
    }

    /// Lamé λ = 2µν/(1 − 2ν).
    fn lambda(&self) -> f64 {
        2.0 * self.mu * self.nu / (1.0 - 2.0 * self.nu)
    }

    /// Oedometric modulus λ + 2µ.
    fn oedometric_modulus(&self) -> f64 {
        self.lambda() + 2.0 * self.mu
    }

    /// Drained bulk modulus K = λ + 2µ/3.
    #[cfg(test)]
    fn bulk_modulus(&self) -> f64 {
        self.lambda() + 2.0 * self.mu / 3.0
    }

    /// Consolidation coefficient c = k (λ + 2µ).
    pub fn consolidation_coefficient(&self) -> f64 {
        self.k * self.oedometric_modulus()
    }
}
