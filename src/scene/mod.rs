//! Scene files: what to simulate (mesh, material, boundary conditions, time stepping, output,
//! solver options), parsed from TOML with unknown keys rejected by name, and validated with
//! physical ranges before anything runs.
//!
//! `Scene` (in `sections`) is the whole scene: its sections in order, checked in `validate`,
//! each by its own file. One file per section holds its serde types, their defaults, the declaration of its keys
//! (`key::Key`: unit, default, valid range, description) and its checks, which read the ranges
//! from those declarations; [`reference`](mod@reference) writes them all as the scene reference
//! (docs/scene-reference.md), and [`explain`](mod@explain) annotates a scene with them.
//! [`LoadedScene`] loads a scene (a file or a builtin, `--set` overrides), and `resolve` turns
//! what it says into what a run uses: the `auto` choices of the measured chart in `auto`, sizes
//! relative to the radius, the plates' radius from the mesh, deprecated keys moved to their new
//! names with a note, the defaults written out. `diagnose` words the errors that TOML and serde
//! give. A key that moves stays readable: tests/data/scenes_v1 holds the previous version's
//! shipped scenes, which must still resolve to today's (`scaling_tests`).

pub(crate) mod auto;
pub(crate) mod bc;
mod diagnose;
pub(crate) mod drainage;
pub mod explain;
pub(crate) mod key;
mod load;
pub(crate) mod material;
pub(crate) mod medium;
pub(crate) mod mesh;
pub(crate) mod numerics;
pub(crate) mod observe;
pub(crate) mod overrides;
pub(crate) mod plates;
mod plausible;
pub(crate) mod protocol;
pub mod reference;
mod resolve;
#[cfg(test)]
mod scaling_tests;
mod sections;
pub(crate) mod surface;
pub(crate) mod time;
pub(crate) mod tools;
mod validate;
#[cfg(test)]
mod validation_tests;

pub(crate) use bc::BoundaryCondition;
pub(crate) use diagnose::toml_message;
pub use load::{LoadedScene, BUILTIN};
pub(crate) use material::{Material, MixtureSpec, SolidSpec};
pub(crate) use mesh::{Geometry, Grading};
pub(crate) use numerics::Element;
pub(crate) use observe::{Probe, ProbeField, Verification};
pub(crate) use plates::{DrainageGap, Protocol};
pub(crate) use sections::Scene;
pub(crate) use time::OutputSpec;
