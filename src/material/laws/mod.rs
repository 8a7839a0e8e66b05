//! The skeleton laws, one per file, each a [`super::law::SkeletonLaw`]. Adding one: its file
//! here, its line below, and its scene variant and factory line (docs/developer.md).

pub(crate) mod holmes_mow;
pub(crate) mod neo_hookean;

pub(crate) use holmes_mow::HolmesMow;
pub(crate) use neo_hookean::NeoHookean;
