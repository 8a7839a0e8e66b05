//! What a scene resolved to, for the run log and `poroplast check`: the element pair, the mesh
//! (its source and size parameters) and, for plate experiments, the accuracy class that the
//! measured error-against-time chart gives for that discretisation (docs/performance.md,
//! "3-D accuracy per second", made by `scripts/accuracy3d.py`).
//!
//! The classes are errors of the peak force and of F(35 s) of the `reference` experiment
//! against its converged meridian values, measured on 2026-12-02 with the scene's default
//! steps; other plate scenes are classed by the same relative mesh size h/R, which is a guide,
//! not a bound.

use crate::material::Integrator;
use crate::reference_cell::Family;
use crate::scene::{Material, Scene};

/// The one-line description: element, cells, mesh source and parameters.
pub(super) fn discretisation(scene: &Scene, family: Family, n_cells: usize) -> String {
    let element = if scene.fem.equal_order() { "equal-order P1–P1 (stabilised)" } else { "Taylor–Hood P2–P1" };
    let m = &scene.mesh;
    // The file the run meshes from, as `LoadedScene::mesh_source` picks it.
    let (geo, file) = m.source();
    let source = file.or(geo).unwrap_or("?");
    let params: Vec<String> = m.params.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    let auto = if m.grading == crate::scene::auto::Grading::Auto { "; sizes by mesh.grading = auto" } else { "" };
    let params = if params.is_empty() { String::new() } else { format!(" ({}{auto})", params.join(", ")) };
    let mirror = if m.mirror.is_empty() { String::new() } else { format!(", mirrored across {}", m.mirror.join(", ")) };
    format!("discretisation: {element} on {n_cells} curved {}; mesh {source}{params}{mirror}", family.cells_name())
}

/// The expected accuracy of the plate force for this discretisation (plate scenes on a sphere
/// `.geo` with R and h; None otherwise).
pub(super) fn accuracy_class(scene: &Scene, family: Family) -> Option<String> {
    scene.plates.as_ref()?;
    let p = &scene.mesh.params;
    let h_over_r = p.get("h")? / p.get("R")?;
    let remodelling = match &scene.material {
        Material::HolmesMow { remodelling: Some(r), .. } => Some(r.integrator),
        _ => None,
    };
    let (class, basis) = match remodelling {
        Some(integrator) if !family.axisymmetric() && !scene.fem.equal_order() && h_over_r <= 0.2 => {
            if integrator == Integrator::Trapezoidal {
                REMODELLING_3D_TRAPEZOIDAL
            } else {
                REMODELLING_3D_BACKWARD_EULER
            }
        }
        _ => class_of(family.axisymmetric(), scene.fem.equal_order(), h_over_r),
    };
    Some(format!("expected accuracy (plate force, h/R = {h_over_r:.2}): {class} [{basis}; docs/performance.md]"))
}

/// With remodelling (`remodel_40` with its steps, measured 2026-12-02): the trapezoidal rule,
/// and backward Euler, whose over-integrated flow through the ramp adds to the mesh's error.
const REMODELLING_3D_TRAPEZOIDAL: (&str, &str) = (
    "peak about 0.5% low, F(35 s) within about 0.5% (trapezoidal remodelling)",
    "3-D P2-P1 remodel_40, h/R = 0.2, h_pole 3, trapezoidal rule: peak -0.48%, F(35 s) +0.12%",
);
const REMODELLING_3D_BACKWARD_EULER: (&str, &str) = (
    "peak about 1.5% low, F(35 s) about 1.4% high (backward-Euler remodelling)",
    "3-D P2-P1 remodel_40, h/R = 0.2, h_pole 3, backward Euler: peak -1.43%, F(35 s) +1.38%",
);

/// The measured class for (meridian?, P1–P1?, h/R): (class, what it was measured on).
fn class_of(meridian: bool, equal_order: bool, h_over_r: f64) -> (&'static str, &'static str) {
    match (meridian, equal_order) {
        (true, _) if h_over_r <= 0.2 => (
            "peak and F(35 s) within about 1%",
            "meridian, h/R = 0.05-0.2: peak -1.07 to +0.14%, F(35 s) -0.33 to +0.56%",
        ),
        (true, _) => ("not charted above h/R = 0.2", "meridian"),
        (false, true) => (
            "peak within about 1.5%, F(35 s) 2-10% high (the linear displacement is stiff)",
            "3-D P1-P1, h/R = 0.15-0.4: peak -0.5 to +1.35%, F(35 s) +2.4 to +10.3%",
        ),
        (false, false) if h_over_r <= 0.2 => (
            "peak 0.5-1.3% low, F(35 s) within about 0.6%",
            "3-D P2-P1, h/R = 0.12-0.2 graded at the poles: peak -0.54 to -1.33%, F(35 s) -0.64 to -0.04%",
        ),
        (false, false) if h_over_r <= 0.3 => {
            ("peak and F(35 s) 1-2.5% low", "3-D P2-P1, h/R = 0.25-0.3: peak -1.5 to -1.9%, F(35 s) -0.9 to -2.4%")
        }
        (false, false) => ("not charted above h/R = 0.3", "3-D P2-P1"),
    }
}
