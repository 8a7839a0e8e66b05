//! The whole scene: its sections, each the type of its own file (checked in `validate`).

use super::bc::BoundaryCondition;
use super::drainage::DrainageSpec;
use super::material::Material;
use super::medium::MediumSpec;
use super::mesh::MeshSpec;
use super::numerics::{FemSpec, SolverSpec};
use super::observe::{Probe, Verification};
use super::plates::PlatesSpec;
use super::surface::SurfaceSpec;
use super::time::{InitialSpec, OutputSpec, TimeSpec};
use super::tools::ToolSpec;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A whole scene. Sections are grouped by concern.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Scene {
    /// Short name (default: the file stem); names the run directory.
    #[serde(default)]
    pub(crate) name: String,
    #[serde(default)]
    pub(crate) description: String,
    pub(crate) mesh: MeshSpec,
    pub(crate) material: Material,
    #[serde(default)]
    pub(crate) bc: Vec<BoundaryCondition>,
    pub(crate) time: TimeSpec,
    #[serde(default)]
    pub(crate) output: OutputSpec,
    #[serde(default)]
    pub(crate) probe: Vec<Probe>,
    #[serde(default)]
    pub(crate) verification: Option<Verification>,
    /// Rigid plates squeezing the aggregate (contact, drainage, loading).
    #[serde(default)]
    pub(crate) plates: Option<PlatesSpec>,
    /// Rigid tools of revolution (an indenter, a pipette, planes), with exact frictionless contact.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) tools: Vec<ToolSpec>,
    /// Surface tension of the aggregate's boundary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) surface: Option<SurfaceSpec>,
    /// The liquid the aggregate sits in (buoyancy, the drained pores' pressure).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) medium: Option<MediumSpec>,
    /// The surface drainage of a scene without plates (sealed where a sealing tool touches it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) drainage: Option<DrainageSpec>,
    #[serde(default)]
    pub(crate) solver: SolverSpec,
    #[serde(default)]
    pub(crate) fem: FemSpec,
    /// The state at t = 0 (default: undeformed, p = 0).
    #[serde(default)]
    pub(crate) initial: Option<InitialSpec>,
    /// PETSc options without the leading dash: `ksp_rtol = 1e-10`, `ksp_monitor = true`.
    #[serde(default)]
    pub(crate) petsc: BTreeMap<String, toml::Value>,
}

impl Scene {
    /// The names of the tools the contact holds the body with, in the tool set's order: the
    /// `[[tools]]`, then the plates' under `plates.contact = "tools"` (their history columns).
    pub(crate) fn tool_names(&self) -> impl Iterator<Item = &str> {
        let plates = self.plates.as_ref().map_or(&[][..], |p| p.tool_names());
        self.tools.iter().map(|t| t.name.as_str()).chain(plates.iter().copied())
    }
}
