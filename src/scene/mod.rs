//! Scene files: what to simulate (mesh, material, boundary conditions, time stepping, output,
//! solver options), parsed from TOML with unknown keys rejected by name, and validated with
//! physical ranges before anything runs.
//!
//! [`Scene`] (in `sections`) is the whole scene: its sections in order, checked in `validate`,
//! each by its own file. One file per section holds its serde types, their defaults, the declaration of its keys
//! ([`key::Key`]: unit, default, valid range, description) and its checks, which read the ranges
//! from those declarations; [`reference`](mod@reference) writes them all as the scene reference
//! (docs/scene-reference.md), and [`explain`](mod@explain) annotates a scene with them.
//! [`LoadedScene`] loads a scene (a file or a builtin, `--set` overrides), and `resolve` turns
//! what it says into what a run uses: the `auto` choices of the measured chart in [`auto`], sizes
//! relative to the radius, the plates' radius from the mesh, deprecated keys moved to their new
//! names with a note, the defaults written out. `diagnose` words the errors that TOML and serde
//! give. A key that moves stays readable: tests/data/scenes_v1 holds the previous version's
//! shipped scenes, which must still resolve to today's (`scaling_tests`).

pub mod auto;
pub mod bc;
mod diagnose;
pub mod explain;
pub mod key;
mod load;
pub mod material;
pub mod mesh;
pub mod numerics;
pub mod observe;
pub mod overrides;
pub mod plates;
mod plausible;
pub mod reference;
mod resolve;
#[cfg(test)]
mod scaling_tests;
mod sections;
pub mod surface;
pub mod time;
pub(crate) mod tools;
mod validate;
#[cfg(test)]
mod validation_tests;

pub use bc::{Axis, BoundaryCondition, Traction};
pub(crate) use diagnose::toml_message;
pub use load::{LoadedScene, BUILTIN};
pub use material::{Material, MixtureSpec, PenaltySpec, RemodellingSpec, SolidSpec};
pub use mesh::{Geometry, Grading, MeshSpec};
pub use numerics::{Element, FemSpec, SolverSpec};
pub use observe::{Probe, ProbeField, Verification};
pub use plates::{DrainageGap, PlatesSpec, Protocol};
pub use sections::Scene;
pub use surface::SurfaceSpec;
pub use time::{InitialSpec, OutputSpec, TimeSpec};
