//! The skeleton laws, one per file, each a [`super::law::SkeletonLaw`]. Adding one: its file
//! here, its line below, and its scene variant and factory line (docs/developer.md).

pub mod holmes_mow;
pub mod neo_hookean;

pub use holmes_mow::HolmesMow;
pub use neo_hookean::NeoHookean;
