//! `[material]`: the constitutive model (linear poroelasticity, or a finite-strain mixture
//! around a skeleton law, Holmes–Mow or neo-Hookean, with its penalty and remodelling), its
//! keys and their checks.

use super::key::{Key, Section, Unset};
use crate::material::remodelling;
use crate::material::{FlowForm, Integrator};
use crate::range::Range;
use serde::{Deserialize, Serialize};

/// Constitutive model of the solid skeleton and the fluid flow. (Parsed once per run, so the
/// size difference between the variants does not matter.)
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields, tag = "model", rename_all = "snake_case")]
pub(crate) enum Material {
    /// Small-strain linear poroelasticity, incompressible constituents (Biot α = 1, M = ∞).
    Linear {
        /// Drained shear modulus µ (kPa).
        mu: f64,
        /// Drained Poisson ratio ν, in (-1, 0.5).
        nu: f64,
        /// Darcy conductivity k (µm⁴/(nN s)): Q = −k ∇p.
        permeability: f64,
    },
    /// Finite-strain biphasic mixture (model.md §2–§3): Holmes–Mow solid, compaction penalty,
    /// Holmes–Mow permeability, gravity.
    HolmesMow(MixtureSpec),
    /// The same mixture around a compressible neo-Hookean solid (`material::laws::neo_hookean`);
    /// Holmes–Mow's `alpha` is refused.
    NeoHookean(MixtureSpec),
}

/// A finite-strain biphasic mixture (`model = "holmes_mow"` or `"neo_hookean"`): its skeleton
/// law's keys (µ and ν, or Holmes–Mow's α's) and the mixture's (permeability, penalty, remodelling, densities, gravity).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MixtureSpec {
    /// Shear modulus µ (kPa) and Poisson ratio ν of Ψ/Φs; the α's follow from eq. (56) ...
    #[serde(default)]
    pub(crate) mu: Option<f64>,
    #[serde(default)]
    pub(crate) nu: Option<f64>,
    /// ... or µ follows from the aggregate's drained shear modulus G = Φs µ (kPa), what a plate
    /// or AFM experiment measures ...
    #[serde(default)]
    pub(crate) drained_shear_modulus: Option<f64>,
    /// ... or from its drained Young's modulus E = 2 G (1 + ν) (kPa) ...
    #[serde(default)]
    pub(crate) drained_youngs_modulus: Option<f64>,
    /// ... or the α's are given directly: [α0 (kPa), α1, α2] (α3 = 1).
    #[serde(default)]
    pub(crate) alpha: Option<[f64; 3]>,
    /// Referential solid fraction Φs.
    pub(crate) phi_s: f64,
    /// Referential conductivity k0 (µm⁴/(nN s); 1 mm⁴/(N s) = 1000).
    pub(crate) k0: f64,
    /// Permeability exponents: k = k0 [(J − Φs)/(1 − Φs)]^κ exp(m0 (J² − 1)/2).
    pub(crate) kappa: f64,
    pub(crate) m0: f64,
    /// Remodelling-dependent permeability (model.md (45)–(48)) with this c; isotropic if absent.
    #[serde(default)]
    pub(crate) permeability_c: Option<f64>,
    /// Compaction penalty U(J) (model.md (33)); none if absent.
    #[serde(default)]
    pub(crate) penalty: Option<PenaltySpec>,
    /// Visco-plastic remodelling of B_p (model.md §4); none if absent (B_p = I, no qp state).
    #[serde(default)]
    pub(crate) remodelling: Option<RemodellingSpec>,
    /// Densities (kg/m³).
    #[serde(default = "water")]
    pub(crate) rho_s: f64,
    #[serde(default = "water")]
    pub(crate) rho_f: f64,
    /// Gravity acceleration (m/s²).
    #[serde(default)]
    pub(crate) gravity: [f64; 3],
    /// No fluid: p ≡ 0 everywhere, the drained skeleton alone (each step a static solve,
    /// the limit a long hold relaxes to).
    #[serde(default)]
    pub(crate) drained: bool,
}

/// How a Holmes–Mow solid is given: by (µ, ν) or by its α's (never both).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum SolidSpec {
    /// Shear modulus (kPa) and Poisson ratio; the α's from eq. (56).
    MuNu { mu: f64, nu: f64 },
    /// [α0 (kPa), α1, α2], α3 = 1.
    Alpha([f64; 3]),
}

/// Compaction penalty U(J) = Φs U0 H(J_cr − J) (J − J_cr)^{2q} / (J − Φs)^r.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PenaltySpec {
    pub(crate) j_cr: f64,
    /// U0 (kPa).
    pub(crate) u0: f64,
    pub(crate) q: f64,
    pub(crate) r: f64,
}

/// Perzyna remodelling dB_p/dt = −2 γp B_p dev Σ, γp = λp [‖dev σ‖ − √(2/3) σy]₊ / ‖dev σ‖.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RemodellingSpec {
    /// λp in (kPa s)⁻¹ (Table 1: 0.001 = 1 (MPa s)⁻¹).
    pub(crate) lambda_p: f64,
    /// Yield stress σy (kPa).
    pub(crate) sigma_y: f64,
    /// Which form of the paper's flow rule (40): "40b" (default, dB_p/dt = −2 γp B_p dev Σ,
    /// what the paper says it solved), "40a" (L b_e = −2 γp b_e dev σ: a rate 1/J faster) or "40b_tau"
    /// ((40b) with γp of τ = J σ: yields later where J < 1).
    #[serde(default)]
    pub(crate) form: FlowForm,
    /// Step integrator: "implicit" (default: the exponential map, unconditionally stable),
    /// "trapezoidal" (half the step explicit, half implicit: second order, A-stable) or
    /// "explicit" (forward Euler in B_p, conditionally stable: for stability studies).
    #[serde(default)]
    pub(crate) integrator: Integrator,
}

fn water() -> f64 {
    1000.0
}

impl Material {
    /// The parameters of the model in their ranges.
    pub(super) fn validate(&self) -> Result<(), String> {
        match self {
            Material::Linear { mu, nu, permeability } => {
                LINEAR_MU.check(*mu)?;
                LINEAR_NU.check(*nu)?;
                PERMEABILITY.check(*permeability)
            }
            Material::HolmesMow(m) => m.validate("holmes_mow"),
            Material::NeoHookean(m) => m.validate("neo_hookean"),
        }
    }

    /// The model's name in a scene (`model = ".."`) and, for a finite-strain model, its mixture
    /// keys, whichever its skeleton law: one line per model.
    pub(crate) fn model(&self) -> (&'static str, Option<&MixtureSpec>) {
        match self {
            Material::Linear { .. } => ("linear", None),
            Material::HolmesMow(m) => ("holmes_mow", Some(m)),
            Material::NeoHookean(m) => ("neo_hookean", Some(m)),
        }
    }

    /// The mixture's keys of a finite-strain model; None for the linear one.
    pub(crate) fn mixture(&self) -> Option<&MixtureSpec> {
        self.model().1
    }
}

/// The keys of `[material]` that each give the solid's stiffness, one of which a scene has: an
/// override of one replaces the scene's (`--set material.drained_shear_modulus=1.5` on a scene
/// written with `mu`).
pub(crate) const MODULI: [&str; 3] = ["mu", "drained_shear_modulus", "drained_youngs_modulus"];

impl MixtureSpec {
    /// The mixture's density Φs ρs + (1 − Φs) ρf (kg/m³): what its weight is of.
    pub(crate) fn mixture_density(&self) -> f64 {
        self.phi_s * self.rho_s + (1.0 - self.phi_s) * self.rho_f
    }

    /// |g| (m/s²).
    pub(crate) fn gravity_magnitude(&self) -> f64 {
        self.gravity.iter().map(|a| a * a).sum::<f64>().sqrt()
    }

    /// How the solid is given, µ from the aggregate's moduli if they are; Err: none or two ways
    /// (the message without its section).
    pub(crate) fn solid(&self) -> Result<SolidSpec, String> {
        let phi_s = self.phi_s;
        match (self.mu, self.drained_shear_modulus, self.drained_youngs_modulus, self.nu, self.alpha) {
            (Some(mu), None, None, Some(nu), None) => Ok(SolidSpec::MuNu { mu, nu }),
            (None, Some(g), None, Some(nu), None) => Ok(SolidSpec::MuNu { mu: g / phi_s, nu }),
            (None, None, Some(e), Some(nu), None) => Ok(SolidSpec::MuNu { mu: e / (2.0 * (1.0 + nu)) / phi_s, nu }),
            (None, None, None, None, Some(a)) => Ok(SolidSpec::Alpha(a)),
            _ => Err("give `nu` and one modulus — `mu` (the solid's), `drained_shear_modulus` or \
                      `drained_youngs_modulus` (the aggregate's, what a lab measures) — or (holmes_mow) `alpha`"
                .into()),
        }
    }

    /// The keys in their ranges; `model` names the scene's model in the messages. A law's own
    /// keys (Holmes–Mow's `alpha`) are refused here for the other models.
    fn validate(&self, model: &str) -> Result<(), String> {
        if self.alpha.is_some() && model != "holmes_mow" {
            return Err(format!(
                "[material] `alpha` is a Holmes–Mow key (its α's): model = \"{model}\" takes `nu` and one of \
                 `mu`, `drained_shear_modulus`, `drained_youngs_modulus`"
            ));
        }
        match self.solid().map_err(|m| format!("[material] {model}: {m}"))? {
            SolidSpec::MuNu { mu, nu } => {
                // The modulus given is the one named.
                if let Some(g) = self.drained_shear_modulus {
                    DRAINED_SHEAR_MODULUS.check(g)?;
                } else if let Some(e) = self.drained_youngs_modulus {
                    DRAINED_YOUNGS_MODULUS.check(e)?;
                } else {
                    MU.check(mu)?;
                }
                NU.check(nu)?;
            }
            SolidSpec::Alpha(a) => ALPHA.check_as("material.alpha[0]", a[0])?,
        }
        PHI_S.check(self.phi_s)?;
        K0.check(self.k0)?;
        KAPPA.check(self.kappa)?;
        M0.check(self.m0)?;
        if let Some(c) = self.permeability_c {
            PERMEABILITY_C.check(c)?;
        }
        if let Some(r) = &self.remodelling {
            LAMBDA_P.check(r.lambda_p)?;
            SIGMA_Y.check(r.sigma_y)?;
        }
        RHO_S.check(self.rho_s)?;
        RHO_F.check(self.rho_f)?;
        for g in self.gravity {
            GRAVITY.check(g)?;
        }
        Ok(())
    }
}

const POISSON: Range = Range::new(-1.0, false, 0.5, false, "Poisson ratio must lie in (-1, 0.5)");
const DENSITY: Range = Range::NON_NEGATIVE.says("must be >= 0 (kg/m^3)");

const LINEAR_MODEL: Key = Key::new(
    "material.model",
    "",
    Unset::Required,
    "`linear`: small-strain poroelasticity, incompressible constituents",
);
const LINEAR_MU: Key =
    Key::new("material.mu", "kPa", Unset::Required, "drained shear modulus µ of the whole (what a lab measures)")
        .range(Range::POSITIVE)
        .enters("σ = 2µ ε + λ tr ε I");
const LINEAR_NU: Key = Key::new("material.nu", "", Unset::Required, "drained Poisson ratio ν").range(POISSON);
const PERMEABILITY: Key =
    Key::new("material.permeability", "µm⁴/(nN s)", Unset::Required, "Darcy conductivity k: Q = −k ∇p")
        .range(Range::POSITIVE)
        .enters("Q = −k ∇p");

const MODEL: Key = Key::new(
    "material.model",
    "",
    Unset::Required,
    "`holmes_mow`: the finite-strain biphasic mixture (Holmes–Mow solid, penalty, permeability, gravity)",
);
const MU: Key = Key::new(
    "material.mu",
    "kPa",
    Unset::Absent(""),
    "the solid's shear modulus µ (of Ψ/Φs; the aggregate's drained modulus is Φs µ); with ν, the α's by eq. (56) \
     (holmes_mow) or λ = 2µν/(1 − 2ν) (neo_hookean)",
)
.range(Range::POSITIVE)
.rule("one of `mu`, `drained_shear_modulus`, `drained_youngs_modulus` with `nu`; or (holmes_mow) `alpha`")
.enters("eq. (56); the neo-Hookean energy");
const DRAINED_SHEAR_MODULUS: Key = Key::new(
    "material.drained_shear_modulus",
    "kPa",
    Unset::Absent(""),
    "the aggregate's drained shear modulus G = Φs µ (what a plate or AFM test measures): µ = G / Φs",
)
.range(Range::POSITIVE)
.rule("instead of `mu`, with `nu`")
.enters("µ = G / Φs");
const DRAINED_YOUNGS_MODULUS: Key = Key::new(
    "material.drained_youngs_modulus",
    "kPa",
    Unset::Absent(""),
    "the aggregate's drained Young's modulus E = 2 G (1 + ν): µ = E / (2 (1 + ν) Φs)",
)
.range(Range::POSITIVE)
.rule("instead of `mu`, with `nu`")
.enters("µ = E / (2 (1 + ν) Φs)");
/// ν has one range in both models.
const NU: Key = Key::new(
    "material.nu",
    "",
    Unset::Absent(""),
    "the aggregate's drained Poisson ratio ν (small strain), also that of Ψ/Φs: Φs scales both Lamé constants",
)
.range(POISSON)
.enters("eq. (56); λ = 2µν/(1 − 2ν)");
const ALPHA: Key =
    Key::new("material.alpha", "kPa, –, –", Unset::Absent(""), "[α0, α1, α2] given directly (α3 = 1); holmes_mow only")
        .range(Range::POSITIVE)
        .rule("the range is α0's; the law checks the others")
        .enters("the Holmes–Mow energy");
const PHI_S: Key = Key::new("material.phi_s", "", Unset::Required, "referential solid fraction Φs").range(Range::new(
    0.0,
    false,
    1.0,
    false,
    "solid fraction must lie in (0, 1)",
));
const K0: Key =
    Key::new("material.k0", "µm⁴/(nN s)", Unset::Required, "referential conductivity k0 (1 mm⁴/(N s) = 1000)")
        .range(Range::POSITIVE)
        .enters("k(J), W = −Q");
const KAPPA: Key =
    Key::new("material.kappa", "", Unset::Required, "exponent κ of k = k0 [(J − Φs)/(1 − Φs)]^κ exp(m0 (J² − 1)/2)")
        .range(Range::FINITE)
        .rule("≥ 0 when the model is built")
        .enters("k(J)");
const M0: Key =
    Key::new("material.m0", "", Unset::Required, "exponent m0 of the permeability").range(Range::FINITE).enters("k(J)");
/// The neo-Hookean model's name.
const NEO_HOOKEAN_MODEL: Key = Key::new(
    "material.model",
    "",
    Unset::Required,
    "`neo_hookean`: the same mixture around a compressible neo-Hookean solid, \
     Ψ = Φs [µ/2 (tr(C B_p) − 3) − µ ln J + λ/2 (ln J)²] (FEBio's form)",
);
const PERMEABILITY_C: Key = Key::new(
    "material.permeability_c",
    "",
    Unset::Absent("isotropic permeability"),
    "c of the remodelling-dependent permeability (model.md (45)–(48))",
)
.range(Range::POSITIVE)
.enters("eqs. (45)–(48)");
const PENALTY: Key =
    Key::new("material.penalty", "", Unset::Absent("no penalty"), "the compaction penalty U(J): a table, below");
const REMODELLING: Key = Key::new(
    "material.remodelling",
    "",
    Unset::Absent("none: B_p = I"),
    "the visco-plastic remodelling of B_p: a table, below",
);
const RHO_S: Key =
    Key::new("material.rho_s", "kg/m³", Unset::Value("1000.0"), "solid density").range(DENSITY).enters("b (weight)");
const RHO_F: Key =
    Key::new("material.rho_f", "kg/m³", Unset::Value("1000.0"), "fluid density").range(DENSITY).enters("b, W (weight)");
const GRAVITY: Key = Key::new("material.gravity", "m/s²", Unset::Value("[0.0, 0.0, 0.0]"), "gravity acceleration")
    .range(Range::FINITE)
    .enters("b, W (weight)");
const DRAINED: Key = Key::new(
    "material.drained",
    "",
    Unset::Value("false"),
    "no fluid: p = 0, each step a static solve of the skeleton",
);

/// λp's and σy's ranges are the law's own (`material::remodelling`).
const LAMBDA_P: Key =
    Key::new("material.remodelling.lambda_p", "1/(kPa s)", Unset::Required, "rate λp (Table 1: 0.001 = 1 (MPa s)⁻¹)")
        .range(remodelling::LAMBDA_P)
        .enters("γp, eq. (40)");
const SIGMA_Y: Key = Key::new("material.remodelling.sigma_y", "kPa", Unset::Required, "yield stress σy")
    .range(remodelling::SIGMA_Y)
    .enters("γp, eq. (40)");

pub(super) const LINEAR_SECTION: Section = Section {
    title: "[material], model = \"linear\"",
    enters: "model.md: Small-strain linear poroelasticity",
    about: "Small-strain linear poroelasticity.",
    keys: &[LINEAR_MODEL, LINEAR_MU, LINEAR_NU, PERMEABILITY],
};

/// The keys of every mixture model, after its `material.model` key and before its law's own.
const MIXTURE_KEYS: [Key; 15] = [
    MU,
    DRAINED_SHEAR_MODULUS,
    DRAINED_YOUNGS_MODULUS,
    NU,
    PHI_S,
    K0,
    KAPPA,
    M0,
    PERMEABILITY_C,
    PENALTY,
    REMODELLING,
    RHO_S,
    RHO_F,
    GRAVITY,
    DRAINED,
];

/// A mixture model's key table: its `material.model` key, [`MIXTURE_KEYS`], then its law's own
/// keys (`L` = 1 + 15 + N, checked when compiled).
const fn mixture_keys<const L: usize, const N: usize>(model: Key, own: [Key; N]) -> [Key; L] {
    assert!(L == 1 + MIXTURE_KEYS.len() + N, "L = 1 + MIXTURE_KEYS.len() + N");
    let mut out = [model; L];
    let mut i = 0;
    while i < MIXTURE_KEYS.len() {
        out[1 + i] = MIXTURE_KEYS[i];
        i += 1;
    }
    let mut j = 0;
    while j < N {
        out[1 + MIXTURE_KEYS.len() + j] = own[j];
        j += 1;
    }
    out
}

const HOLMES_MOW_KEYS: [Key; 17] = mixture_keys(MODEL, [ALPHA]);

pub(super) const HOLMES_MOW_SECTION: Section = Section {
    title: "[material], model = \"holmes_mow\"",
    enters: "model.md: The finite-strain biphasic model",
    about: "The finite-strain biphasic mixture (docs/model.md §2–§4).",
    keys: &HOLMES_MOW_KEYS,
};

const NEO_HOOKEAN_KEYS: [Key; 16] = mixture_keys(NEO_HOOKEAN_MODEL, []);

/// The Holmes–Mow mixture's keys but `alpha`; constant permeability is κ = m0 = 0.
pub(super) const NEO_HOOKEAN_SECTION: Section = Section {
    title: "[material], model = \"neo_hookean\"",
    enters: "model.md: The neo-Hookean skeleton",
    about: "The finite-strain biphasic mixture of `holmes_mow` (penalty, permeability, remodelling, gravity) around a \
            compressible neo-Hookean solid, FEBio's form with the remodelling metric: \
            Ψ = Φs [µ/2 (tr(C B_p) − 3) − µ ln J + λ/2 (ln J)²], λ = 2µν/(1 − 2ν) (docs/model.md, \
            \"The neo-Hookean skeleton\"). `alpha` is refused. Constant permeability k = k0 is `kappa = 0.0`, \
            `m0 = 0.0`.",
    keys: &NEO_HOOKEAN_KEYS,
};

/// Checked by the law (`material::CompactionPenalty`) when the model is built.
pub(super) const PENALTY_SECTION: Section = Section {
    title: "material.penalty",
    enters: "model.md: The finite-strain biphasic model (U(J) above)",
    about: "The compaction penalty (the paper's (33); docs/model.md, \"The finite-strain biphasic model\"), an energy \
            per unit reference volume added to the solid's, in kPa (= kJ/m³):\n\n    \
            U(J) = Φs U0 H(J_cr − J) (J − J_cr)^{2q} / (J − Φs)^r\n\n\
            J = det F is the volume ratio (dimensionless), H the Heaviside step: U acts only once the mixture is \
            compressed below J_cr, and for r > 0 grows without bound as J approaches Φs (all the fluid expelled). \
            j_cr, q and r are dimensionless, u0 is in kPa; the shipped scenes use { j_cr = 0.7, u0 = 1000.0, q = 2.0, \
            r = 0.5 } (Table 1: U0 = 1 MPa). Checked when the model is built.",
    keys: &[
        Key::new("material.penalty.j_cr", "", Unset::Required, "the volume ratio J below which the penalty acts")
            .rule("in (Φs, 1]"),
        Key::new("material.penalty.u0", "kPa", Unset::Required, "its modulus U0").rule("≥ 0"),
        Key::new("material.penalty.q", "", Unset::Required, "exponent q of (J − J_cr)^{2q}").rule("≥ 1"),
        Key::new("material.penalty.r", "", Unset::Required, "exponent r of (J − Φs)^−r").rule("≥ 0"),
    ],
};

pub(super) const REMODELLING_SECTION: Section = Section {
    title: "material.remodelling",
    enters: "model.md: Visco-plastic remodelling",
    about: "Perzyna flow dB_p/dt = −2 γp B_p dev Σ, γp = λp [‖dev σ‖ − √(2/3) σy]₊ / ‖dev σ‖.",
    keys: &[
        LAMBDA_P,
        SIGMA_Y,
        Key::new(
            "material.remodelling.form",
            "",
            Unset::Value("\"40b\""),
            "the paper's flow rule (40): `40b` (dB_p/dt = −2 γp B_p dev Σ), `40a` (a rate 1/J faster) or `40b_tau` (40b with γp of τ = J σ)",
        ),
        Key::new(
            "material.remodelling.integrator",
            "",
            Unset::Value("\"implicit\""),
            "`implicit` (exponential map), `trapezoidal` (second order) or `explicit` (stability studies only)",
        ),
    ],
};
