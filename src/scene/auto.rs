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

use super::{Element, Geometry, Grading, Scene};
use crate::material::Integrator;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The chart's data file.
const CHART: &str = include_str!("../../scripts/data/accuracy_classes.toml");

/// The measured chart: the automatic sizes and the accuracy classes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Chart {
    /// Mesh sizes relative to R (`h`, `h_pole`, `r_pole`).
    pub auto_sizes: BTreeMap<String, f64>,
    /// The classes, the first match wins.
    pub class: Vec<Class>,
}

/// One accuracy class and the discretisations it holds for.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Class {
    pub geometry: Geometry,
    /// The element pair (any if absent).
    #[serde(default)]
    pub element: Option<Element>,
    /// Remodelling scenes integrated by one of these (any scene if absent).
    #[serde(default)]
    pub remodelling: Option<Vec<Integrator>>,
    /// The largest h/R (any if absent).
    #[serde(default)]
    pub max_h_over_r: Option<f64>,
    /// What to expect of the plate force.
    pub class: String,
    /// What it was measured on.
    pub basis: String,
}

/// The chart, parsed once; Err: the data file's error.
pub fn chart() -> Result<&'static Chart, String> {
    static PARSED: OnceLock<Result<Chart, String>> = OnceLock::new();
    PARSED
        .get_or_init(|| toml::from_str(CHART).map_err(|e| format!("scripts/data/accuracy_classes.toml: {e}")))
        .as_ref()
        .map_err(Clone::clone)
}

impl Chart {
    /// The class of a discretisation: the geometry, the element pair (P2–P1 or P1–P1), the
    /// remodelling's integrator if any, and h/R.
    pub fn class_of(
        &self,
        geometry: Geometry,
        element: Element,
        remodelling: Option<Integrator>,
        h_over_r: f64,
    ) -> Option<&Class> {
        self.class.iter().find(|c| {
            c.geometry == geometry
                && c.element.is_none_or(|e| e == element)
                && c.remodelling.as_ref().is_none_or(|list| remodelling.is_some_and(|i| list.contains(&i)))
                && c.max_h_over_r.is_none_or(|m| h_over_r <= m)
        })
    }
}

/// Replaces the scene's `auto` element and grading by what they stand for. Err: a message for
/// the scene's error (an automatic grading without the radius it scales with; a chart that does
/// not parse, for every scene, so that it shows at the first load).
pub fn resolve(scene: &mut Scene) -> Result<(), String> {
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

    #[test]
    fn the_chart_parses_and_every_class_can_match() {
        let chart = chart().unwrap();
        let sizes: Vec<(&str, f64)> = chart.auto_sizes.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        assert_eq!(sizes, [("h", 0.2), ("h_pole", 0.03), ("r_pole", 0.5)]);
        // Each row is the first match of its own discretisation: no row hides behind another.
        for (i, c) in chart.class.iter().enumerate() {
            let element = c.element.unwrap_or(Element::P2P1);
            let integrator = c.remodelling.as_ref().map(|l| l[0]);
            let h = c.max_h_over_r.unwrap_or(1.0);
            let found = chart.class_of(c.geometry, element, integrator, h).map(|f| f as *const Class);
            assert_eq!(found, Some(c as *const Class), "row {i} ({}) is hidden", c.class);
        }
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
