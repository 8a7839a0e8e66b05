//! What a scene resolved to, for the run log and `poroplast check`: the element pair, the mesh
//! (its source and size parameters) and, for plate experiments, the accuracy class that the
//! measured error-against-time chart gives for that discretisation (docs/performance.md,
//! "3-D accuracy per second", made by `scripts/accuracy3d.py`).
//!
//! The classes are measured errors of the peak force and of F(35 s) of the `reference` and
//! `remodel_40` experiments against their converged meridian values, kept with the chart's data
//! (`scripts/data/accuracy_classes.toml`, read by `scene::auto`); other plate scenes are classed
//! only inside the domain of scenes each class was measured in (the drainage c_v t_ramp / R²,
//! the compression, the steps through the ramp, the stabilisation); outside it the line says so.

use super::schedule::Schedule;
use crate::fem::kernel::Stabilisation;
use crate::physics::problem::PoroProblem;
use crate::reference_cell::Family;
use crate::scene::{auto, Element, Geometry, Grading, Scene, SolidSpec};

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

/// The expected accuracy of the plate force of a run (plate scenes on a sphere `.geo` with R
/// and h; None otherwise): the measured class of its discretisation if the scene lies in the
/// domain that class was measured in (`scene::auto::Class::outside`), else a line that says
/// which group is outside and how to measure the run's own observables.
pub(super) fn accuracy_class(scene: &Scene, schedule: &Schedule, problem: &PoroProblem) -> Option<String> {
    // The steps through the ramp: the run's schedule (kinks, landings, cap), ending there.
    let ramp = scene.plates.as_ref()?.protocol().ramp;
    if !ramp.is_finite() {
        return None;
    }
    let mut through_ramp = schedule.clone();
    through_ramp.t_end = ramp;
    let ramp_steps = through_ramp.remaining(0.0, through_ramp.dt0);
    accuracy_line(scene, problem.mesh().family, problem.stabilisation(), ramp_steps)
}

/// `accuracy_class` given the stabilisation the run assembles with (its c_v = k0 (λ + 2µ) of
/// the reference state, µm²/s, and whether and how it fades) and the steps its schedule takes
/// through the ramp.
pub(super) fn accuracy_line(scene: &Scene, family: Family, stab: Stabilisation, ramp_steps: usize) -> Option<String> {
    let plates = scene.plates.as_ref()?;
    let p = &scene.mesh.params;
    let radius = *p.get("R")?;
    let h_over_r = p.get("h")? / radius;
    let remodelling = scene.material.mixture().and_then(|m| m.remodelling.as_ref()).map(|r| r.integrator);
    let geometry = if family.axisymmetric() { Geometry::Axisymmetric } else { Geometry::Solid };
    let element = if scene.fem.equal_order() { Element::P1P1 } else { Element::P2P1 };
    let protocol = plates.protocol();
    let hold_end = protocol.ends()[1];
    let hold = if hold_end <= scene.time.t_end {
        format!("F({} s)", crate::io::fmt_significant(hold_end, 6))
    } else {
        "F(end)".to_string()
    };
    let stabilisation = match stab.fade {
        _ if stab.c_s == 0.0 => auto::Stabilisation::Off,
        Some(_) => auto::Stabilisation::Faded,
        None => auto::Stabilisation::Constant,
    };
    let domain = auto::Domain {
        drainage: stab.c_v * protocol.ramp / (radius * radius),
        compression: plates.compression(),
        ramp_steps,
        stabilisation,
    };
    // Loading the scene parsed the chart, so it is there.
    let class = auto::chart().ok()?.class_of(geometry, element, remodelling, h_over_r, &domain)?;
    // The chart measured ramp-hold-release compressions of a Holmes–Mow solid without surface
    // tension.
    let model = scene.material.model().0;
    let class = if model != "holmes_mow" {
        Err(format!("a {model} solid; measured with Holmes–Mow"))
    } else if plates.table.is_some() {
        Err("a plates.table loading; measured on ramp-hold-release compressions".to_string())
    } else if scene.surface.is_some() {
        Err("surface tension; measured without".to_string())
    } else {
        class
    };
    let head = format!("expected accuracy (plate force, h/R = {h_over_r:.2})");
    Some(match class {
        Ok(c) => format!("{head}: {} [{}; docs/performance.md]", c.class.replace("{hold}", &hold), c.basis),
        Err(why) => format!(
            "{head}: none measured for this scene ({why}); measure its peak force and {hold} with \
             scripts/convergence_study.py (docs/howto-publication.md)"
        ),
    })
}

/// The moduli of a mixture given by (µ, ν), however the scene named them: the solid's µ, which
/// the law takes, and the aggregate's drained moduli G = Φs µ and E = 2 G (1 + ν), which a lab
/// measures (None for other materials).
pub(super) fn moduli(scene: &Scene) -> Option<String> {
    let m = scene.material.mixture()?;
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
