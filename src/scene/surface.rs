//! `[surface]`: the tension of the aggregate's boundary (tissue surface tension) and its work of
//! adhesion to the plates, their keys and checks.

use super::key::{Key, Section, Unset};
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// Surface tension γ on the aggregate's boundary: the energy γ ∫ da over its current surface
/// (model.md: Surface tension).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SurfaceSpec {
    /// γ in mN/m (= kPa µm, the solver's unit).
    pub(crate) tension: f64,
    /// The boundary group the tension acts on.
    #[serde(default = "default_group")]
    pub(crate) group: String,
    /// Work of adhesion w to the plates, mN/m: faces on a plate carry γ − w (model.md: Surface
    /// tension). 0: non-adhesive plates.
    #[serde(default)]
    pub(crate) adhesion: f64,
    /// Adhesion range g_a, µm: the gap over which the adhesion switches off (filled in: 0.05 R).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) adhesion_range: Option<f64>,
}

fn default_group() -> String {
    "surface".into()
}

/// The adhesion range's default over R. Why not the seal distance 0.01 R: the attraction
/// w S'/g_a of a short range on the first, tangent contact of a sphere snaps it onto the plate
/// (Newton fails in the first step at w = 5 mN/m, µ = 20 kPa with 0.01 R; converges with 0.05 R);
/// the contact angle away from the contact line does not depend on the range (model.md: Surface
/// tension).
pub(crate) const DEFAULT_ADHESION_RANGE: f64 = 0.05;

/// Tissue surface tensions measured by tensiometry lie around 1–30 mN/m; a value outside
/// [`PLAUSIBLE`] is most likely in another unit.
const PLAUSIBLE: (f64, f64) = (1e-2, 1e3);

impl SurfaceSpec {
    /// The adhesion range's default, [`DEFAULT_ADHESION_RANGE`] × the plates' `radius` R,
    /// filled in when there is adhesion.
    pub(super) fn resolve(&mut self, radius: Option<f64>) {
        if self.adhesion > 0.0 && self.adhesion_range.is_none() {
            self.adhesion_range = radius.map(|r| DEFAULT_ADHESION_RANGE * r);
        }
    }

    /// `plates`: whether the scene has plates (adhesion acts only on faces touching one).
    pub(super) fn validate(&self, plates: bool) -> Result<(), String> {
        TENSION.check(self.tension)?;
        plausible("surface.tension", self.tension)?;
        ADHESION.check(self.adhesion)?;
        let (g, w) = (self.tension, self.adhesion);
        if let Some(r) = self.adhesion_range {
            ADHESION_RANGE.check(r)?;
        }
        if w == 0.0 {
            return Ok(());
        }
        plausible("surface.adhesion", w)?;
        if g == 0.0 {
            return Err(format!(
                "surface.adhesion = {w} without surface.tension: the adhesion lowers the tension γ of the faces on \
                 a plate to γ − w; give surface.tension (mN/m), with w ≤ 2γ"
            ));
        }
        if w > 2.0 * g {
            return Err(format!(
                "surface.adhesion = {w} > 2 × surface.tension = {}: beyond complete wetting (w = 2γ, contact angle \
                 0: cos θ = w/γ − 1 ≤ 1), no contact angle exists; the model needs w ≤ 2γ",
                2.0 * g
            ));
        }
        if !plates {
            return Err(format!(
                "surface.adhesion = {w}: the work of adhesion is to the plates, and this scene has no [plates] (drop \
                 surface.adhesion, or add the plates)"
            ));
        }
        Ok(())
    }
}

/// A tension's magnitude: 0, or within [`PLAUSIBLE`] (outside: the unit mistake, named).
fn plausible(key: &str, g: f64) -> Result<(), String> {
    if g > 0.0 && g < PLAUSIBLE.0 {
        return Err(format!(
            "{key} = {g}: the unit is mN/m (= kPa µm), and tissues measure 1–30 mN/m; a value below {} looks like \
             N/m (write {} mN/m)",
            PLAUSIBLE.0,
            g * 1e3
        ));
    }
    if g > PLAUSIBLE.1 {
        return Err(format!(
            "{key} = {g}: the unit is mN/m (= kPa µm), and tissues measure 1–30 mN/m; a value above {} looks like \
             µN/m (write {} mN/m)",
            PLAUSIBLE.1,
            g * 1e-3
        ));
    }
    Ok(())
}

pub(super) const TENSION: Key =
    Key::new("surface.tension", "mN/m", Unset::Required, "surface tension γ of the aggregate's boundary")
        .range(Range::NON_NEGATIVE)
        .rule("0 or within [0.01, 1000] mN/m (outside: a unit mistake, named)")
        .enters("model.md: Surface tension");
const GROUP: Key = Key::new("surface.group", "", Unset::Value("\"surface\""), "the boundary group the tension acts on");
const ADHESION: Key = Key::new(
    "surface.adhesion",
    "mN/m",
    Unset::Value("0"),
    "work of adhesion w to the plates: faces on a plate carry γ − w (contact angle cos θ = w/γ − 1)",
)
.range(Range::NON_NEGATIVE)
.rule("0, or within [0.01, 1000] mN/m and ≤ 2 × surface.tension (complete wetting); needs [plates]")
.enters("model.md: Surface tension");
const ADHESION_RANGE: Key = Key::new(
    "surface.adhesion_range",
    "µm",
    Unset::Absent("0.05 R (filled in when adhesion > 0)"),
    "gap to a plate over which the adhesion switches off smoothly",
)
.range(Range::POSITIVE)
.enters("model.md: Surface tension");

pub(super) const SECTION: Section = Section {
    title: "surface",
    enters: "model.md: Surface tension",
    about: "Surface tension: the energy γ ∫ da over the aggregate's current boundary (its free surface and the \
            faces on the plates), the faces on a plate lowered to γ − w by the work of adhesion w. Optional; \
            without it, no surface term.",
    keys: &[TENSION, GROUP, ADHESION, ADHESION_RANGE],
};
