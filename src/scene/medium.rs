//! `[medium]`: the liquid the aggregate sits in, its keys and checks. Its hydrostatic pressure
//! loads the boundary and sets the drained pores' pressure, so the aggregate's weight is its
//! excess over the medium's (model.md: The medium).

use super::bc::BoundaryCondition;
use super::key::{Key, Section, Unset};
use super::material::MixtureSpec;
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// The medium: its density (filled in from the pores' fluid) and the boundary group it wets.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MediumSpec {
    /// ρ_m in kg/m³; filled in with material.rho_f, which it must equal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) density: Option<f64>,
    /// The boundary group the medium's pressure acts on.
    #[serde(default = "default_group")]
    pub(crate) group: String,
}

fn default_group() -> String {
    "surface".into()
}

impl MediumSpec {
    /// The density's default: the pores' fluid, material.rho_f (none for the linear model).
    pub(super) fn resolve(&mut self, mixture: Option<&MixtureSpec>) {
        if self.density.is_none() {
            self.density = mixture.map(|m| m.rho_f);
        }
    }

    /// `mixture`: the finite-strain material's densities and gravity (None: the linear model);
    /// `bcs`: the scene's boundary conditions (none may prescribe the pressure the medium sets).
    pub(super) fn validate(&self, mixture: Option<&MixtureSpec>, bcs: &[BoundaryCondition]) -> Result<(), String> {
        if let Some((i, bc)) = bcs.iter().enumerate().find(|(_, bc)| bc.pressure.is_some() && bc.group == self.group) {
            return Err(format!(
                "bc #{i} prescribes the pore pressure on group \"{}\", which [medium] wets: the medium sets the \
                 drained pressure there (drop the bc's pressure, or [medium])",
                bc.group
            ));
        }
        let Some(m) = mixture else {
            return Err(
                "[medium] needs a finite-strain mixture (material.model = \"holmes_mow\" or \"neo_hookean\"): \
                        the medium's weight acts with the mixture's densities and gravity, which the linear model \
                        has not; drop [medium]"
                    .into(),
            );
        };
        let Some(rho) = self.density else { return Ok(()) };
        DENSITY.check(rho)?;
        // With ρ_m ≠ ρf the fluid at rest between two drained faces at different heights would
        // flow for ever: the pores are open to the medium, so they hold it.
        if rho != m.rho_f {
            return Err(format!(
                "medium.density = {rho}: the pores hold the medium, so its density is material.rho_f = {} kg/m³ \
                 (drop medium.density, or set material.rho_f = {rho})",
                m.rho_f
            ));
        }
        Ok(())
    }
}

/// The density the aggregate's weight is of: the mixture's ρ_mix = Φs ρs + (1 − Φs) ρf, less the
/// medium's ρ_m if it sits in one (its excess weight; Bond numbers and the settling's cause).
pub(crate) fn weighing_density(mixture: &MixtureSpec, medium: Option<&MediumSpec>) -> f64 {
    mixture.mixture_density() - medium.map_or(0.0, |md| md.density.unwrap_or(mixture.rho_f))
}

const DENSITY: Key = Key::new(
    "medium.density",
    "kg/m³",
    Unset::Absent("material.rho_f (filled in)"),
    "density ρ_m of the medium: its hydrostatic pressure g_f ρ_m a_g·x loads the boundary and the drained pores",
)
.range(Range::NON_NEGATIVE.says("must be finite and >= 0 (kg/m^3)"))
.rule("must equal material.rho_f (the pores hold the medium)")
.enters("model.md: The medium");
const GROUP: Key = Key::new("medium.group", "", Unset::Value("\"surface\""), "the boundary group the medium wets");

pub(super) const SECTION: Section = Section {
    title: "medium",
    enters: "model.md: The medium",
    about: "The liquid the aggregate sits in: its hydrostatic pressure p_m = g_f ρ_m a_g·x (g_f the settling's \
            gravity factor) loads the whole boundary group with −p_m n, on the plates too, so the plates carry the \
            excess weight (ρ_mix − ρ_m) g V; drained faces drain towards p_m. Optional; without it, the aggregate \
            is weighed as in air and the drained pores are at 0.",
    keys: &[DENSITY, GROUP],
};
