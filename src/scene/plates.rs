//! `[plates]`: the compression–release experiment's rigid plates (geometry, loading, drainage
//! and the plates' permeability); their keys and checks.

use super::key::{Key, Section, Unset};
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// The compression–release experiment (model.md §1, §5): rigid, flat, impermeable,
/// frictionless plates; the reference sphere (radius R, centre (0, 0, R)) touches the lower plate
/// (top face z = 0, moving up by u(t), eq. (53)) and the fixed upper plate (bottom face z = 2R).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlatesSpec {
    /// Radius R of the reference sphere (must match the mesh).
    pub radius: f64,
    /// Surface group that can touch the plates (and drains where it does not).
    #[serde(default = "default_surface")]
    pub group: String,
    /// ũ_max = u_max / (2R): the lower plate rises by u_max.
    pub compression: f64,
    /// Duration of each ramp (s).
    pub t_ramp: f64,
    /// End of the release ramp (s); the rest lasts until time.t_end.
    pub t_end: f64,
    /// p = 0 on the surface out of contact (false: sealed aggregate).
    #[serde(default = "yes")]
    pub drainage: bool,
    /// Point group of the bottom pole, kept on the lower plate (bilateral contact).
    #[serde(default = "default_anchor")]
    pub anchor: String,
    /// γ of the free-surface drainage conductance β_max = γ k0 / h (stiff Robin, p ≈ 0).
    #[serde(default = "default_penalty")]
    pub drainage_penalty: f64,
    /// Gap (µm) over which drainage opens as a contact separates (default 0.01 R).
    #[serde(default)]
    pub seal_gap: Option<f64>,
    /// Which gap opens the drainage within a step: the step predictor's (default) or the
    /// Newton iterate's (fully implicit; numerics.md, "Drainage that follows contact").
    #[serde(default)]
    pub drainage_gap: DrainageGap,
    /// The plates' permeability k_β (µm⁴/(nN s); the paper's Table 1: 3.7729e-4): fluid leaves
    /// through the contact area with the conductance k_β / `thickness` (a Robin outflow; the
    /// plates are impermeable when it is omitted).
    #[serde(default)]
    pub permeability: Option<f64>,
    /// The plates' thickness L (µm) that the outflow through them crosses (with `permeability`).
    #[serde(default)]
    pub thickness: Option<f64>,
    /// The material point X_U of the `probe_p` and `probe_porosity` columns (reference
    /// coordinates, µm; default the paper's (0.4 R, 0, 1.9 R), 1.5 µm under the surface).
    #[serde(default)]
    pub probe_point: Option<[f64; 3]>,
}

/// The gap that sets a surface vertex's drainage conductance during a step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DrainageGap {
    /// The step predictor's gap (semi-implicit: fixed during the Newton iteration).
    #[default]
    Predicted,
    /// The current iterate's gap (fully implicit, differentiated exactly).
    Current,
}

fn default_penalty() -> f64 {
    100.0
}

fn default_anchor() -> String {
    "pole_bottom".into()
}

fn default_surface() -> String {
    "surface".into()
}

fn yes() -> bool {
    true
}

impl PlatesSpec {
    /// Geometry, loading, drainage and the plates' permeability.
    pub(super) fn validate(&self) -> Result<(), String> {
        RADIUS.check(self.radius)?;
        COMPRESSION.check(self.compression)?;
        T_RAMP.check(self.t_ramp)?;
        if !(self.t_end.is_finite() && self.t_end >= 2.0 * self.t_ramp) {
            return Err(format!("plates.t_end = {}: must be at least 2 t_ramp = {}", self.t_end, 2.0 * self.t_ramp));
        }
        DRAINAGE_PENALTY.check(self.drainage_penalty)?;
        if let Some(g) = self.seal_gap {
            SEAL_GAP.check(g)?;
        }
        match (self.permeability, self.thickness) {
            (Some(k), Some(l)) => {
                PERMEABILITY.check(k)?;
                THICKNESS.check(l)?;
                if !self.drainage && k > 0.0 {
                    return Err("plates.permeability: the plates drain the contact area, but plates.drainage = false \
                                seals the aggregate (drop one of them)"
                        .into());
                }
            }
            (Some(_), None) => {
                return Err("plates.permeability needs plates.thickness (µm), the plates' thickness".into())
            }
            (None, Some(_)) => return Err("plates.thickness is only used with plates.permeability: set both".into()),
            (None, None) => {}
        }
        for x in self.probe_point.iter().flatten() {
            PROBE_POINT.check(*x)?;
        }
        Ok(())
    }
}

const RADIUS: Key =
    Key::new("plates.radius", "µm", Unset::Required, "radius R of the reference sphere (must match the mesh)")
        .range(Range::POSITIVE);
const COMPRESSION: Key =
    Key::new("plates.compression", "", Unset::Required, "ũ_max = u_max / (2R): the lower plate rises by u_max")
        .range(Range::new(0.0, true, 1.0, false, "must lie in [0, 1)"));
const T_RAMP: Key = Key::new("plates.t_ramp", "s", Unset::Required, "duration of each ramp (compression, release)")
    .range(Range::POSITIVE);
const DRAINAGE_PENALTY: Key = Key::new(
    "plates.drainage_penalty",
    "",
    Unset::Value("100.0"),
    "γ of the free-surface drainage conductance β_max = γ k0 / h (a stiff Robin condition, p ≈ 0)",
)
.range(Range::POSITIVE);
const SEAL_GAP: Key =
    Key::new("plates.seal_gap", "µm", Unset::Absent("0.01 R"), "gap over which drainage opens as a contact separates")
        .range(Range::POSITIVE);
const PERMEABILITY: Key = Key::new(
    "plates.permeability",
    "µm⁴/(nN s)",
    Unset::Absent("impermeable plates"),
    "the plates' permeability k_β: outflow through the contact area with conductance k_β / thickness",
)
.range(Range::NON_NEGATIVE.says("must be >= 0"))
.rule("with `thickness`; not with drainage = false");
const THICKNESS: Key =
    Key::new("plates.thickness", "µm", Unset::Absent(""), "the plates' thickness that the outflow crosses")
        .range(Range::POSITIVE)
        .rule("with `permeability`");
const PROBE_POINT: Key = Key::new(
    "plates.probe_point",
    "µm",
    Unset::Absent("(0.4 R, 0, 1.9 R)"),
    "the material point of the `probe_p` and `probe_porosity` columns (reference coordinates)",
)
.range(Range::FINITE);

pub(super) const SECTION: Section = Section {
    title: "[plates]",
    about: "The compression–release experiment: rigid, flat, frictionless plates; the reference sphere (radius \
            R, centre (0, 0, R)) touches the lower plate (z = 0, rising by u(t)) and the fixed upper plate \
            (z = 2R). The load ramps up over t_ramp, holds, ramps down to t_end, and rests until time.t_end.",
    keys: &[
        RADIUS,
        Key::new("plates.group", "", Unset::Value("\"surface\""), "the surface group that can touch the plates"),
        COMPRESSION,
        T_RAMP,
        Key::new("plates.t_end", "s", Unset::Required, "end of the release ramp").rule("≥ 2 t_ramp"),
        Key::new("plates.drainage", "", Unset::Value("true"), "p = 0 on the surface out of contact (false: sealed)"),
        Key::new("plates.anchor", "", Unset::Value("\"pole_bottom\""), "the point group kept on the lower plate"),
        DRAINAGE_PENALTY,
        SEAL_GAP,
        Key::new(
            "plates.drainage_gap",
            "",
            Unset::Value("\"predicted\""),
            "the gap that opens drainage in a step: the predictor's, or `current` (the Newton iterate's)",
        ),
        PERMEABILITY,
        THICKNESS,
        PROBE_POINT,
    ],
};
