//! Constitutive laws of the aggregate, per unit reference volume of mixture: P_sc = F S_sc with
//! S_sc = 2 ∂(Ψ + U)/∂C (a skeleton law Ψ from [`laws`] plus the compaction penalty U(J)), the
//! referential conductivity K of Darcy's law Q = −K (Grad p − ϱf Fᵀ a_g), and the remodelling
//! of B_p.
//!
//! What a law is ([`law`]), the laws one per file ([`laws`]), the mixture's solid ([`solid`]);
//! fourth-order tangents and the other tensor helpers are in [`tensor`].

pub(crate) mod domain;
pub(crate) mod dual;
pub(crate) mod law;
pub(crate) mod laws;
pub(crate) mod penalty;
pub(crate) mod permeability;
pub(crate) mod remodelling;
#[cfg(test)]
mod remodelling_tests;
pub(crate) mod solid;
pub(crate) mod tensor;

#[cfg(test)]
pub(crate) mod test_util;

pub(crate) use domain::{domain_error, locate, AtPoint};
pub(crate) use law::{Kinematics, SkeletonLaw, SolidLaw};
pub(crate) use penalty::CompactionPenalty;
pub(crate) use permeability::{Permeability, PermeabilityModel};
pub(crate) use remodelling::{FlowForm, Integrator, Remodelling};
pub(crate) use solid::Solid;
pub(crate) use tensor::{cof, idx, Tangent};
