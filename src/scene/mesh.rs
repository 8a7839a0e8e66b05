//! `[mesh]`: where the mesh comes from (a `.geo` meshed on the fly, or a `.msh`), the body's
//! geometry (solid or a meridian), mirroring and the size parameters; their keys and checks.

use super::key::{Key, Section, Unset};
use crate::range::Range;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Where the mesh comes from: a Gmsh `.geo` source meshed on the fly (cached), or a `.msh` file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MeshSpec {
    /// A `.geo` file (relative to the scene file, or the name of one shipped in `meshes/`).
    #[serde(default)]
    pub(crate) geo: Option<String>,
    /// A ready Gmsh 4.1 `.msh` file (relative to the scene file).
    #[serde(default)]
    pub(crate) file: Option<String>,
    /// `-setnumber` parameters for the `.geo` (R, h, h_pole, ...).
    #[serde(default)]
    pub(crate) params: BTreeMap<String, f64>,
    /// Symmetry planes (face groups) to reflect the mesh across, in order: a quarter sphere
    /// mirrored across `["symmetry_x", "symmetry_y"]` is a full sphere with the same elements.
    #[serde(default)]
    pub(crate) mirror: Vec<String>,
    /// The body's geometry: `solid` (3-D, tetrahedra) or `axisymmetric` (a body of revolution
    /// about the z axis, meshed on its meridian in the x–z plane with triangles).
    #[serde(default)]
    pub(crate) geometry: Geometry,
    /// The `.geo` of the body's meridian, used instead of `geo` when `geometry = "axisymmetric"`
    /// (with the same `params`): so one override switches a scene to its meridian.
    #[serde(default)]
    pub(crate) meridian: Option<String>,
    /// `given` (default: the sizes in `params` and `relative_sizes`) or `auto` (the measured best
    /// sizes for plate experiments, relative to `params.R`; sizes given win). See [`super::auto`].
    #[serde(default)]
    pub(crate) grading: Grading,
    /// Mesh sizes relative to `params.R` (`h = 0.2`: a fifth of the radius), so that a scene
    /// keeps its resolution when only R changes; moved into `params` in µm when the scene is
    /// loaded (a size given there in µm wins, so `--set mesh.params.h=10` still works). The
    /// shipped aggregate scenes give them rather than `grading = "auto"`: a refresh of the chart
    /// must not move their meshes, and `reference_axi`'s meridian is finer than the chart's.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub(crate) relative_sizes: BTreeMap<String, f64>,
}

/// The geometry of a scene's body (see [`MeshSpec::geometry`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Geometry {
    #[default]
    Solid,
    Axisymmetric,
}

impl Geometry {
    /// The mesh family this geometry is discretised with.
    pub(crate) fn family(self) -> crate::reference_cell::Family {
        match self {
            Geometry::Solid => crate::reference_cell::Family::Tet10,
            Geometry::Axisymmetric => crate::reference_cell::Family::Tri6,
        }
    }
}

/// How the mesh sizes of a `.geo` are chosen (`mesh.grading`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Grading {
    /// The sizes in `mesh.params`; the `.geo`'s own defaults for the others.
    #[default]
    Given,
    /// The chart's choice scaled by `mesh.params.R` ([`super::auto`]); a size given in
    /// `mesh.params` wins.
    Auto,
}

impl MeshSpec {
    /// The `.geo` source and `.msh` file the geometry uses (one of the two is set).
    pub(crate) fn source(&self) -> (Option<&str>, Option<&str>) {
        match (self.geometry, &self.meridian) {
            (Geometry::Axisymmetric, Some(m)) => (Some(m.as_str()), None),
            _ => (self.geo.as_deref(), self.file.as_deref()),
        }
    }

    /// `relative_sizes` into `params` in µm (R times each; a size in `params` wins).
    pub(super) fn resolve(&mut self) -> Result<(), String> {
        if self.relative_sizes.is_empty() {
            return Ok(());
        }
        let Some(&r) = self.params.get("R") else {
            return Err("mesh.relative_sizes are relative to the aggregate's radius: give mesh.params.R".into());
        };
        for (key, factor) in std::mem::take(&mut self.relative_sizes) {
            RELATIVE_SIZE.check_as(&format!("mesh.relative_sizes.{key}"), factor)?;
            self.params.entry(key).or_insert(factor * r);
        }
        Ok(())
    }

    /// One source, mirror only for solids, finite numbers and positive lengths, and a radius
    /// and sizes of plausible magnitude (a length in mm or nm is named as such).
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
        if let Some(&r) = self.params.get("R") {
            check_radius("mesh.params.R", r)?;
            for k in ["h", "h_pole"] {
                match self.params.get(k) {
                    Some(&h) if h > r => {
                        return Err(format!(
                            "mesh.params.{k} = {h} is larger than the radius R = {r}: the mesh would have a handful \
                             of cells (lengths are µm; or give the sizes relative to R in mesh.relative_sizes)"
                        ))
                    }
                    _ => {}
                }
            }
        }
        Ok(())
    }
}

/// The radius of an aggregate: between 1 µm and 10 mm.
pub(super) const RADIUS_RANGE: Range = Range::new(1.0, true, 1e4, true, "must lie in [1, 10000] µm");

/// Ok if `r` (µm) is a plausible radius; else the message names the likely unit mistake.
pub(super) fn check_radius(name: &str, r: f64) -> Result<(), String> {
    RADIUS_RANGE.check(name, r).map_err(|m| {
        if r > 0.0 && r < 1.0 {
            format!("{m}: {r} looks like mm ({r} mm = {} µm); lengths are µm", r * 1000.0)
        } else if r > 1e4 {
            format!("{m}: {r} looks like nm ({r} nm = {} µm); lengths are µm", r / 1000.0)
        } else {
            m
        }
    })
}

/// What a relative size must be.
const RELATIVE_SIZE: Key = Key::new(
    "mesh.relative_sizes",
    "R",
    Unset::Absent("none"),
    "mesh lengths as fractions of params.R: any length of `params` (h, h_pole, r_pole, h_surf, w_surf, ...)",
)
.range(Range::new(0.0, false, 1.0, true, "must lie in (0, 1] (a fraction of R)"))
.rule("needs params.R; a size in params (µm) wins");

/// The `params` that are lengths of the shipped `.geo` files.
const LENGTHS: [&str; 5] = ["R", "h", "h_pole", "H", "W"];
/// What a length in `params` must be.
const LENGTH: Range = Range::POSITIVE.says("a length must be positive");

pub(super) const SECTION: Section = Section {
    title: "[mesh]",
    enters: "reference-scene-files.md: Shipped meshes",
    about: "Where the mesh comes from: `geo` or `file` (one of the two). The sizes are µm in `params`, or \
            fractions of the radius in `relative_sizes` (the shipped aggregate scenes: a copy with another R keeps \
            its resolution relative to R).",
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
            "`given` (the sizes in params and relative_sizes) or `auto` (the chart's best sizes relative to params.R; a size given wins)",
        )
        .rule("`auto` needs params.R and a `geo`"),
        RELATIVE_SIZE,
        Key::new("mesh.params.R", "µm", Unset::Absent(""), "the aggregate's radius (sphere `.geo` files); plates.radius follows it")
            .range(RADIUS_RANGE),
        Key::new("mesh.params.h", "µm", Unset::Absent("the `.geo`'s"), "the bulk mesh size").rule("≤ R"),
        Key::new("mesh.params.h_pole", "µm", Unset::Absent("the `.geo`'s"), "the mesh size at the poles (the plate contacts)")
            .rule("≤ R"),
        Key::new("mesh.params.r_pole", "µm", Unset::Absent("the `.geo`'s"), "the distance from a pole over which h_pole blends into h"),
        Key::new(
            "mesh.params.h_surf",
            "µm",
            Unset::Absent("h (no grading)"),
            "sphere `.geo` files: the mesh size on the whole curved surface, on when below h (resolves the pressure \
             layer under the drained surface, which the peak force depends on)",
        ),
        Key::new("mesh.params.w_surf", "µm", Unset::Absent("0.3 R"), "the depth over which h_surf grows back to h"),
        Key::new(
            "mesh.params.h_edge",
            "µm",
            Unset::Absent("h (no grading)"),
            "sphere `.geo` files: the mesh size at the contact edges (the rings where the contact patch ends at the \
             peak force), on when below h",
        ),
        Key::new("mesh.params.r_edge", "µm", Unset::Absent("0.62 R"), "the reference radius of the contact-edge rings"),
        Key::new("mesh.params.w_edge", "µm", Unset::Absent("0.25 R"), "the distance over which h_edge grows back to h"),
        Key::new(
            "mesh.params.H",
            "µm",
            Unset::Absent("1 (`block_meridian.geo`: 1000)"),
            "`column.geo`, `column_meridian.geo`, `block_meridian.geo`: the column's or block's height",
        ),
        Key::new(
            "mesh.params.W",
            "µm",
            Unset::Absent("0.1 H (`block_meridian.geo`: H)"),
            "the column's width (`column.geo`, square section) or radius (`column_meridian.geo`, `block_meridian.geo`)",
        ),
        Key::new(
            "mesh.params.h_c",
            "µm",
            Unset::Absent("H / 200"),
            "`block_meridian.geo`: the mesh size within d_c of the top of the axis, where a tool indents",
        ),
        Key::new("mesh.params.d_c", "µm", Unset::Absent("20 h_c"), "`block_meridian.geo`: the radius of the finest region"),
        Key::new(
            "mesh.params.w_c",
            "µm",
            Unset::Absent("H / 2"),
            "`block_meridian.geo`: the distance over which the size grows from h_c to h",
        ),
        Key::new(
            "mesh.params.h_top",
            "µm",
            Unset::Absent("h"),
            "the columns' vertical element size at the top (the drained face), graded from h at the bottom",
        ),
        Key::new("mesh.params.L", "µm", Unset::Absent("1"), "`block.geo`: the cube's edge (its h defaults to L)"),
    ],
};
