//! `[surface]`: the tension of the aggregate's boundary (tissue surface tension), its keys and
//! checks.

use super::key::{Key, Section, Unset};
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// Surface tension γ on the aggregate's boundary: the energy γ ∫ da over its current surface
/// (model.md: Surface tension).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    /// γ in mN/m (= kPa µm, the solver's unit).
    pub tension: f64,
    /// The boundary group the tension acts on.
    #[serde(default = "default_group")]
    pub group: String,
}

fn default_group() -> String {
    "surface".into()
}

/// Tissue surface tensions measured by tensiometry lie around 1–30 mN/m; a value outside
/// [`PLAUSIBLE`] is most likely in another unit.
const PLAUSIBLE: (f64, f64) = (1e-2, 1e3);

impl SurfaceSpec {
    pub(super) fn validate(&self) -> Result<(), String> {
        TENSION.check(self.tension)?;
        let g = self.tension;
        if g > 0.0 && g < PLAUSIBLE.0 {
            return Err(format!(
                "surface.tension = {g}: the unit is mN/m (= kPa µm), and tissues measure 1–30 mN/m; a value below \
                 {} looks like N/m (write {} mN/m)",
                PLAUSIBLE.0,
                g * 1e3
            ));
        }
        if g > PLAUSIBLE.1 {
            return Err(format!(
                "surface.tension = {g}: the unit is mN/m (= kPa µm), and tissues measure 1–30 mN/m; a value above \
                 {} looks like µN/m (write {} mN/m)",
                PLAUSIBLE.1,
                g * 1e-3
            ));
        }
        Ok(())
    }
}

pub(super) const TENSION: Key =
    Key::new("surface.tension", "mN/m", Unset::Required, "surface tension γ of the aggregate's boundary")
        .range(Range::NON_NEGATIVE)
        .rule("0 or within [0.01, 1000] mN/m (outside: a unit mistake, named)")
        .enters("model.md: Surface tension");
const GROUP: Key = Key::new("surface.group", "", Unset::Value("\"surface\""), "the boundary group the tension acts on");

pub(super) const SECTION: Section = Section {
    title: "surface",
    enters: "model.md: Surface tension",
    about: "Surface tension: the energy γ ∫ da over the aggregate's current boundary (its free surface and the \
            faces on the plates). Optional; without it, no surface term.",
    keys: &[TENSION, GROUP],
};
