//! `[solver]` and `[fem]`: the solver preset, the element pair, the quadrature degree and the
//! pressure stabilisation; their keys and checks.

use super::key::{Key, Section, Unset};
use super::mesh::Geometry;
use crate::range::Range;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SolverSpec {
    /// `auto` (default: `direct` for small systems, `fieldsplit` for large ones), `direct`
    /// (Krylov with a reused MUMPS factorisation), `fieldsplit` (Schur fieldsplit, AMG on u with
    /// rigid-body modes, fixed-stress Schur approximation) or `lu` (MUMPS for every Newton
    /// system, the reference). See `solver`.
    #[serde(default)]
    pub(crate) preset: Option<crate::solver::Preset>,
}

#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FemSpec {
    /// Degree of the quadrature rule (default 2 for the linear model, exact on straight
    /// elements; 3 for the finite-strain models). On a meridian mesh the triangle rule is one
    /// degree higher (dV = 2πR dA).
    #[serde(default)]
    pub(crate) quadrature_degree: Option<usize>,
    /// c of the pressure stabilisation (c / (λ + 2µ)) ∫ (ṗ − Πṗ)(q − Πq) that keeps the
    /// undrained limit monotone next to drained boundaries (default 4: exact lumping; 0 off).
    #[serde(default)]
    pub(crate) stabilisation: Option<f64>,
    /// τ₀: the stabilisation fades, weight c (1 − r²)₊ with r the larger of τ/τ₀, τ = c_v Δt / h²
    /// (the step resolves the drainage), and (Δt/Δt₀ − 1)/(s − 1) (the steps have grown since a
    /// kink; s = `stabilisation_steps`) (`fem::kernel::Stabilisation`; default: constant).
    /// Taylor–Hood only: P1–P1 keeps the constant weight, which its inf–sup stability needs.
    #[serde(default)]
    pub(crate) stabilisation_fade: Option<f64>,
    /// s: with `stabilisation_fade`, the faded weight is gone once the steps have grown to s
    /// times the first step after a kink (`time.dt`) (default `fem::kernel::STEP_FADE`, 8).
    #[serde(default)]
    pub(crate) stabilisation_steps: Option<f64>,
    /// The element: "P2-P1" (Taylor–Hood, default), "auto" (the measured best: P2–P1; see
    /// [`super::auto`]) or "P1-P1" (equal order, unstable without
    /// the stabilisation; `fem::equal_order`). With plates, P1–P1's contact bounds and contact
    /// state are on the vertices (its mid-edge nodes follow their edges); its stabilisation
    /// keeps the constant weight (`stabilisation_fade` is for Taylor–Hood only).
    #[serde(default)]
    pub(crate) element: Option<Element>,
}

/// The element pair of the u–p discretisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub(crate) enum Element {
    /// Taylor–Hood P2–P1.
    #[serde(rename = "P2-P1")]
    P2P1,
    /// Equal-order P1–P1 (`fem::equal_order`).
    #[serde(rename = "P1-P1")]
    P1P1,
    /// The measured best for the scene; resolved when the scene is loaded ([`super::auto`]).
    #[serde(rename = "auto")]
    Auto,
}

/// Default c of the pressure stabilisation: 4 lumps the P1 mass of the undrained constraint
/// exactly (see `fem::kernel::ElementKernel::stab`).
pub(crate) const DEFAULT_STABILISATION: f64 = 4.0;

/// Default quadrature degrees: 2 for the linear model (exact on straight elements), 3 for the
/// finite-strain ones (exponential energy, curved elements); the meridian adds one (dV = 2πr dA).
pub(crate) const QUADRATURE_DEGREE_LINEAR: usize = 2;
pub(crate) const QUADRATURE_DEGREE_FINITE_STRAIN: usize = 3;

impl SolverSpec {
    /// The preset's default (`auto`) written out.
    pub(super) fn fill_defaults(&mut self) {
        self.preset.get_or_insert_with(Default::default);
    }
}

impl FemSpec {
    /// The defaults written out, so the run directory's scene.toml shows them: Taylor–Hood, the
    /// stabilisation's c, and the quadrature degree — 2 for the linear model (exact on straight
    /// elements), 3 for the finite-strain ones (exponential energy, curved elements).
    /// (`stabilisation_fade` has no value to write: absent is the constant weight.)
    pub(super) fn fill_defaults(&mut self, linear: bool) {
        self.element.get_or_insert(Element::P2P1);
        self.stabilisation.get_or_insert(self.stabilisation_c());
        self.quadrature_degree.get_or_insert(self.degree(linear));
    }

    /// The stabilisation's c: the scene's, or [`DEFAULT_STABILISATION`].
    pub(crate) fn stabilisation_c(&self) -> f64 {
        self.stabilisation.unwrap_or(DEFAULT_STABILISATION)
    }

    /// The steps s of the stabilisation's fade by step growth: the scene's, or
    /// `fem::kernel::STEP_FADE`.
    pub(crate) fn fade_steps(&self) -> f64 {
        self.stabilisation_steps.unwrap_or(crate::fem::kernel::STEP_FADE)
    }

    /// The quadrature degree on the tetrahedron (the meridian's triangle rule is one higher):
    /// the scene's, or the default of the linear or the finite-strain model.
    pub(crate) fn degree(&self, linear: bool) -> usize {
        let default = if linear { QUADRATURE_DEGREE_LINEAR } else { QUADRATURE_DEGREE_FINITE_STRAIN };
        self.quadrature_degree.unwrap_or(default)
    }

    /// Equal-order P1–P1 instead of Taylor–Hood.
    pub(crate) fn equal_order(&self) -> bool {
        self.element == Some(Element::P1P1)
    }

    /// Stabilisation, quadrature degree, and P1–P1 on tetrahedra only (`geometry`: the mesh's).
    pub(super) fn validate(&self, geometry: Geometry) -> Result<(), String> {
        if let Some(c) = self.stabilisation {
            STABILISATION.check(c)?;
        }
        if let Some(t) = self.stabilisation_fade {
            STABILISATION_FADE.check(t)?;
        }
        if let Some(s) = self.stabilisation_steps {
            STABILISATION_STEPS.check(s)?;
        }
        if let Some(q) = self.quadrature_degree {
            QUADRATURE_DEGREE.check_count(q)?;
        }
        if geometry == Geometry::Axisymmetric && self.equal_order() {
            return Err("fem.element = \"P1-P1\" is for tetrahedral meshes only (not the meridian)".into());
        }
        Ok(())
    }
}

pub(super) const SOLVER_SECTION: Section = Section {
    title: "[solver]",
    enters: "numerics.md: Nonlinear and linear solvers",
    about: "How the Newton systems are solved (docs/numerics.md).",
    keys: &[Key::new(
        "solver.preset",
        "",
        Unset::Absent("`auto`"),
        "`auto` (`direct` for small systems, `fieldsplit` for large), `direct` (Krylov with a reused MUMPS \
         factorisation), `fieldsplit` (Schur, AMG on u) or `lu` (MUMPS every Newton step)",
    )],
};

const STABILISATION: Key = Key::new(
    "fem.stabilisation",
    "",
    Unset::Absent("4"),
    "c of the pressure stabilisation (c / (λ + 2µ)) ∫ (ṗ − Πṗ)(q − Πq) (4: exact lumping; 0: off)",
)
.range(Range::NON_NEGATIVE.says("must be >= 0"))
.enters("numerics.md: Pressure stabilisation");
const STABILISATION_FADE: Key = Key::new(
    "fem.stabilisation_fade",
    "",
    Unset::Absent("constant weight"),
    "τ₀: the weight fades as c (1 − r²)₊, r the larger of c_v Δt / (h² τ₀) and (Δt/Δt₀ − 1)/(s − 1), Δt₀ = time.dt, \
     s = fem.stabilisation_steps (Taylor–Hood only)",
)
.range(Range::POSITIVE.says("must be positive (omit it for none)"))
.enters("numerics.md: Pressure stabilisation");
const STABILISATION_STEPS: Key = Key::new(
    "fem.stabilisation_steps",
    "",
    Unset::Absent("8"),
    "s: with fem.stabilisation_fade, the weight is gone once the steps have grown to s × time.dt since a kink",
)
.range(Range::new(1.0, false, f64::INFINITY, false, "must be above 1"))
.enters("numerics.md: Pressure stabilisation");
const QUADRATURE_DEGREE: Key = Key::new(
    "fem.quadrature_degree",
    "",
    Unset::Absent("2 (linear model), 3 (finite strain)"),
    "degree of the quadrature rule; one more on the meridian (dV = 2πr dA)",
)
.range(Range::new(1.0, true, 8.0, true, "use 1..8"))
.enters("numerics.md: Elements and quadrature");

pub(super) const FEM_SECTION: Section = Section {
    title: "[fem]",
    enters: "numerics.md: Elements and quadrature",
    about: "The discretisation.",
    keys: &[
        QUADRATURE_DEGREE,
        STABILISATION,
        STABILISATION_FADE,
        STABILISATION_STEPS,
        Key::new(
            "fem.element",
            "",
            Unset::Absent("`P2-P1`"),
            "`P2-P1` (Taylor–Hood), `auto` (the measured best: P2-P1) or `P1-P1` (equal order, stabilised)",
        )
        .rule("P1-P1 not on the meridian"),
    ],
};

#[cfg(test)]
mod tests {
    use super::super::LoadedScene;

    #[test]
    fn the_quadrature_key_states_the_defaults() {
        let super::super::key::Unset::Absent(text) = super::QUADRATURE_DEGREE.default else {
            panic!("fem.quadrature_degree: its default should be stated as absent-means-a-value")
        };
        let want = format!(
            "{} (linear model), {} (finite strain)",
            super::QUADRATURE_DEGREE_LINEAR,
            super::QUADRATURE_DEGREE_FINITE_STRAIN
        );
        assert_eq!(text, want);
        let fem = super::FemSpec::default();
        assert_eq!((fem.degree(true), fem.degree(false)), (2, 3));
        assert_eq!((fem.stabilisation_c(), fem.fade_steps()), (4.0, 8.0));
    }

    #[test]
    fn the_stabilisation_steps_key_states_the_kernels_default() {
        // the key text is a &'static str: it cannot be formatted from the constant, so it is held to it
        let super::super::key::Unset::Absent(text) = super::STABILISATION_STEPS.default else {
            panic!("fem.stabilisation_steps: its default should be stated as absent-means-a-value")
        };
        assert_eq!(
            text.parse::<f64>().ok(),
            Some(crate::fem::kernel::STEP_FADE),
            "fem.stabilisation_steps' text: {text}"
        );
    }

    #[test]
    fn equal_order_is_refused_on_the_meridian_when_loaded() {
        let sets = ["mesh.geometry=\"axisymmetric\"".to_string(), "fem.element=\"P1-P1\"".to_string()];
        let e = LoadedScene::load("reference", &sets).unwrap_err().to_string();
        assert_eq!(
            e,
            "scene builtin:reference: fem.element = \"P1-P1\" is for tetrahedral meshes only (not the meridian)"
        );
        assert!(LoadedScene::load("reference", &sets[1..]).is_ok());
    }
}
