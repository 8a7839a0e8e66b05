//! `[time]`, `[output]` and `[initial]`: the steps, what is written when, and the state at
//! t = 0; their keys and their checks.

use super::key::{Key, Section, Unset};
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// The longest experiment (s): two days. A longer time is unusual (`plausible`), and a plates
/// table that lasts longer is in ms.
pub(super) const LONGEST_USUAL_TIME: f64 = 2.0 * 86400.0;

/// Time stepping: geometric growth from `dt` to `dt_max`, landing exactly on `t_end` and on
/// every time in `land_on`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TimeSpec {
    pub(crate) t_end: f64,
    /// First step (s).
    pub(crate) dt: f64,
    #[serde(default)]
    pub(crate) dt_max: Option<f64>,
    /// Largest step during the plates' loading ramp (0 to `plates.t_ramp`): backward Euler
    /// over-integrates a flow that rises through the ramp (the remodelling) by a share of
    /// Δt / t, which geometric growth keeps constant; a cap makes it shrink.
    #[serde(default)]
    pub(crate) dt_max_ramp: Option<f64>,
    /// dt_{n+1} = min(growth · dt_n, dt_max); 1 = constant steps. With `error_tolerance`, only
    /// where there is no error estimate (the first step after a kink of the loading).
    #[serde(default = "one")]
    pub(crate) growth: f64,
    /// Choose the steps by a local error estimate (see `driver::rate::StepRate::error`): the
    /// tolerance relative to each field's magnitude. Absent: geometric growth.
    #[serde(default)]
    pub(crate) error_tolerance: Option<f64>,
    #[serde(default)]
    pub(crate) land_on: Vec<f64>,
    /// The end times of the steps, in order: the run takes exactly these (a failed solve still
    /// cuts a step, whose rest then ends at the next of them), the step controller and the
    /// growth unused. Replaying one run's accepted steps (its history.csv `time` column) makes
    /// runs at nearby parameters take the same steps, so that a result is a smooth function of
    /// the parameters (calibration's finite differences); adaptive steps chosen anew would jump.
    #[serde(default)]
    pub(crate) steps: Vec<f64>,
    /// Retries (each cutting the step, by 0.25 by default) allowed when a solve fails.
    #[serde(default = "default_retries")]
    pub(crate) max_retries: usize,
    /// A step cut below this (s) by failed solves ends the run with an error: the solve is not
    /// converging there, and ever shorter steps would only make the run crawl (default 1e-6 dt).
    #[serde(default)]
    pub(crate) dt_min: Option<f64>,
}

fn one() -> f64 {
    1.0
}
fn default_retries() -> usize {
    8
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct OutputSpec {
    /// Write fields every N steps (and always the last); 0 = last step only.
    #[serde(default = "default_every")]
    pub(crate) fields_every: usize,
    /// Write fields at all (large runs in studies may only want history.csv).
    #[serde(default = "yes")]
    pub(crate) fields: bool,
    /// Also write fields at these times (the time steps land on them).
    #[serde(default)]
    pub(crate) fields_at: Vec<f64>,
    /// Write a checkpoint every N steps (0: not by steps).
    #[serde(default = "default_checkpoint_every")]
    pub(crate) checkpoint_every: usize,
    /// Write a checkpoint when this much wall time (minutes) has passed since the last (0: not
    /// by time).
    #[serde(default = "default_checkpoint_minutes")]
    pub(crate) checkpoint_minutes: f64,
}
fn default_checkpoint_every() -> usize {
    25
}
fn default_checkpoint_minutes() -> f64 {
    10.0
}
impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            fields_every: default_every(),
            fields: yes(),
            fields_at: vec![],
            checkpoint_every: default_checkpoint_every(),
            checkpoint_minutes: default_checkpoint_minutes(),
        }
    }
}
fn default_every() -> usize {
    1
}
fn yes() -> bool {
    true
}

/// An affine initial displacement u(X, 0) = G X (a homogeneous deformation F = I + G), e.g. a
/// stretch applied at t = 0 and then held by the boundary conditions.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct InitialSpec {
    /// G = Grad u, rows i: `G[i][j]` = ∂u_i/∂X_j.
    pub(crate) displacement_gradient: [[f64; 3]; 3],
}

/// The smallest step, relative to `dt`, when `time.dt_min` is not given.
pub(crate) const DT_MIN_RELATIVE: f64 = 1e-6;

impl TimeSpec {
    /// The smallest step a failed solve may cut to: `dt_min`, or [`DT_MIN_RELATIVE`] dt.
    pub(crate) fn dt_min(&self) -> f64 {
        self.dt_min.unwrap_or(DT_MIN_RELATIVE * self.dt)
    }

    /// The largest step: `dt_max`, or the run's length (no cap).
    pub(crate) fn dt_max(&self) -> f64 {
        self.dt_max.unwrap_or(self.t_end)
    }

    /// Positive steps and end time, growth >= 1, landing times (and `fields_at`) inside the
    /// run; a ramp cap only with plates (`plates`: the scene has them).
    pub(super) fn validate(&self, fields_at: &[f64], plates: bool) -> Result<(), String> {
        for &a in self.land_on.iter().chain(fields_at) {
            if !(a > 0.0 && a <= self.t_end) {
                return Err(format!(
                    "time.land_on / output.fields_at: {a} must lie in (0, time.t_end = {}]",
                    self.t_end
                ));
            }
        }
        T_END.check(self.t_end)?;
        DT.check(self.dt)?;
        let mut last = 0.0;
        for (i, &s) in self.steps.iter().enumerate() {
            if !(s > last && s <= self.t_end) {
                return Err(format!(
                    "time.steps[{i}] = {s}: the step end times must increase from above 0 to at most time.t_end = {}",
                    self.t_end
                ));
            }
            last = s;
        }
        if let Some(m) = self.dt_max_ramp {
            DT_MAX_RAMP.check(m)?;
            if !plates {
                return Err(
                    "time.dt_max_ramp caps the steps of the plates' loading ramp: the scene has no [plates]".into()
                );
            }
            if self.dt > m {
                return Err(format!(
                    "time.dt = {} exceeds time.dt_max_ramp = {m}: the first step must be <= it",
                    self.dt
                ));
            }
        }
        if let Some(m) = self.dt_max {
            DT_MAX.check(m)?;
            if self.dt > m {
                return Err(format!(
                    "time.dt = {} exceeds time.dt_max = {m}: the first step must be <= dt_max",
                    self.dt
                ));
            }
        }
        if let Some(e) = self.error_tolerance {
            ERROR_TOLERANCE.check(e)?;
        }
        if let Some(m) = self.dt_min {
            DT_MIN.check(m)?;
            if m >= self.dt {
                return Err(format!("time.dt_min = {m}: must be below the first step time.dt = {}", self.dt));
            }
        }
        GROWTH.check(self.growth)
    }
}

impl OutputSpec {
    /// The checkpoint interval.
    pub(super) fn validate(&self) -> Result<(), String> {
        CHECKPOINT_MINUTES.check(self.checkpoint_minutes)
    }
}

impl InitialSpec {
    /// A finite displacement gradient with det(I + G) > 0.
    pub(super) fn validate(&self) -> Result<(), String> {
        for g in self.displacement_gradient.iter().flatten() {
            DISPLACEMENT_GRADIENT.check(*g)?;
        }
        let f = nalgebra::Matrix3::from_fn(|i, j| self.displacement_gradient[i][j] + if i == j { 1.0 } else { 0.0 });
        if f.determinant() <= 0.0 {
            return Err(format!("initial.displacement_gradient: det(I + G) = {} must be > 0", f.determinant()));
        }
        Ok(())
    }
}

const T_END: Key = Key::new("time.t_end", "s", Unset::Required, "end of the run").range(Range::POSITIVE);
const DT: Key = Key::new("time.dt", "s", Unset::Required, "the first step, and again after each kink of the loading")
    .range(Range::POSITIVE);
const DT_MAX: Key =
    Key::new("time.dt_max", "s", Unset::Absent("no cap"), "the largest step").range(Range::POSITIVE).rule("≥ dt");
const DT_MAX_RAMP: Key = Key::new(
    "time.dt_max_ramp",
    "s",
    Unset::Absent("no cap"),
    "the largest step during the plates' loading ramp (backward Euler over-integrates the remodelling there)",
)
.range(Range::POSITIVE)
.rule("≥ dt; needs [plates]")
.enters("numerics.md: Time integration");
const GROWTH: Key =
    Key::new("time.growth", "", Unset::Value("1.0"), "dt_{n+1} = min(growth dt_n, dt_max); 1: constant steps")
        .range(Range::new(1.0, true, f64::INFINITY, false, "must be >= 1"));
const ERROR_TOLERANCE: Key = Key::new(
    "time.error_tolerance",
    "",
    Unset::Absent("geometric growth"),
    "choose the steps by a local error estimate, relative to each field's magnitude",
)
.range(Range::POSITIVE)
.enters("numerics.md: Time integration");
const DT_MIN: Key = Key::new(
    "time.dt_min",
    "s",
    Unset::Absent("1e-6 dt"),
    "a step cut below this by failed solves ends the run with an error",
)
.range(Range::POSITIVE)
.rule("< dt");

pub(super) const TIME_SECTION: Section = Section {
    title: "[time]",
    enters: "numerics.md: Time integration",
    about: "Steps grow geometrically from `dt` to `dt_max` (or follow an error estimate), landing exactly on \
            `t_end`, on `land_on` and on the kinks of the loading.",
    keys: &[
        T_END,
        DT,
        DT_MAX,
        DT_MAX_RAMP,
        GROWTH,
        ERROR_TOLERANCE,
        Key::new("time.land_on", "s", Unset::Value("[]"), "times the steps land on exactly").rule("in (0, t_end]"),
        Key::new(
            "time.steps",
            "s",
            Unset::Value("[]"),
            "the end times of the steps to take, replacing the growth and the error control (a run's history.csv `time`)",
        )
        .rule("increasing, in (0, t_end]"),
        Key::new("time.max_retries", "", Unset::Value("8"), "retries of a failed step, each cutting it to 1/4")
            .rule("an integer ≥ 0"),
        DT_MIN,
    ],
};

const CHECKPOINT_MINUTES: Key = Key::new(
    "output.checkpoint_minutes",
    "min",
    Unset::Value("10.0"),
    "a checkpoint when this much wall time has passed since the last (0: not by time)",
)
.range(Range::NON_NEGATIVE.says("must be >= 0 (0: not by time)"));

pub(super) const OUTPUT_SECTION: Section = Section {
    title: "[output]",
    enters: "reference-run-directory.md: Files",
    about: "history.csv gets a row every step; the fields and checkpoints are written as set here.",
    keys: &[
        Key::new(
            "output.fields_every",
            "",
            Unset::Value("1"),
            "fields every N steps, and always the last (0: the last only)",
        )
        .rule("an integer ≥ 0"),
        Key::new("output.fields", "", Unset::Value("true"), "write fields at all"),
        Key::new(
            "output.fields_at",
            "s",
            Unset::Value("[]"),
            "also write fields at these times (the steps land on them)",
        )
        .rule("in (0, time.t_end]"),
        Key::new("output.checkpoint_every", "", Unset::Value("25"), "a checkpoint every N steps (0: not by steps)")
            .rule("an integer ≥ 0"),
        CHECKPOINT_MINUTES,
    ],
};

const DISPLACEMENT_GRADIENT: Key = Key::new(
    "initial.displacement_gradient",
    "",
    Unset::Required,
    "G = Grad u of the affine initial state u(X, 0) = G X, rows i: G[i][j] = ∂u_i/∂X_j",
)
.range(Range::FINITE)
.rule("det(I + G) > 0");

pub(super) const INITIAL_SECTION: Section = Section {
    title: "[initial]",
    enters: "model.md: Unknowns and weak form",
    about: "The state at t = 0 (default: undeformed, p = 0).",
    keys: &[DISPLACEMENT_GRADIENT],
};

#[cfg(test)]
mod tests {
    use super::super::key::Unset;

    #[test]
    fn the_step_bounds_keys_state_the_defaults() {
        // The key texts are &'static str: they cannot be formatted from the constants, so they are held to them.
        let Unset::Absent(text) = super::DT_MIN.default else { panic!("time.dt_min: its default should be stated") };
        let relative = text.strip_suffix(" dt").and_then(|f| f.parse::<f64>().ok());
        assert_eq!(relative, Some(super::DT_MIN_RELATIVE), "time.dt_min's text: {text}");
        let Unset::Absent(text) = super::DT_MAX.default else { panic!("time.dt_max: its default should be stated") };
        assert_eq!(text, "no cap");
        let time: super::TimeSpec = toml::from_str("dt = 0.5\nt_end = 40.0").unwrap();
        assert_eq!((time.dt_min(), time.dt_max()), (0.5e-6, 40.0));
        let time: super::TimeSpec = toml::from_str("dt = 0.5\nt_end = 40.0\ndt_min = 1e-3\ndt_max = 2.0").unwrap();
        assert_eq!((time.dt_min(), time.dt_max()), (1e-3, 2.0));
    }
}
