//! `[[probe]]` and `[verification]`: the scalar columns a run adds to `history.csv` (values at
//! points or means over groups, and exact solutions next to them); their keys and checks.

use super::key::{Key, Section, Unset};
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// A scalar observable written to `history.csv` each step.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Probe {
    /// Column name.
    pub(crate) name: String,
    /// `p`, `ux`, `uy` or `uz`.
    pub(crate) field: ProbeField,
    /// Value at this reference point ...
    #[serde(default)]
    pub(crate) point: Option<[f64; 3]>,
    /// ... or the mean over this surface group.
    #[serde(default)]
    pub(crate) group: Option<String>,
    /// The column holds value / scale (e.g. the applied load, to normalise).
    #[serde(default = "one")]
    pub(crate) scale: f64,
}

fn one() -> f64 {
    1.0
}

/// What a probe reads: the pore pressure or a displacement component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum ProbeField {
    P,
    Ux,
    Uy,
    Uz,
}

impl std::fmt::Display for ProbeField {
    /// The scene's spelling.
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            ProbeField::P => "p",
            ProbeField::Ux => "ux",
            ProbeField::Uy => "uy",
            ProbeField::Uz => "uz",
        })
    }
}

/// Adds exact-solution columns next to the probes, for verification scenes.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
pub(crate) enum Verification {
    /// Columns `<probe>_exact` for probes named `p_bottom` (pressure at z = 0, normalised by the
    /// load) and `settlement` (top displacement, downward positive).
    Terzaghi { height: f64, load: f64 },
    /// Column `p_center_exact` (centre pressure normalised by the load).
    Cryer { radius: f64, load: f64 },
}

impl Probe {
    /// One location, a finite non-zero scale.
    pub(super) fn validate(&self) -> Result<(), String> {
        if self.point.is_some() == self.group.is_some() {
            return Err(format!("probe \"{}\": give exactly one of `point` or `group`", self.name));
        }
        if self.scale == 0.0 || !self.scale.is_finite() {
            return Err(format!("probe \"{}\": scale must be finite and non-zero", self.name));
        }
        Ok(())
    }
}

impl Verification {
    /// A positive length and a finite load.
    pub(super) fn validate(&self) -> Result<(), String> {
        let (key, length, load) = match self {
            Verification::Terzaghi { height, load } => (HEIGHT, height, load),
            Verification::Cryer { radius, load } => (RADIUS, radius, load),
        };
        key.check_as("verification length", *length)?;
        LOAD.check_as("verification load", *load)
    }
}

pub(super) const PROBE_SECTION: Section = Section {
    title: "[[probe]]",
    enters: "reference-run-directory.md: history.csv columns",
    about: "A column of history.csv: a field's value at a reference point, or its mean over a surface group.",
    keys: &[
        Key::new("probe.name", "", Unset::Required, "the column's name"),
        Key::new("probe.field", "", Unset::Required, "`p`, `ux`, `uy` or `uz`"),
        Key::new("probe.point", "µm", Unset::Absent(""), "the reference point read").rule("`point` or `group`"),
        Key::new("probe.group", "", Unset::Absent(""), "the surface group averaged over"),
        Key::new("probe.scale", "", Unset::Value("1.0"), "the column holds value / scale (the load, to normalise)")
            .rule("finite, not 0"),
    ],
};

const HEIGHT: Key =
    Key::new("verification.height", "µm", Unset::Required, "the column's height (`terzaghi`)").range(Range::POSITIVE);
const RADIUS: Key =
    Key::new("verification.radius", "µm", Unset::Required, "the sphere's radius (`cryer`)").range(Range::POSITIVE);
const LOAD: Key = Key::new("verification.load", "kPa", Unset::Required, "the applied load").range(Range::FINITE);

pub(super) const VERIFICATION_SECTION: Section = Section {
    title: "[verification]",
    enters: "verification.md: Shipped scenes",
    about: "Exact-solution columns next to the probes: `<probe>_exact` for `p_bottom` and `settlement` \
            (Terzaghi), `p_center_exact` (Cryer).",
    keys: &[Key::new("verification.kind", "", Unset::Required, "`terzaghi` or `cryer`"), HEIGHT, RADIUS, LOAD],
};
