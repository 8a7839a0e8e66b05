//! `[medium]`: the liquid the aggregate sits in, its keys and checks. Its hydrostatic pressure
//! loads the boundary and sets the drained pores' pressure, so the aggregate's weight is its
//! excess over the medium's (model.md: The medium).

use super::bc::BoundaryCondition;
use super::key::{Key, Section, Unset};
use super::material::MixtureSpec;
use super::tools::{ToolKind, ToolSpec};
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
    /// η_m in Pa s: the viscous drag on the surface (0: none).
    #[serde(default = "default_viscosity")]
    pub(crate) viscosity: f64,
    /// The pipettes' suctions.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) suction: Vec<SuctionSpec>,
}

/// `[[medium.suction]]`: a pipette's bore held at Δp(t) below the medium.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SuctionSpec {
    /// The `[[tools]]` pipette's name.
    pub(crate) tool: String,
    /// Δp(t) rows, linear between them, held after the last.
    pub(crate) table: Vec<SuctionRow>,
}

/// One row of a suction table.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SuctionRow {
    /// Time, s.
    pub(crate) t: f64,
    /// The suction (the medium's pressure less the bore's), kPa.
    pub(crate) dp: f64,
}

fn default_group() -> String {
    "surface".into()
}

/// Water's (the culture medium's, 0.7–1 mPa s at 20–37 °C): what makes a released aggregate's
/// translation along the pipette well posed, so on unless switched off.
fn default_viscosity() -> f64 {
    1e-3
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
    /// `tools`: the scene's `[[tools]]` (a suction names a pipette among them).
    pub(super) fn validate(
        &self,
        mixture: Option<&MixtureSpec>,
        bcs: &[BoundaryCondition],
        tools: &[ToolSpec],
    ) -> Result<(), String> {
        VISCOSITY.check(self.viscosity)?;
        self.validate_suctions(tools)?;
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

impl MediumSpec {
    /// Each suction names one pipette of `tools`, at most one per pipette; its table from t = 0,
    /// in order, Δp finite (errors name the row, 1-based).
    fn validate_suctions(&self, tools: &[ToolSpec]) -> Result<(), String> {
        for (i, s) in self.suction.iter().enumerate().map(|(i, s)| (i + 1, s)) {
            if tools.is_empty() {
                return Err(format!(
                    "medium.suction #{i} names tool \"{}\", but the scene has no [[tools]]: a suction needs a \
                     pipette (add a [[tools]] entry with kind = \"pipette\")",
                    s.tool
                ));
            }
            let Some(tool) = tools.iter().find(|t| t.name == s.tool) else {
                let names: Vec<&str> = tools.iter().map(|t| t.name.as_str()).collect();
                return Err(format!(
                    "medium.suction #{i}: no tool named \"{}\" (the tools: {})",
                    s.tool,
                    names.join(", ")
                ));
            };
            if tool.kind != ToolKind::Pipette {
                return Err(format!("suction needs a pipette: tools.{} is a {}", tool.name, tool.kind.name()));
            }
            if self.suction[..i - 1].iter().any(|o| o.tool == s.tool) {
                return Err(format!("medium.suction #{i}: a second suction in pipette \"{}\"; give one table", s.tool));
            }
            let key = format!("medium.suction #{i} table");
            if s.table.is_empty() {
                return Err(format!("{key}: no rows; give at least one, as [{{ t = 0, dp = 0.0 }}]"));
            }
            if s.table[0].t != 0.0 {
                return Err(format!("{key} row 1: t = {} s: the table starts at t = 0", s.table[0].t));
            }
            for (j, row) in s.table.iter().enumerate().map(|(j, r)| (j + 1, r)) {
                if !row.dp.is_finite() {
                    return Err(format!("{key} row {j}: dp = {} kPa must be finite", row.dp));
                }
                if j > 1 && !(row.t.is_finite() && row.t > s.table[j - 2].t) {
                    return Err(format!(
                        "{key} row {j}: t = {} s is not after row {}'s {} s: rows in increasing time",
                        row.t,
                        j - 1,
                        s.table[j - 2].t
                    ));
                }
            }
        }
        Ok(())
    }

    /// Every suction's table as (t, Δp) with its tool's index in `tools` (validated).
    pub(crate) fn suction_tables<'a>(
        &'a self,
        tools: &'a [ToolSpec],
    ) -> impl Iterator<Item = (usize, Vec<(f64, f64)>)> + 'a {
        self.suction.iter().filter_map(move |s| {
            let k = tools.iter().position(|t| t.name == s.tool)?;
            Some((k, s.table.iter().map(|r| (r.t, r.dp)).collect()))
        })
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
const VISCOSITY: Key = Key::new(
    "medium.viscosity",
    "Pa s",
    Unset::Value("1e-3"),
    "viscosity η_m of the medium: the surface's drag −ζ_d u̇, ζ_d = 3η_m/(2R₀) (Stokes' drag of a sphere of the \
     body's volume, radius R₀); 0 switches it off (a free body's translation then has no stiffness)",
)
.range(Range::NON_NEGATIVE.says("must be finite and >= 0 (Pa s)"))
.enters("model.md: The medium");
const SUCTION_TOOL: Key = Key::new(
    "medium.suction.tool",
    "",
    Unset::Absent("no suction"),
    "`[[medium.suction]]`: the `[[tools]]` pipette whose bore is sucked",
)
.rule("names a pipette; one suction per pipette");
const SUCTION_TABLE: Key = Key::new(
    "medium.suction.table",
    "s, kPa",
    Unset::Required,
    "rows { t, dp }: the suction Δp(t) (the bore's pressure is p_m − Δp up to the mouth, rising smoothly to \
     p_m within the rim radius in front of it), linear between rows, held after the last; steps land on the rows' times",
)
.rule("from t = 0, times increasing; dp ≤ 10 E (kPa)")
.enters("model.md: The medium");

pub(super) const SECTION: Section = Section {
    title: "medium",
    enters: "model.md: The medium",
    about: "The liquid the aggregate sits in: its hydrostatic pressure p_m = g_f ρ_m a_g·x (g_f the settling's \
            gravity factor) loads the whole boundary group with −p_m n, on the plates too, so the plates carry the \
            excess weight (ρ_mix − ρ_m) g V; drained faces drain towards p_m. A `[[medium.suction]]` lowers the \
            pressure in a pipette's bore by Δp(t); the medium's viscosity drags the moving surface. Optional; \
            without it, the aggregate is weighed as in air and the drained pores are at 0.",
    keys: &[DENSITY, GROUP, VISCOSITY, SUCTION_TOOL, SUCTION_TABLE],
};
