//! `[mesh]`: where the mesh comes from (a `.geo` meshed on the fly, or a `.msh`), the body's
//! geometry (solid or a meridian), mirroring and the size parameters; their keys and checks.

use super::key::{Key, Section, Unset};
use crate::range::Range;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Where the mesh comes from: a Gmsh `.geo` source meshed on the fly (cached), or a `.msh` file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// A `.geo` file (relative to the scene file, or the name of one shipped in `meshes/`).
    #[serde(default)]
    pub geo: Option<String>,
    /// A ready Gmsh 4.1 `.msh` file (relative to the scene file).
    #[serde(default)]
    pub file: Option<String>,
    /// `-setnumber` parameters for the `.geo` (R, h, h_pole, ...).
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
    /// Symmetry planes (face groups) to reflect the mesh across, in order: a quarter sphere
    /// mirrored across `["symmetry_x", "symmetry_y"]` is a full sphere with the same elements.
    #[serde(default)]
    pub mirror: Vec<String>,
    /// The body's geometry: `solid` (3-D, tetrahedra) or `axisymmetric` (a body of revolution
    /// about the z axis, meshed on its meridian in the x–z plane with triangles).
    #[serde(default)]
    pub geometry: Geometry,
    /// The `.geo` of the body's meridian, used instead of `geo` when `geometry = "axisymmetric"`
    /// (with the same `params`): so one override switches a scene to its meridian.
    #[serde(default)]
    pub meridian: Option<String>,
    /// `given` (default: the sizes in `params`) or `auto` (the measured best sizes for plate
    /// experiments, scaled by `params.R`; sizes given in `params` win). See [`super::auto`].
    #[serde(default)]
    pub grading: Grading,
}

/// The geometry of a scene's body (see [`MeshSpec::geometry`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Geometry {
    #[default]
    Solid,
    Axisymmetric,
}

impl Geometry {
    /// The mesh family this geometry is discretised with.
    pub fn family(self) -> crate::reference_cell::Family {
        match self {
            Geometry::Solid => crate::reference_cell::Family::Tet10,
            Geometry::Axisymmetric => crate::reference_cell::Family::Tri6,
        }
    }
}

/// How the mesh sizes of a `.geo` are chosen (`mesh.grading`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Grading {
    /// The sizes in `mesh.params`; the `.geo`'s own defaults for the others.
    #[default]
    Given,
    /// The chart's choice scaled by `mesh.params.R` ([`super::auto`]); a size given in
    /// `mesh.params` wins.
    Auto,
}

impl MeshSpec {
    /// The `.geo` source and `.msh` file the geometry uses (one of the two is set).
    pub fn source(&self) -> (Option<&str>, Option<&str>) {
        match (self.geometry, &self.meridian) {
            (Geometry::Axisymmetric, Some(m)) => (Some(m.as_str()), None),
            _ => (self.geo.as_deref(), self.file.as_deref()),
        }
    }

    /// One source, mirror only for solids, finite numbers and positive lengths.
    pub(super) fn validate(&self) -> Result<(), String> {
        match (&self.geo, &self.file) {
            (Some(_), Some(_)) => return Err("[mesh]: give either `geo` or `file`, not both".into()),
            (None, None) => return Err("[mesh]: give `geo` (a .geo source) or `file` (a .msh mesh)".into()),
            _ => {}
        }
        if self.geometry == Geometry::Axisymmetric && !self.mirror.is_empty() {
            return Err(
                "[mesh]: mirror is for solid (3-D) meshes; an axisymmetric meridian is already the whole body".into()
            );
        }
        for (k, v) in &self.params {
            if !v.is_finite() {
                return Err(format!("[mesh.params] {k} = {v} is not a finite number"));
            }
            if LENGTHS.contains(&k.as_str()) {
                LENGTH.check(&format!("[mesh.params] {k}"), *v)?;
            }
        }
        Ok(())
    }
}

/// The `params` that are lengths of the shipped `.geo` files.
const LENGTHS: [&str; 5] = ["R", "h", "h_pole", "H", "W"];
/// What a length in `params` must be.
const LENGTH: Range = Range::POSITIVE.says("a length must be positive");

pub(super) const SECTION: Section = Section {
    title: "[mesh]",
    about: "Where the mesh comes from: `geo` or `file` (one of the two).",
    keys: &[
        Key::new(
            "mesh.geo",
            "",
            Unset::Absent(""),
            "a Gmsh `.geo` source, next to the scene or shipped in `meshes/`, meshed by gmsh and cached",
        )
        .rule("`geo` or `file`, not both"),
        Key::new(
            "mesh.file",
            "",
            Unset::Absent(""),
            "a ready Gmsh 4.1 ASCII mesh (tet4/tet10; tri3/tri6 in the x–z plane for a meridian)",
        ),
        Key::new(
            "mesh.params",
            "µm",
            Unset::Value("{}"),
            "`-setnumber` parameters of the `.geo` (R, h, h_pole, r_pole, H, W, ...)",
        )
        .range(LENGTH)
        .rule("the range is for the lengths R, h, h_pole, H, W; the others finite"),
        Key::new(
            "mesh.mirror",
            "",
            Unset::Value("[]"),
            "symmetry face groups to reflect the mesh across, in order (a quarter → a full sphere)",
        )
        .rule("solid geometry only"),
        Key::new(
            "mesh.geometry",
            "",
            Unset::Value("\"solid\""),
            "`solid` (tetrahedra) or `axisymmetric` (a body of revolution about z, solved on its meridian)",
        ),
        Key::new(
            "mesh.meridian",
            "",
            Unset::Absent(""),
            "the meridian `.geo` used instead of `geo` when `geometry = \"axisymmetric\"` (same params)",
        ),
        Key::new(
            "mesh.grading",
            "",
            Unset::Value("\"given\""),
            "`given` (the sizes in params) or `auto` (the measured best sizes scaled by params.R; a size given wins)",
        )
        .rule("`auto` needs params.R and a `geo`"),
    ],
};
