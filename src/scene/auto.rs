//! The `auto` choices of a scene, resolved when it is loaded so that the run directory's
//! `scene.toml` and the run log show what was chosen: the element (`fem.element = "auto"`) and
//! the mesh sizes (`mesh.grading = "auto"`). The solver preset's `auto` depends on the dofs and
//! is resolved by `solver` once the mesh is known.
//!
//! The choices are the front of the measured 3-D accuracy-per-second chart (docs/performance.md,
//! "3-D accuracy per second", `scripts/accuracy3d.py`): Taylor–Hood P2–P1 on a mesh of bulk size
//! h = 0.2 R graded to 0.03 R at the plate contacts over 0.5 R. Scaled by the aggregate's radius
//! R, a scene of any size gets the same relative resolution, dofs and accuracy class.

use super::{Element, Scene};
use serde::{Deserialize, Serialize};

/// How the mesh sizes of a `.geo` are chosen (`mesh.grading`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Grading {
    /// The sizes in `mesh.params`; the `.geo`'s own defaults for the others.
    #[default]
    Given,
    /// The chart's choice scaled by `mesh.params.R` ([`AUTO_SIZES`]); a size given in
    /// `mesh.params` wins.
    Auto,
}

/// The automatic mesh sizes relative to R: bulk h, the size at the plate contacts (poles) and
/// the distance over which it blends back to h.
pub const AUTO_SIZES: [(&str, f64); 3] = [("h", 0.2), ("h_pole", 0.03), ("r_pole", 0.5)];

/// Replaces the scene's `auto` element and grading by what they stand for. Err: a message for
/// the scene's error (an automatic grading without the radius it scales with).
pub fn resolve(scene: &mut Scene) -> Result<(), String> {
    if scene.fem.element == Some(Element::Auto) {
        scene.fem.element = Some(Element::P2P1);
    }
    if scene.mesh.grading == Grading::Auto {
        if scene.mesh.file.is_some() {
            return Err("mesh.grading = \"auto\" sizes a .geo source; a ready .msh `file` has its sizes".into());
        }
        let r = *scene.mesh.params.get("R").ok_or(
            "mesh.grading = \"auto\" scales the mesh sizes by the aggregate's radius: give mesh.params.R".to_string(),
        )?;
        for (key, factor) in AUTO_SIZES {
            scene.mesh.params.entry(key.to_string()).or_insert(factor * r);
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
