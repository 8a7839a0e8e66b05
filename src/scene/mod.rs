//! Scene files: what to simulate (mesh, material, boundary conditions, time stepping, output,
//! solver options), parsed from TOML with unknown keys rejected by name, and validated with
//! physical ranges before anything runs.
//!
//! One file per section holds its serde types, their defaults, the declaration of its keys
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
pub mod surface;
pub mod time;
pub(crate) mod tools;
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
pub use surface::SurfaceSpec;
pub use time::{InitialSpec, OutputSpec, TimeSpec};

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A whole scene. Sections are grouped by concern.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name (default: the file stem); names the run directory.
    #[serde(default)]
    pub name: String,
    #[serde(default)]
    pub description: String,
    pub mesh: MeshSpec,
    pub material: Material,
    #[serde(default)]
    pub bc: Vec<BoundaryCondition>,
    pub time: TimeSpec,
    #[serde(default)]
    pub output: OutputSpec,
    #[serde(default)]
    pub probe: Vec<Probe>,
    #[serde(default)]
    pub verification: Option<Verification>,
    /// Rigid plates squeezing the aggregate (contact, drainage, loading).
    #[serde(default)]
    pub plates: Option<PlatesSpec>,
    /// Surface tension of the aggregate's boundary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<SurfaceSpec>,
    #[serde(default)]
    pub solver: SolverSpec,
    #[serde(default)]
    pub fem: FemSpec,
    /// The state at t = 0 (default: undeformed, p = 0).
    #[serde(default)]
    pub initial: Option<InitialSpec>,
    /// PETSc options without the leading dash: `ksp_rtol = 1e-10`, `ksp_monitor = true`.
    #[serde(default)]
    pub petsc: BTreeMap<String, toml::Value>,
}

impl Scene {
    /// Checks ranges and consistency, section by section; the message names the key and value.
    /// What is allowed but likely a mistake is a note in `notes`.
    pub(crate) fn validate(&self, notes: &mut Vec<String>) -> Result<(), String> {
        self.mesh.validate()?;
        self.material.validate()?;
        for (i, bc) in self.bc.iter().enumerate() {
            bc.validate(i)?;
        }
        if let Some(init) = &self.initial {
            init.validate()?;
        }
        self.output.validate()?;
        self.time.validate(&self.output.fields_at, self.plates.is_some())?;
        for p in &self.probe {
            p.validate()?;
        }
        if let Some(p) = &self.plates {
            p.validate(self.time.t_end, notes)?;
        }
        if let Some(v) = &self.verification {
            v.validate()?;
        }
        if let Some(sf) = &self.surface {
            sf.validate(self.plates.is_some())?;
        }
        self.fem.validate(self.mesh.geometry)?;
        plausible::check(self, notes)?;
        self.validate_petsc()
    }

    /// [petsc]: scalar values only.
    fn validate_petsc(&self) -> Result<(), String> {
        for (k, v) in &self.petsc {
            if matches!(v, toml::Value::Array(_) | toml::Value::Table(_)) {
                return Err(format!("[petsc] {k}: values must be strings, numbers or booleans"));
            }
        }
        Ok(())
    }
}
