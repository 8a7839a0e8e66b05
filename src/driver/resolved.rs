//! What a scene resolved to, for the run log and `poroplast check`: the element pair, the mesh
//! (its source and size parameters) and, for plate experiments, the accuracy class that the
//! measured error-against-time chart gives for that discretisation (docs/performance.md,
//! "3-D accuracy per second", made by `scripts/accuracy3d.py`).
//!
//! The classes are measured errors of the peak force and of F(35 s) of the `reference` and
//! `remodel_40` experiments against their converged meridian values, kept with the chart's data
//! (`scripts/data/accuracy_classes.toml`, read by `scene::auto`); other plate scenes are classed
//! by the same relative mesh size h/R, which is a guide, not a bound.

use crate::reference_cell::Family;
use crate::scene::{auto, Element, Geometry, Grading, HolmesMowSpec, Material, Scene, SolidSpec};

/// The one-line description: element, cells, mesh source and parameters.
pub(super) fn discretisation(scene: &Scene, family: Family, n_cells: usize) -> String {
    let element = if scene.fem.equal_order() { "equal-order P1–P1 (stabilised)" } else { "Taylor–Hood P2–P1" };
    let m = &scene.mesh;
    // The file the run meshes from, as `LoadedScene::mesh_source` picks it.
    let (geo, file) = m.source();
    let source = file.or(geo).unwrap_or("?");
    let params: Vec<String> = m.params.iter().map(|(k, v)| format!("{k} = {v}")).collect();
    let auto = if m.grading == Grading::Auto { "; sizes by mesh.grading = auto" } else { "" };
    let params = if params.is_empty() { String::new() } else { format!(" ({}{auto})", params.join(", ")) };
    let mirror = if m.mirror.is_empty() { String::new() } else { format!(", mirrored across {}", m.mirror.join(", ")) };
    format!("discretisation: {element} on {n_cells} curved {}; mesh {source}{params}{mirror}", family.cells_name())
}

/// The expected accuracy of the plate force for this discretisation (plate scenes on a sphere
/// `.geo` with R and h; None otherwise): the measured class (`scene::auto::Chart`).
pub(super) fn accuracy_class(scene: &Scene, family: Family) -> Option<String> {
    scene.plates.as_ref()?;
    let p = &scene.mesh.params;
    let h_over_r = p.get("h")? / p.get("R")?;
    let remodelling = match &scene.material {
        Material::HolmesMow(HolmesMowSpec { remodelling: Some(r), .. }) => Some(r.integrator),
        _ => None,
    };
    let geometry = if family.axisymmetric() { Geometry::Axisymmetric } else { Geometry::Solid };
    let element = if scene.fem.equal_order() { Element::P1P1 } else { Element::P2P1 };
    // Loading the scene parsed the chart, so it is there.
    let c = auto::chart().ok()?.class_of(geometry, element, remodelling, h_over_r)?;
    Some(format!(
        "expected accuracy (plate force, h/R = {h_over_r:.2}): {} [{}; docs/performance.md]",
        c.class, c.basis
    ))
}

/// The moduli of a mixture given by (µ, ν), however the scene named them: the solid's µ, which
/// the law takes, and the aggregate's drained moduli G = Φs µ and E = 2 G (1 + ν), which a lab
/// measures (None for other materials).
pub(super) fn moduli(scene: &Scene) -> Option<String> {
    let Material::HolmesMow(m) = &scene.material else { return None };
    let SolidSpec::MuNu { mu, nu } = m.solid().ok()? else { return None };
    let g = m.phi_s * mu;
    // Six significant digits: G = 0.6 × 20 kPa is 12, not 12.000000000000002.
    let shown = |x: f64| crate::io::fmt_significant(x, 6);
    Some(format!(
        "material: the solid's shear modulus µ = {} kPa (ν = {nu}); the aggregate's drained shear modulus Φs µ = {} \
         kPa, drained Young's modulus 2 Φs µ (1 + ν) = {} kPa",
        shown(mu),
        shown(g),
        shown(2.0 * g * (1.0 + nu))
    ))
}
