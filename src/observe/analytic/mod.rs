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
//! a panic; [`Drained::new`] reports them as [`Error::Material`](crate::error::Error::Material).

mod cryer;
mod drained;
#[cfg(test)]
mod reference;
mod special;
mod terzaghi;

pub(crate) use cryer::CryerSeries;
pub(crate) use drained::Drained;
pub(crate) use terzaghi::{terzaghi_pressure, terzaghi_settlement};
