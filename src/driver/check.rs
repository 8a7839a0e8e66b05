//! The `poroplast check` command: a scene validated as `run` sets it up, through its first step.
//! (That every PETSc option was read after the first step is `petsc::options::ensure_all_used`'s;
//! the per-step Jacobian check, `-poroplast_check_jacobian`, is a step's: `step`.)

use super::args::{Log, RunArgs};
use super::entry::{petsc_args, tell_notes, with_petsc};
use super::progress::{Progress, Stages};
use super::resolved;
use super::setup::setup;
use crate::error::Result;
use crate::scene::LoadedScene;
use mpi::topology::SimpleCommunicator;

/// Validates a scene as `run` does (`poroplast check`): the set-up — scene, mesh (orientation,
/// folded elements), groups, plates against the mesh, anchor, probes, material — and the first
/// step, after which every PETSc option has been read; nothing is written.
pub fn check(world: &SimpleCommunicator, scene_arg: &str, set: &[String], petsc: &[String]) -> Result<String> {
    let scene = LoadedScene::load(scene_arg, set)?;
    tell_notes(world, &scene);
    let args = RunArgs {
        scene: scene_arg.into(),
        set: set.to_vec(),
        out: None,
        force: false,
        petsc: petsc.to_vec(),
        log: Log::Silent,
    };
    with_petsc(world, &petsc_args(&scene, petsc), || {
        let mut run = setup(world, &scene, &args, None)?;
        // The same first step as `run` (settling included), into no directory: then the PETSc
        // options have all been read, and the first solve has worked.
        let mut pg = Progress::start(run.dt0());
        run.first_step(&mut pg, Stages::register()?, true)?;
        let (mesh, info) = (run.problem().mesh(), run.setup_info());
        let warning = info.ellipticity.as_ref().map(|w| format!("\nwarning: {w}")).unwrap_or_default();
        let s = &scene.scene;
        let accuracy = run.accuracy().map(|a| format!("\n{a}")).unwrap_or_default();
        let moduli = resolved::moduli(s).map(|m| format!("\n{m}")).unwrap_or_default();
        Ok(format!(
            "{}: ok — mesh {} ({} {}, {} nodes, {} vertices; {} dofs), first step taken\n{}\n{}{moduli}{accuracy}{warning}",
            scene.source,
            info.mesh_path.display(),
            mesh.n_global_elems,
            mesh.family.cells_name(),
            mesh.n_global_nodes,
            mesh.n_global_vertices,
            info.n_global_dofs,
            resolved::discretisation(s, mesh.family, mesh.n_global_elems),
            info.solver_line
        ))
    })
}
