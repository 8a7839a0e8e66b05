//! The measured 3-D accuracy-per-second chart (docs/performance.md, "3-D accuracy per second",
//! `scripts/accuracy3d.py`) as the solver uses it: the `auto` choices of a scene, resolved when
//! it is loaded so that the run directory's `scene.toml` and the run log show what was chosen
//! (the element, `fem.element = "auto"`, and the mesh sizes, `mesh.grading = "auto"`), and the
//! accuracy class of a plate scene's discretisation. The solver preset's `auto` depends on the
//! dofs and is resolved by `solver` once the mesh is known.
//!
//! The numbers are measurements, so they live in a data file,
//! `scripts/data/accuracy_classes.toml` (which says how to refresh them), compiled in and parsed
//! when the first scene is loaded. The chart's front is Taylor–Hood P2–P1 on a mesh of bulk size
//! h = 0.2 R graded to 0.03 R at the plate contacts over 0.5 R; scaled by the aggregate's radius
//! R, a scene of any size gets the same relative resolution, dofs and accuracy class.

use super::mesh::{Geometry, Grading};
use super::numerics::Element;
use super::sections::Scene;
use crate::material::Integrator;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The chart's data file.
const CHART: &str = include_str!("../../scripts/data/accuracy_classes.toml");

/// The measured chart: the automatic sizes and the accuracy classes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Chart {
    /// Mesh sizes relative to R (`h`, `h_pole`, `r_pole`).
    pub(crate) auto_sizes: BTreeMap<String, f64>,
    /// The classes, the first match wins.
    pub(crate) class: Vec<Class>,
}

/// One accuracy class, the discretisations it holds for and the domain of scenes it was
/// measured in.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Class {
    pub(crate) geometry: Geometry,
    /// The element pair (any if absent).
    #[serde(default)]
    pub(crate) element: Option<Element>,
    /// Remodelling scenes integrated by one of these (any scene if absent).
    #[serde(default)]
    pub(crate) remodelling: Option<Vec<Integrator>>,
    /// The largest h/R (any if absent).
    #[serde(default)]
    pub(crate) max_h_over_r: Option<f64>,
    /// The range of c_v t_ramp / R² measured (any if absent).
    #[serde(default)]
    pub(crate) drainage: Option<[f64; 2]>,
    /// The range of the compression ũ measured (any if absent).
    #[serde(default)]
    pub(crate) compression: Option<[f64; 2]>,
    /// The fewest steps through the ramp measured (any if absent).
    #[serde(default)]
    pub(crate) min_ramp_steps: Option<usize>,
    /// The stabilisations measured (any if absent).
    #[serde(default)]
    pub(crate) stabilisation: Option<Vec<Stabilisation>>,
    /// What to expect of the plate force; `{hold}` stands for the force at the end of the
    /// scene's hold, F(t) with its own t.
    pub(crate) class: String,
    /// What it was measured on.
    pub(crate) basis: String,
}

/// The pressure stabilisation of a scene, as the chart tells them apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum Stabilisation {
    /// At full weight in every step (`fem.stabilisation_fade` absent).
    Constant,
    /// Faded (`fem.stabilisation_fade`).
    Faded,
    /// `fem.stabilisation = 0`.
    Off,
}

/// Where a plate scene lies in the dimensionless groups its force's discretisation error
/// depends on besides the mesh (docs/performance.md, "What the accuracy line means").
#[derive(Debug, Clone, Copy)]
pub(crate) struct Domain {
    /// c_v t_ramp / R²: how far the ramp drains the aggregate. With h/R it gives the drainage
    /// layer √(c_v t_ramp) in elements, which decides what the stabilisation costs.
    pub(crate) drainage: f64,
    /// The compression ũ.
    pub(crate) compression: f64,
    /// The steps the schedule takes through the ramp.
    pub(crate) ramp_steps: usize,
    pub(crate) stabilisation: Stabilisation,
}

impl Class {
    /// The first group of `d` outside the domain this class was measured in, said for a user
    /// (None: inside).
    pub(crate) fn outside(&self, d: &Domain) -> Option<String> {
        let out = |x: f64, [lo, hi]: [f64; 2]| x < lo || x > hi;
        if let Some(r) = self.drainage.filter(|&r| out(d.drainage, r)) {
            return Some(format!("c_v t_ramp / R² = {:.2e}, measured {:.2e} to {:.2e}", d.drainage, r[0], r[1]));
        }
        if let Some(r) = self.compression.filter(|&r| out(d.compression, r)) {
            return Some(format!("compression {}, measured {} to {}", d.compression, r[0], r[1]));
        }
        if let Some(n) = self.min_ramp_steps.filter(|&n| d.ramp_steps < n) {
            return Some(format!("{} steps through the ramp, measured with {n} or more", d.ramp_steps));
        }
        if let Some(list) = self.stabilisation.as_ref().filter(|l| !l.contains(&d.stabilisation)) {
            let name = |s: &Stabilisation| format!("{s:?}").to_lowercase();
            let measured: Vec<String> = list.iter().map(name).collect();
            return Some(format!(
                "the {} pressure stabilisation, measured {}",
                name(&d.stabilisation),
                measured.join(" or ")
            ));
        }
        None
    }
}

/// The chart, parsed once; Err: the data file's error.
pub(crate) fn chart() -> Result<&'static Chart, String> {
    static PARSED: OnceLock<Result<Chart, String>> = OnceLock::new();
    PARSED
        .get_or_init(|| toml::from_str(CHART).map_err(|e| format!("scripts/data/accuracy_classes.toml: {e}")))
        .as_ref()
        .map_err(Clone::clone)
}

impl Chart {
    /// The classes of a discretisation, in the chart's order: the geometry, the element pair
    /// (P2–P1 or P1–P1), the remodelling's integrator if any, and h/R.
    pub(crate) fn classes_of(
        &self,
        geometry: Geometry,
        element: Element,
        remodelling: Option<Integrator>,
        h_over_r: f64,
    ) -> impl Iterator<Item = &Class> {
        self.class.iter().filter(move |c| {
            c.geometry == geometry
                && c.element.is_none_or(|e| e == element)
                && c.remodelling.as_ref().is_none_or(|list| remodelling.is_some_and(|i| list.contains(&i)))
                && c.max_h_over_r.is_none_or(|m| h_over_r <= m)
        })
    }

    /// The class of a scene: the first of its discretisation's classes measured in a domain
    /// that holds `domain`; Err: the first such class's reason why the scene is outside it, or
    /// the h/R the discretisation was charted up to (None: not charted at all).
    pub(crate) fn class_of(
        &self,
        geometry: Geometry,
        element: Element,
        remodelling: Option<Integrator>,
        h_over_r: f64,
        domain: &Domain,
    ) -> Option<Result<&Class, String>> {
        let mut classes = self.classes_of(geometry, element, remodelling, h_over_r).peekable();
        let Some(&first) = classes.peek() else {
            // Charted for finer meshes only.
            let finest = self.classes_of(geometry, element, remodelling, 0.0).filter_map(|c| c.max_h_over_r);
            return finest.reduce(f64::max).map(|m| Err(format!("h/R = {h_over_r:.2}, measured up to {m}")));
        };
        Some(classes.find(|c| c.outside(domain).is_none()).ok_or_else(|| first.outside(domain).unwrap_or_default()))
    }
}

/// Replaces the scene's `auto` element and grading by what they stand for. Err: a message for
/// the scene's error (an automatic grading without the radius it scales with; a chart that does
/// not parse, for every scene, so that it shows at the first load).
pub(crate) fn resolve(scene: &mut Scene) -> Result<(), String> {
    let chart = chart()?;
    if scene.fem.element == Some(Element::Auto) {
        scene.fem.element = Some(Element::P2P1);
    }
    if scene.mesh.grading == Grading::Auto {
        if scene.mesh.file.is_some() {
            return Err("mesh.grading = \"auto\" sizes a .geo source; a ready .msh `file` has its sizes".into());
        }
        scene.mesh.params.get("R").ok_or(
            "mesh.grading = \"auto\" scales the mesh sizes by the aggregate's radius: give mesh.params.R".to_string(),
        )?;
        // Relative sizes: the mesh's resolution moves them into params (a size given wins).
        for (key, factor) in &chart.auto_sizes {
            scene.mesh.relative_sizes.entry(key.clone()).or_insert(*factor);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::LoadedScene;
    use super::*;

    fn load(sets: &[&str]) -> crate::error::Result<LoadedScene> {
        LoadedScene::load("reference", &sets.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    }

    /// A domain inside a class's ranges (their lower ends).
    fn inside(c: &Class) -> Domain {
        Domain {
            drainage: c.drainage.map_or(0.06, |r| r[0]),
            compression: c.compression.map_or(0.3, |r| r[0]),
            ramp_steps: c.min_ramp_steps.unwrap_or(17),
            stabilisation: c.stabilisation.as_ref().map_or(Stabilisation::Faded, |l| l[0]),
        }
    }

    #[test]
    fn the_chart_parses_and_every_class_can_match() {
        let chart = chart().unwrap();
        let sizes: Vec<(&str, f64)> = chart.auto_sizes.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        assert_eq!(sizes, [("h", 0.2), ("h_pole", 0.03), ("r_pole", 0.5)]);
        // Each row is the first match of its own discretisation and domain: no row hides behind
        // another.
        for (i, c) in chart.class.iter().enumerate() {
            let element = c.element.unwrap_or(Element::P2P1);
            let integrator = c.remodelling.as_ref().map(|l| l[0]);
            let h = c.max_h_over_r.unwrap_or(1.0);
            let found = chart.class_of(c.geometry, element, integrator, h, &inside(c));
            let found = found.and_then(|f| f.ok()).map(|f| f as *const Class);
            assert_eq!(found, Some(c as *const Class), "row {i} ({}) is hidden", c.class);
        }
    }

    /// Every measured class has its domain: a class without one would be printed for any scene.
    #[test]
    fn every_class_says_where_it_was_measured() {
        for c in &chart().unwrap().class {
            let d = (c.drainage, c.compression, c.min_ramp_steps, &c.stabilisation);
            assert!(d.0.is_some() && d.1.is_some() && d.2.is_some() && d.3.is_some(), "{}: no domain", c.class);
            assert!(c.max_h_over_r.is_some(), "{}: no largest h/R", c.class);
        }
    }

    #[test]
    fn a_scene_outside_the_measured_domain_gets_the_reason() {
        let chart = chart().unwrap();
        let class = |d: &Domain, h: f64| chart.class_of(Geometry::Solid, Element::P2P1, None, h, d).unwrap();
        let reference =
            Domain { drainage: 0.0604, compression: 0.3, ramp_steps: 17, stabilisation: Stabilisation::Faded };
        assert!(class(&reference, 0.2).unwrap().class.starts_with("peak 0.5-1.3% low"));
        // The soft aggregate (E = 1.2 kPa, R = 220 µm, ramp 10 s) drains 48 times less in its
        // ramp: its own class, measured on it.
        let soft = Domain { drainage: 1.26e-3, compression: 0.25, ramp_steps: 20, ..reference };
        assert!(class(&soft, 0.2).unwrap().basis.contains("soft aggregate"));
        // A large one (the reference at R = 300 µm) was not measured: the first class's reason.
        let large = Domain { drainage: 6.71e-3, ..reference };
        let e = class(&large, 0.2).unwrap_err();
        assert!(e.starts_with("c_v t_ramp / R² = 6.71e-3, measured 6.00e-2 to 6.10e-2"), "{e}");
        let e = class(&Domain { compression: 0.3, ..soft }, 0.2).unwrap_err();
        assert!(e.starts_with("c_v t_ramp / R² = 1.26e-3, measured 6.00e-2"), "{e}");
        let e = class(&Domain { ramp_steps: 8, ..reference }, 0.2).unwrap_err();
        assert_eq!(e, "8 steps through the ramp, measured with 17 or more");
        let e = class(&Domain { stabilisation: Stabilisation::Constant, ..reference }, 0.2).unwrap_err();
        assert_eq!(e, "the constant pressure stabilisation, measured faded or off");
        let e = class(&reference, 0.35).unwrap_err();
        assert_eq!(e, "h/R = 0.35, measured up to 0.3");
    }

    #[test]
    fn auto_grading_at_r_100_is_the_shipped_default_and_scales_with_r() {
        let shipped = load(&[]).unwrap().scene.mesh.params;
        let auto = load(&["mesh.grading=\"auto\"", "mesh.params={ R = 100.0 }"]).unwrap().scene.mesh.params;
        assert_eq!(auto, shipped, "the chart's choice at R = 100 is the reference scene's mesh");
        let big = load(&["mesh.grading=\"auto\"", "mesh.params={ R = 300.0 }"]).unwrap().scene.mesh.params;
        let want: Vec<(&str, f64)> = vec![("R", 300.0), ("h", 60.0), ("h_pole", 9.0), ("r_pole", 150.0)];
        for (k, v) in want {
            assert!((big[k] - v).abs() < 1e-12, "{k} = {} at R = 300, want {v}", big[k]);
        }
        // A size given wins over the automatic one.
        let given = load(&["mesh.grading=\"auto\"", "mesh.params={ R = 300.0, h = 40.0 }"]).unwrap().scene.mesh.params;
        assert_eq!((given["h"], given["h_pole"]), (40.0, 9.0));
    }

    #[test]
    fn auto_grading_needs_the_radius_and_a_geo() {
        let e = load(&["mesh.grading=\"auto\"", "mesh.params={ h = 20.0 }"]).unwrap_err().to_string();
        assert!(e.contains("give mesh.params.R"), "{e}");
        let e = load(&["mesh.grading=\"auto\"", "mesh.geo=\"\"", "mesh.file=\"m.msh\""]);
        let e = e.unwrap_err().to_string();
        assert!(e.contains("ready .msh"), "{e}");
    }

    #[test]
    fn auto_element_is_taylor_hood() {
        let s = load(&["fem.element=\"auto\""]).unwrap().scene;
        assert_eq!(s.fem.element, Some(Element::P2P1));
        assert!(!s.fem.equal_order());
    }
}
