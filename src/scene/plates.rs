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
pub(crate) struct PlatesSpec {
    /// Radius R of the reference sphere; `mesh.params.R` when absent (filled in when loaded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) radius: Option<f64>,
    /// Surface group that can touch the plates (and drains where it does not).
    #[serde(default = "default_surface")]
    pub(crate) group: String,
    /// ũ_max = u_max / (2R): the lower plate rises by u_max (absent with `table`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) compression: Option<f64>,
    /// The protocol as a table of (t in s, ũ = u / (2R)) rows, linear between them, from
    /// [0, 0]: instead of `compression` and the phases (two compressions, a long hold, ...).
    #[serde(default, skip_serializing_if = "Option::is_none", deserialize_with = "table_rows")]
    pub(crate) table: Option<Vec<[f64; 2]>>,
    /// The protocol's phases (s): the plate rises over `ramp`, holds for `hold`, returns over
    /// `release`; then the aggregate rests until time.t_end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) ramp: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) hold: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) release: Option<f64>,
    /// Deprecated: the duration of both ramps, and the end of the release (read into `ramp`,
    /// `hold` and `release` when the scene is loaded, with a note saying what to write).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) t_ramp: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) t_end: Option<f64>,
    /// p = 0 on the surface out of contact (false: sealed aggregate).
    #[serde(default = "yes")]
    pub(crate) drainage: bool,
    /// Point group of the bottom pole, kept on the lower plate (bilateral contact).
    #[serde(default = "default_anchor")]
    pub(crate) anchor: String,
    /// γ of the free-surface drainage conductance β_max = γ k0 / h (stiff Robin, p ≈ 0).
    #[serde(default = "default_penalty")]
    pub(crate) drainage_penalty: f64,
    /// Gap (µm) over which drainage opens as a contact separates (default 0.01 R).
    #[serde(default)]
    pub(crate) seal_gap: Option<f64>,
    /// Which gap opens the drainage within a step: the step predictor's (default) or the
    /// Newton iterate's (fully implicit; numerics.md, "Drainage that follows contact").
    #[serde(default)]
    pub(crate) drainage_gap: DrainageGap,
    /// The plates' permeability k_β (µm⁴/(nN s); the paper's Table 1: 3.7729e-4): fluid leaves
    /// through the contact area with the conductance k_β / `thickness` (a Robin outflow; the
    /// plates are impermeable when it is omitted).
    #[serde(default)]
    pub(crate) permeability: Option<f64>,
    /// The plates' thickness L (µm) that the outflow through them crosses (with `permeability`).
    #[serde(default)]
    pub(crate) thickness: Option<f64>,
    /// The material point X_U of the `probe_p` and `probe_porosity` columns (reference
    /// coordinates, µm; default the paper's (0.4 R, 0, 1.9 R), 1.5 µm under the surface).
    #[serde(default)]
    pub(crate) probe_point: Option<[f64; 3]>,
    /// The upper plate's protocol (`scene::protocol` rows; µm downwards, or µN): absent, it
    /// stays at z = 2R.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) upper: Option<Vec<super::protocol::ProtocolRow>>,
    /// Which contact path holds the body on the plates: bounds on the surface u_z dofs (default),
    /// or the plates as two plane tools on the general path of `[[tools]]` (a check of it).
    #[serde(default)]
    pub(crate) contact: PlateContact,
}

/// How the plates' contact is solved (issue 53: the plates give the same history either way).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum PlateContact {
    /// Bounds on the surface nodes' u_z: the active-set Newton's plane split.
    #[default]
    Bounds,
    /// Two plane tools, `plate_lower` and `plate_upper`: frames, the curved split, projection.
    Tools,
}

/// The names of the plates' tools under `contact = "tools"` (their history columns too).
pub(crate) const PLATE_TOOLS: [&str; 2] = ["plate_lower", "plate_upper"];

/// The gap that sets a surface vertex's drainage conductance during a step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum DrainageGap {
    /// The step predictor's gap (semi-implicit: fixed during the Newton iteration).
    #[default]
    Predicted,
    /// The current iterate's gap (fully implicit, differentiated exactly).
    Current,
}

/// A table's rows, each exactly two numbers (a third column would otherwise be dropped unseen).
fn table_rows<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<Vec<[f64; 2]>>, D::Error> {
    let rows: Vec<Vec<f64>> = Deserialize::deserialize(d)?;
    rows.iter()
        .enumerate()
        .map(|(i, r)| match r[..] {
            [t, u] => Ok([t, u]),
            _ => Err(serde::de::Error::custom(format!(
                "plates.table row {} = {r:?} has {} number(s): each row is exactly [t (s), ũ = u / (2R)]",
                i + 1,
                r.len()
            ))),
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
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

/// The plate protocol's phases (s): u rises to u_max over `ramp`, holds for `hold`, returns to 0
/// over `release`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Protocol {
    pub(crate) ramp: f64,
    pub(crate) hold: f64,
    pub(crate) release: f64,
}

impl Protocol {
    /// The ends of the ramp, of the hold and of the release.
    pub(crate) fn ends(&self) -> [f64; 3] {
        let hold_end = self.ramp + self.hold;
        [self.ramp, hold_end, hold_end + self.release]
    }
}

/// The keys of a protocol given by its phases (a `plates.table` override replaces them).
pub(crate) const PHASE_KEYS: [&str; 6] = ["compression", "ramp", "hold", "release", "t_ramp", "t_end"];

/// The seal gap's default, relative to R.
pub(crate) const DEFAULT_SEAL_GAP: f64 = 0.01;

/// The default probe point X_U = (0.4 R, 0, 1.9 R): the paper's, 1.5 µm under the upper pole's
/// surface at R = 100 µm.
pub(crate) fn default_probe_point(radius: f64) -> [f64; 3] {
    [0.4 * radius, 0.0, 1.9 * radius]
}

impl PlatesSpec {
    /// R (filled in from `mesh.params.R` when the scene is loaded: NaN before).
    pub(crate) fn radius(&self) -> f64 {
        self.radius.unwrap_or(f64::NAN)
    }

    /// ũ_max: `compression`, or the table's largest ũ (NaN before the scene is loaded).
    pub(crate) fn compression(&self) -> f64 {
        match &self.table {
            Some(rows) => rows.iter().map(|r| r[1]).fold(0.0, f64::max),
            None => self.compression.unwrap_or(f64::NAN),
        }
    }

    /// The plates' tools under `contact = "tools"` (none on the bounds' path).
    pub(crate) fn tool_names(&self) -> &'static [&'static str] {
        match self.contact {
            PlateContact::Bounds => &[],
            PlateContact::Tools => &PLATE_TOOLS,
        }
    }

    /// The plate's path as rows [t, ũ] from [0, 0], linear between them: the table, or the
    /// phases' corners (eq. (53)).
    pub(crate) fn path(&self) -> Vec<[f64; 2]> {
        if let Some(rows) = &self.table {
            return rows.clone();
        }
        let [a, b, c] = self.protocol().ends();
        let top = self.compression();
        vec![[0.0, 0.0], [a, top], [b, top], [c, 0.0]]
    }

    /// The phases (filled in from the deprecated keys when the scene is loaded: NaN before). A
    /// table's: the ramp to its first row at the largest ũ, the hold to its last such row, the
    /// release to the next row at ũ = 0 (or the table's end), as the summary reports them.
    pub(crate) fn protocol(&self) -> Protocol {
        if let Some(rows) = &self.table {
            let top = self.compression();
            let first = rows.iter().position(|r| r[1] == top).unwrap_or(0);
            let last = rows.iter().rposition(|r| r[1] == top).unwrap_or(0);
            let back = rows[last..].iter().position(|r| r[1] == 0.0).map_or(rows.len() - 1, |k| last + k);
            let t = |i: usize| rows[i][0];
            return Protocol { ramp: t(first), hold: t(last) - t(first), release: t(back) - t(last) };
        }
        let nan = f64::NAN;
        Protocol {
            ramp: self.ramp.unwrap_or(nan),
            hold: self.hold.unwrap_or(nan),
            release: self.release.unwrap_or(nan),
        }
    }

    /// What the loading fills in: R from the mesh's `R` unless given; the phases from the
    /// deprecated `t_ramp` (both ramps) and `t_end` (the release's end), each with a note in
    /// `notes` of what to write instead (they may also come as overrides of a scene written with
    /// the phases: `t_end` then moves the release, keeping the ramps); the seal gap and the
    /// probe point at their defaults.
    pub(super) fn resolve(&mut self, mesh_radius: Option<f64>, notes: &mut Vec<String>) -> Result<(), String> {
        let r = match (self.radius, mesh_radius) {
            (Some(r), _) | (None, Some(r)) => r,
            (None, None) => {
                return Err("plates.radius: give the aggregate's radius, as mesh.params.R or plates.radius".into())
            }
        };
        self.radius = Some(r);
        if self.table.is_some() {
            let given = [
                ("compression", self.compression),
                ("ramp", self.ramp),
                ("hold", self.hold),
                ("release", self.release),
                ("t_ramp", self.t_ramp),
                ("t_end", self.t_end),
            ];
            if let Some((key, _)) = given.iter().find(|(_, v)| v.is_some()) {
                return Err(format!(
                    "[plates]: plates.table gives the whole protocol; leave out plates.{key} (or the table)"
                ));
            }
        } else if self.compression.is_none() {
            return Err("[plates]: give plates.compression (ũ_max) with the phases, or plates.table".into());
        } else if self.t_ramp.is_none() && self.t_end.is_none() {
            for (key, v) in [("ramp", self.ramp), ("hold", self.hold), ("release", self.release)] {
                if v.is_none() {
                    return Err(format!(
                        "[plates]: give the protocol's phases ramp, hold and release (s); plates.{key} is missing"
                    ));
                }
            }
        } else {
            self.move_deprecated(notes)?;
        }
        self.seal_gap.get_or_insert(DEFAULT_SEAL_GAP * r);
        self.probe_point.get_or_insert(default_probe_point(r));
        Ok(())
    }

    /// `t_ramp` and `t_end` into `ramp`, `hold` and `release` (see `resolve`).
    fn move_deprecated(&mut self, notes: &mut Vec<String>) -> Result<(), String> {
        let was = [self.t_ramp, self.t_end];
        if let Some(t) = self.t_ramp.take() {
            T_RAMP.check(t)?;
            // The release lasted t_ramp, and ended at t_end.
            let end = self.t_end.or(self.ramp.zip(self.hold).zip(self.release).map(|((a, b), c)| a + b + c));
            self.ramp = Some(t);
            self.release = Some(t);
            self.t_end = end;
        }
        let (Some(ramp), Some(release)) = (self.ramp, self.release) else {
            return Err("plates.t_end is deprecated and needs plates.ramp and plates.release: give ramp, hold and \
                        release (s) instead"
                .into());
        };
        let Some(end) = self.t_end.take() else {
            return Err(
                "plates.t_ramp is deprecated and needs plates.t_end: give ramp, hold and release (s) instead".into()
            );
        };
        let hold = end - ramp - release;
        if !(end.is_finite() && hold >= 0.0) {
            return Err(format!("plates.t_end = {end}: must be at least ramp + release = {}", ramp + release));
        }
        self.hold = Some(hold);
        let given: Vec<String> = [("t_ramp", was[0]), ("t_end", was[1])]
            .iter()
            .filter_map(|(k, v)| v.map(|v| format!("plates.{k} = {v}")))
            .collect();
        notes.push(format!(
            "{} {} deprecated: write plates.ramp = {ramp}, plates.hold = {hold}, plates.release = {release} (the \
             durations of the protocol's phases, s)",
            given.join(" and "),
            if given.len() > 1 { "are" } else { "is" }
        ));
        Ok(())
    }

    /// Geometry, loading, drainage and the plates' permeability (resolved: see `resolve`);
    /// `t_end` is the run's end (a release after it is a warning in `notes`).
    pub(super) fn validate(&self, t_end: f64, notes: &mut Vec<String>) -> Result<(), String> {
        super::mesh::check_radius(RADIUS.name, self.radius())?;
        if let Some(rows) = &self.table {
            check_table(rows, t_end, notes)?;
        } else {
            self.check_phases(t_end, notes)?;
        }
        self.check_drainage()?;
        if let Some(rows) = &self.upper {
            super::protocol::check(UPPER.name, rows)?;
            let displaced = |r: &super::protocol::ProtocolRow| {
                matches!(r.displacement, Some(super::protocol::Displacement::Value(_)))
            };
            if self.contact == PlateContact::Tools && !rows.iter().all(displaced) {
                return Err("plates.contact = \"tools\": the upper plate's force control (and \"held\") is on the \
                            bounds' path only; use contact = \"bounds\" (the default) with such rows in plates.upper"
                    .into());
            }
        }
        for x in self.probe_point.iter().flatten() {
            PROBE_POINT.check(*x)?;
        }
        Ok(())
    }

    /// ũ_max and the phases; a release ending after the run's end is a note.
    fn check_phases(&self, t_end: f64, notes: &mut Vec<String>) -> Result<(), String> {
        check_compression(COMPRESSION.name, self.compression())?;
        let p = self.protocol();
        RAMP.check(p.ramp)?;
        HOLD.check(p.hold)?;
        RELEASE.check(p.release)?;
        let [ramp_end, hold_end, release_end] = p.ends();
        if release_end > t_end {
            let during = if ramp_end >= t_end {
                "the ramp"
            } else if hold_end >= t_end {
                "the hold"
            } else {
                "the release"
            };
            notes.push(format!(
                "the plates' release ends at {release_end} s (ramp {} + hold {} + release {}), after the run's end \
                 time.t_end = {t_end} s: the run stops during {during}",
                p.ramp, p.hold, p.release
            ));
        }
        Ok(())
    }

    /// The drainage's and the plates' permeability's keys.
    fn check_drainage(&self) -> Result<(), String> {
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
        Ok(())
    }
}

/// A protocol table: from [0, 0], times increasing, every ũ in COMPRESSION's range; rows after
/// the run's end are a note. Errors name the row (1-based, as a lab's file counts them).
fn check_table(rows: &[[f64; 2]], t_end: f64, notes: &mut Vec<String>) -> Result<(), String> {
    if rows.len() < 2 {
        return Err(format!("plates.table: {} row(s); give at least [0, 0] and one more [t, ũ]", rows.len()));
    }
    if rows[0] != [0.0, 0.0] {
        return Err(format!(
            "plates.table row 1 = [{}, {}]: the table starts at rest, [0, 0] (t in s, ũ = u / (2R))",
            rows[0][0], rows[0][1]
        ));
    }
    for (i, w) in rows.windows(2).enumerate() {
        let [t, c] = w[1];
        if !(t.is_finite() && t > w[0][0]) {
            return Err(format!(
                "plates.table row {}: time {t} s does not come after row {}'s {} s (rows in increasing time)",
                i + 2,
                i + 1,
                w[0][0]
            ));
        }
        check_compression(&format!("plates.table row {} compression", i + 2), c)?;
    }
    let last = rows[rows.len() - 1][0];
    if t_end < rows[1][0] {
        // A short run of a table (a test, the first instants) is a note; with times beyond what
        // experiments last, the table is in ms.
        let ends = format!(
            "plates.table: the run ends (time.t_end = {t_end} s) before the table's second row, at {} s: the plates \
             do not finish their first move",
            rows[1][0]
        );
        if last > super::time::LONGEST_USUAL_TIME {
            return Err(format!(
                "{ends}, and the table lasts {last} s, longer than experiments do. Its times are seconds \
                 (milliseconds? divide them by 1000)"
            ));
        }
        notes.push(ends);
    }
    if last > t_end {
        notes.push(format!(
            "the plates' table runs to {last} s, after the run's end time.t_end = {t_end} s: its later rows are not reached"
        ));
    }
    Ok(())
}

/// ũ in [0, 1): a value from 1 to 100 is most likely a percentage, and the message says so.
fn check_compression(name: &str, c: f64) -> Result<(), String> {
    COMPRESSION.check_as(name, c).map_err(|m| {
        if (1.0..=100.0).contains(&c) {
            format!("{m}: {c} looks like a percentage ({c}% = {} of 2R)", c / 100.0)
        } else {
            m
        }
    })
}

const RADIUS: Key = Key::new(
    "plates.radius",
    "µm",
    Unset::Absent("mesh.params.R"),
    "radius R of the reference sphere: the plates are at z = 0 and z = 2R (give it for a mesh `file`)",
)
.range(super::mesh::RADIUS_RANGE)
.rule("must match the mesh")
.enters("plates at z = 0 and z = 2R");
const TABLE: Key = Key::new(
    "plates.table",
    "s, —",
    Unset::Absent("the phases below"),
    "the protocol as rows [t, ũ] (ũ = u / (2R)), linear between them: two compressions, a long hold, ...",
)
.rule("from [0, 0], times increasing, ũ in [0, 1); without compression and the phases")
.enters("u(t), eq. (53) as a table");
const COMPRESSION: Key = Key::new(
    "plates.compression",
    "",
    Unset::Absent("required unless plates.table"),
    "ũ_max = u_max / (2R): the lower plate rises by u_max",
)
.range(Range::new(0.0, true, 1.0, false, "must lie in [0, 1)"))
.enters("u(t), eq. (53)");
const RAMP: Key = Key::new(
    "plates.ramp",
    "s",
    Unset::Absent("required unless plates.table"),
    "duration of the loading ramp: u rises linearly from 0 to u_max",
)
.range(Range::POSITIVE)
.enters("u(t), eq. (53)");
const HOLD: Key =
    Key::new("plates.hold", "s", Unset::Absent("required unless plates.table"), "duration of the hold at u_max")
        .range(Range::NON_NEGATIVE.says("must be >= 0"))
        .enters("u(t), eq. (53)");
const RELEASE: Key = Key::new(
    "plates.release",
    "s",
    Unset::Absent("required unless plates.table"),
    "duration of the release: u returns linearly to 0",
)
.range(Range::POSITIVE)
.rule("ramp + hold + release ≤ time.t_end, else a warning")
.enters("u(t), eq. (53)");
const T_RAMP: Key = Key::new(
    "plates.t_ramp",
    "s",
    Unset::Absent(""),
    "deprecated: the duration of both ramps (read as ramp = release = t_ramp)",
)
.range(Range::POSITIVE);
const T_END: Key = Key::new(
    "plates.t_end",
    "s",
    Unset::Absent(""),
    "deprecated: the end of the release (read as hold = t_end − ramp − release)",
)
.rule("≥ ramp + release");
const UPPER: Key = Key::new(
    "plates.upper",
    "s, µm | µN",
    Unset::Absent("fixed at z = 2R"),
    "the upper plate's protocol: rows { t, displacement = µm (downwards) } or { t, force = µN } (pressing, \
     full body; its position is then an unknown), linear between rows of one control, held after the last; a \
     switch is two rows at one time; { t, displacement = \"held\" } holds the position reached",
)
.rule("times in order; force > 0; a switch to force only where the plate touches the body")
.enters("model.md: Force control");
const DRAINAGE_PENALTY: Key = Key::new(
    "plates.drainage_penalty",
    "",
    Unset::Value("100.0"),
    "γ of the free-surface drainage conductance β_max = γ k0 / h (a stiff Robin condition, p ≈ 0)",
)
.range(Range::POSITIVE)
.enters("numerics.md: Contact and drainage");
const SEAL_GAP: Key = Key::new(
    "plates.seal_gap",
    "µm",
    Unset::Absent("0.01 R (filled in)"),
    "gap over which drainage opens as a contact separates",
)
.range(Range::POSITIVE)
.enters("numerics.md: Contact and drainage");
const PERMEABILITY: Key = Key::new(
    "plates.permeability",
    "µm⁴/(nN s)",
    Unset::Absent("impermeable plates"),
    "the plates' permeability k_β: outflow through the contact area with conductance k_β / thickness",
)
.range(Range::NON_NEGATIVE.says("must be >= 0"))
.rule("with `thickness`; not with drainage = false")
.enters("Robin outflow k_β / L");
const THICKNESS: Key =
    Key::new("plates.thickness", "µm", Unset::Absent(""), "the plates' thickness that the outflow crosses")
        .range(Range::POSITIVE)
        .rule("with `permeability`");
const PROBE_POINT: Key = Key::new(
    "plates.probe_point",
    "µm",
    Unset::Absent("(0.4 R, 0, 1.9 R) (filled in)"),
    "the material point of the `probe_p` and `probe_porosity` columns (reference coordinates)",
)
.range(Range::FINITE);

pub(super) const SECTION: Section = Section {
    title: "[plates]",
    enters: "model.md: Rigid plates, contact and drainage",
    about: "The compression–release experiment: rigid, flat, frictionless plates; the reference sphere (radius \
            R, centre (0, 0, R)) touches the lower plate (z = 0, rising by u(t)) and the fixed upper plate \
            (z = 2R). The lower plate rises by u_max = compression · 2R over `ramp`, holds for `hold`, returns over \
            `release`, and the aggregate rests until time.t_end (docs/model.md, \"Rigid plates, contact and drainage\", eq. (53)). R defaults to \
            mesh.params.R, so a scene scales with one key.",
    keys: &[
        RADIUS,
        Key::new("plates.group", "", Unset::Value("\"surface\""), "the surface group that can touch the plates"),
        COMPRESSION,
        TABLE,
        RAMP,
        HOLD,
        RELEASE,
        T_RAMP,
        T_END,
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
        UPPER,
        Key::new(
            "plates.contact",
            "",
            Unset::Value("\"bounds\""),
            "the contact's path: bounds on the surface u_z, or `tools` (the plates as two plane tools, columns \
             plate_lower_* and plate_upper_*: the general path, to check that it gives the same history)",
        )
        .enters("numerics.md: Contact with curved tools"),
    ],
};
