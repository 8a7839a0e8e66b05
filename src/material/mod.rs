//! Constitutive laws of the aggregate, per unit reference volume of mixture: P_sc = F S_sc with
//! S_sc = 2 ∂(Ψ + U)/∂C (a skeleton law Ψ from [`laws`] plus the compaction penalty U(J)), the
//! referential conductivity K of Darcy's law Q = −K (Grad p − ϱf Fᵀ a_g), and the remodelling
//! of B_p.
//!
//! What a law is ([`law`]), the laws one per file ([`laws`]), the mixture's solid ([`solid`]);
//! fourth-order tangents and the other tensor helpers are in [`tensor`].

pub mod domain;
pub mod dual;
pub mod law;
pub mod laws;
pub mod penalty;
pub mod permeability;
pub mod remodelling;
#[cfg(test)]
mod remodelling_tests;
pub mod solid;
pub mod tensor;

#[cfg(test)]
pub(crate) mod test_util;

pub use domain::{domain_error, locate, AtPoint};
pub use law::{Kinematics, SkeletonLaw, SolidLaw};
pub use penalty::CompactionPenalty;
pub use permeability::{Permeability, PermeabilityModel};
pub use remodelling::{FlowForm, Integrator, Remodelling};
pub use solid::Solid;
pub use tensor::{cof, idx, Tangent};
