//! The driver's entry points: `run` a scene, `resume` a run from its last checkpoint, with
//! PETSc initialised for the call from the scene's and the user's options, and the scene's notes
//! told first.

use super::args::{Log, RunArgs};
use super::record::RunRecord;
use super::setup::setup;
use super::signals;
use crate::error::{Error, Result};
use crate::io::checkpoint::{self as checkpoint_file, Checkpoint, RunState};
use crate::io::rundir;
use crate::parallel::agree;
use crate::petsc::{options, Petsc};
use crate::scene::LoadedScene;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};

/// Runs a scene; returns the run directory. PETSc lives exactly as long as this call.
pub fn run(world: &SimpleCommunicator, args: &RunArgs) -> Result<PathBuf> {
    let scene = LoadedScene::load(&args.scene, &args.set)?;
    if args.log != Log::Silent {
        tell_notes(world, &scene);
    }
    signals::stop_in_setup(world, signals::NOTHING_WRITTEN)?;
    with_petsc(world, &petsc_args(&scene, &args.petsc), || {
        let mut run = setup(world, &scene, args, None)?;
        signals::stop_in_setup(world, signals::NOTHING_WRITTEN)?;
        run.execute(None)
    })
}

/// The scene's notes (deprecated keys, likely mistakes) on standard error, by rank 0.
pub(crate) fn tell_notes(world: &SimpleCommunicator, scene: &LoadedScene) {
    if world.rank() == 0 {
        for n in &scene.notes {
            eprintln!("poroplast: note: {}: {n}", scene.source);
        }
    }
}

/// Runs `f` with PETSc initialised on `world` from `options` and finalised after; an error about an
/// option's value names the option (only PETSc's live options database can tell which).
pub(super) fn with_petsc<T>(
    world: &SimpleCommunicator,
    options: &[String],
    f: impl FnOnce() -> Result<T>,
) -> Result<T> {
    let petsc = Petsc::init(world, options)?;
    let r = f().map_err(options::name_option);
    drop(petsc);
    r
}

/// Continues the run in `dir` from its last checkpoint (`poroplast resume`), with the scene,
/// overrides and PETSc options it was started with, then `petsc` (added, or overriding).
pub fn resume(world: &SimpleCommunicator, dir: &Path, petsc: &[String], log: Log) -> Result<PathBuf> {
    // Stopped before it continued, the run is as it was, and can be resumed again.
    resume_from_checkpoint(world, dir, petsc, log).map_err(|e| match e {
        Error::StoppedInSetup(m) => Error::Stopped(format!(
            "{}; continue with `{}`",
            m.replace(signals::NOTHING_WRITTEN, "the run directory is as it was"),
            crate::launch::command(world.size() as usize, &["resume", &dir.display().to_string()])
        )),
        e => e,
    })
}

fn resume_from_checkpoint(world: &SimpleCommunicator, dir: &Path, petsc: &[String], log: Log) -> Result<PathBuf> {
    let record = agree(world, RunRecord::read(dir))?;
    let status = std::fs::read_to_string(dir.join("status.txt")).unwrap_or_default();
    if status.starts_with("completed") {
        if world.rank() == 0 {
            crate::console::line(&format!("{}: the run has {}; nothing to resume", dir.display(), status.trim()));
        }
        return Ok(dir.to_path_buf());
    }
    // Before anything is read: a run still going in `dir` keeps it.
    let lock = agree(world, rundir::lock(dir, world.rank() == 0))?;
    // Killed before its first checkpoint: the run starts again from t = 0 in its directory.
    let checkpoints = agree(world, checkpoint_file::list(dir))?;
    let scene = agree(world, record.scene(dir))?;
    let mut options = record.petsc.clone();
    options.extend(petsc.iter().cloned());
    let args = RunArgs {
        scene: record.scene.clone(),
        set: record.set.clone(),
        out: Some(dir.to_path_buf()),
        force: true,
        petsc: options,
        log,
    };
    with_petsc(world, &petsc_args(&scene, &args.petsc), || {
        let mut run = setup(world, &scene, &args, Some(lock))?;
        signals::stop_in_setup(world, signals::NOTHING_WRITTEN)?;
        let per_elem = run.problem().qp_state_per_elem();
        let fingerprint = checkpoint_file::mesh_fingerprint(world, run.problem().mesh());
        let voice = *run.voice();
        // The last checkpoint that can be read (a damaged one is passed over, with a warning).
        let mut found = None;
        for path in checkpoints.iter().rev() {
            match RunState::read(world, path, run.checkpoint_layout(), per_elem, fingerprint)? {
                Checkpoint::Read(state) => {
                    found = Some((path.clone(), state));
                    break;
                }
                Checkpoint::Damaged(e) => voice.warn(&format!("{e}; trying the checkpoint before it")),
            }
        }
        let Some((checkpoint, state)) = found else {
            if !checkpoints.is_empty() {
                return Err(Error::io(dir, "no checkpoint of this run can be read (see the warnings above)"));
            }
            voice.say("no checkpoint yet: the run starts again from t = 0");
            return run.execute(None);
        };
        // The solver's state, if saved on as many ranks as now (else it starts afresh).
        let solver = checkpoint_file::read_solver(dir, state.counters.step, world.rank(), world.size());
        let found = crate::parallel::all(world, matches!(solver, Ok(Some(_))));
        match (solver, found) {
            (Ok(Some(s)), true) => run.restore_solver_state(s),
            (Err(e), _) => {
                voice.warn(&format!("{e}; the solver starts afresh (the resumed run matches to solver tolerance)"))
            }
            _ => {}
        }
        voice.say(&format!(
            "resuming from {} (step {}, t = {})",
            checkpoint.display(),
            state.counters.step,
            state.counters.t
        ));
        run.execute(Some(state))
    })
}

/// PETSc's command line: the scene's options, then the user's; PETSc's own signal handler off
/// (a stop signal is the run's, see `signals`).
pub(super) fn petsc_args(scene: &LoadedScene, user: &[String]) -> Vec<String> {
    let mut popts = scene.petsc_args();
    popts.extend(user.iter().cloned());
    if !popts.iter().any(|o| o == "-no_signal_handler") {
        popts.push("-no_signal_handler".into());
    }
    popts
}
