//! `[[bc]]`: boundary conditions on named physical groups, their keys and their checks.

use super::key::{Key, Section, Unset};
use super::mesh::Geometry;
use crate::range::Range;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A boundary condition on a named physical surface group. Exactly one kind per entry.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BoundaryCondition {
    pub(crate) group: String,
    /// Prescribed displacement components, e.g. `{ z = 0.0 }` or `{ x = 0, y = 0, z = 0 }`.
    #[serde(default)]
    pub(crate) displacement: Option<BTreeMap<Axis, f64>>,
    /// Zero normal displacement on an axis-aligned plane (symmetry planes, confined sides).
    #[serde(default)]
    pub(crate) roller: Option<bool>,
    /// Reference-configuration traction: `{ normal = -1.0 }` (t = value·N) or `{ vector = [..] }`.
    #[serde(default)]
    pub(crate) traction: Option<Traction>,
    /// Prescribed pore pressure (kPa), e.g. 0 on a drained surface.
    #[serde(default)]
    pub(crate) pressure: Option<f64>,
    /// Prescribed outward fluid flux Q·N (µm/s); zero flux is the default and needs no entry.
    #[serde(default)]
    pub(crate) flux: Option<f64>,
    /// Only in this geometry (e.g. the quarter's symmetry rollers: `geometry = "solid"`); both if
    /// absent.
    #[serde(default)]
    pub(crate) geometry: Option<Geometry>,
}

/// A Cartesian axis: a displacement component's name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// 0, 1, 2.
    pub(crate) fn index(self) -> usize {
        self as usize
    }
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Traction {
    #[serde(default)]
    pub(crate) normal: Option<f64>,
    #[serde(default)]
    pub(crate) vector: Option<[f64; 3]>,
}

impl BoundaryCondition {
    /// One kind per entry, finite displacements, one traction form; `i` counts from 0.
    pub(super) fn validate(&self, i: usize) -> Result<(), String> {
        let kinds = [
            self.displacement.is_some(),
            self.roller.is_some(),
            self.traction.is_some(),
            self.pressure.is_some(),
            self.flux.is_some(),
        ];
        if kinds.iter().filter(|k| **k).count() != 1 {
            return Err(format!(
                "bc #{} (group \"{}\"): give exactly one of displacement, roller, traction, pressure, flux",
                i + 1,
                self.group
            ));
        }
        for v in self.displacement.iter().flat_map(|d| d.values()) {
            DISPLACEMENT.check_as("displacement", *v)?;
        }
        if let Some(t) = &self.traction {
            if t.normal.is_some() == t.vector.is_some() {
                return Err(format!(
                    "bc #{} (group \"{}\"): traction needs exactly one of `normal` or `vector`",
                    i + 1,
                    self.group
                ));
            }
        }
        Ok(())
    }
}

const DISPLACEMENT: Key = Key::new(
    "bc.displacement",
    "µm",
    Unset::Absent(""),
    "prescribed components, e.g. `{ z = 0.0 }` (on a surface or point group)",
)
.range(Range::FINITE)
.rule("components x, y, z");

pub(super) const SECTION: Section = Section {
    title: "[[bc]]",
    enters: "model.md: Boundary conditions",
    about: "One entry per condition on a physical group, with exactly one of displacement, roller, traction, \
            pressure, flux. A surface without an entry is traction-free and impermeable.",
    keys: &[
        Key::new("bc.group", "", Unset::Required, "the physical group (surface or point) the condition acts on"),
        DISPLACEMENT,
        Key::new("bc.roller", "", Unset::Absent(""), "zero normal displacement on an axis-aligned plane")
            .rule("`true`"),
        Key::new(
            "bc.traction",
            "kPa",
            Unset::Absent(""),
            "reference-configuration traction: `{ normal = t }` (t N) or `{ vector = [tx, ty, tz] }`",
        )
        .rule("one of `normal`, `vector`"),
        Key::new("bc.traction.normal", "kPa", Unset::Absent(""), "the traction t N along the outward normal"),
        Key::new("bc.traction.vector", "kPa", Unset::Absent(""), "the traction vector"),
        Key::new("bc.pressure", "kPa", Unset::Absent(""), "prescribed pore pressure (0: a drained surface)"),
        Key::new("bc.flux", "µm/s", Unset::Absent("zero flux"), "prescribed outward fluid flux Q·N"),
        Key::new("bc.geometry", "", Unset::Absent("both"), "apply only in this geometry (`solid` or `axisymmetric`)"),
    ],
};
