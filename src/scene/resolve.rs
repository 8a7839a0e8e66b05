//! From what a scene says to what a run uses, when it is loaded: the `auto` choices
//! ([`super::auto`]), sizes relative to the radius in µm, the plates' radius taken from the
//! mesh, deprecated keys moved to their new names (each with a note saying what to write), and
//! the defaults written out — so that the run directory's `scene.toml` shows every value the
//! run used, and a scene scales with one key, `mesh.params.R`.

use super::auto;
use super::material::Material;
use super::sections::Scene;

/// Resolves `scene` in place; Ok: the notes for the user (deprecated keys), Err: the message.
pub(super) fn resolve(scene: &mut Scene) -> Result<Vec<String>, String> {
    let mut notes = Vec::new();
    auto::resolve(scene)?;
    scene.mesh.resolve()?;
    if let Some(p) = &mut scene.plates {
        p.resolve(scene.mesh.params.get("R").copied(), &mut notes)?;
    }
    if let Some(sf) = &mut scene.surface {
        sf.resolve(scene.plates.as_ref().map(|p| p.radius()));
    }
    if let Some(m) = &mut scene.medium {
        m.resolve(scene.material.mixture());
    }
    scene.fem.fill_defaults(matches!(scene.material, Material::Linear { .. }));
    scene.solver.fill_defaults();
    Ok(notes)
}
