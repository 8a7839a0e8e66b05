//! One run: scene → PETSc → mesh → partition → problem → TS loop with output, in a run
//! directory holding the resolved scene, the PETSc options, `history.csv`, `fields.h5/.xdmf`
//! and `timings.txt`. Everything that can fail on bad input is checked before the run directory
//! is touched, so a failed start never damages an earlier run's results.
//!
//! This module holds the entry points (`run`, `resume`) and the time loop (`Run::execute`);
//! the rest, one concept a module: the set-up (`setup`), the `check` command (`check`), a time
//! step and settling (`step`), the step controller (`schedule`) and the step rate it acts on
//! (`rate`), the state between steps and the checkpoint files (`state`), writing and reading
//! checkpoints in a run (`checkpoint`), the run directory's outputs and log (`output`), what the
//! scene resolved to and its expected accuracy (`resolved`), the run record `run.toml` (`record`)
//! and stop signals (`signals`).

mod check;
mod checkpoint;
mod output;
mod rate;
mod record;
mod resolved;
mod schedule;
mod setup;
pub(crate) mod signals;
pub mod state;
mod step;

pub use check::check;
use record::RunRecord;
pub use schedule::Schedule;
use signals::StopRequest;
use state::{FileLayout, RunState, StepState};
use step::{Progress, Stages};

use crate::error::{Error, Result};
use crate::io::rundir;
use crate::parallel::{agree, on_root};
use crate::petsc::{options, Petsc, Ts};
use crate::physics::observers::Observers;
use crate::physics::problem::PoroProblem;
use crate::scene::LoadedScene;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `poroplast run` was asked to do.
#[derive(Debug, Clone)]
pub struct RunArgs {
    pub scene: String,
    /// `--set KEY=VALUE` overrides of scene values.
    pub set: Vec<String>,
    pub out: Option<PathBuf>,
    pub force: bool,
    pub petsc: Vec<String>,
    /// Print a progress line per step (rank 0).
    pub progress: bool,
}

/// Runs a scene; returns the run directory. PETSc lives exactly as long as this call.
pub fn run(world: &SimpleCommunicator, args: &RunArgs) -> Result<PathBuf> {
    let scene = LoadedScene::load(&args.scene, &args.set)?;
    with_petsc(world, &petsc_args(&scene, &args.petsc), || Run::setup(world, &scene, args)?.execute(None))
}

/// Runs `f` with PETSc initialised on `world` from `options` and finalised after; an error about an
/// option's value names the option (only PETSc's live options database can tell which).
fn with_petsc<T>(world: &SimpleCommunicator, options: &[String], f: impl FnOnce() -> Result<T>) -> Result<T> {
    let petsc = Petsc::init(world, options)?;
    let r = f().map_err(options::name_option);
    drop(petsc);
    r
}

/// Continues the run in `dir` from its last checkpoint (`poroplast resume`), with the scene,
/// overrides and PETSc options it was started with, then `petsc` (added, or overriding).
pub fn resume(world: &SimpleCommunicator, dir: &Path, petsc: &[String], progress: bool) -> Result<PathBuf> {
    let record = agree(world, RunRecord::read(dir))?;
    let status = std::fs::read_to_string(dir.join("status.txt")).unwrap_or_default();
    if status.starts_with("completed") {
        if world.rank() == 0 {
            println!("{}: the run has {}; nothing to resume", dir.display(), status.trim());
        }
        return Ok(dir.to_path_buf());
    }
    // Before anything is read: a run still going in `dir` keeps it.
    let lock = agree(world, rundir::lock(dir, world.rank() == 0))?;
    // Killed before its first checkpoint: the run starts again from t = 0 in its directory.
    let checkpoints = agree(world, state::list(dir))?;
    let scene = agree(world, record.scene(dir))?;
    let mut options = record.petsc.clone();
    options.extend(petsc.iter().cloned());
    let args = RunArgs {
        scene: record.scene.clone(),
        set: record.set.clone(),
        out: Some(dir.to_path_buf()),
        force: true,
        petsc: options,
        progress,
    };
    with_petsc(world, &petsc_args(&scene, &args.petsc), || {
        let mut run = Run::setup(world, &scene, &args)?;
        run.lock = Some(lock);
        let per_elem = run.ts.problem().qp_state_per_elem();
        let fingerprint = state::mesh_fingerprint(world, run.ts.problem().mesh());
        // The last checkpoint that can be read (a damaged one is passed over, with a warning).
        let mut found = None;
        for path in checkpoints.iter().rev() {
            match RunState::read(world, path, run.setup.layout, per_elem, fingerprint)? {
                state::Checkpoint::Read(state) => {
                    found = Some((path.clone(), state));
                    break;
                }
                state::Checkpoint::Damaged(e) => run.warn(&format!("{e}; trying the checkpoint before it")),
            }
        }
        let Some((checkpoint, state)) = found else {
            if !checkpoints.is_empty() {
                return Err(Error::io(dir, "no checkpoint of this run can be read (see the warnings above)"));
            }
            run.say("no checkpoint yet: the run starts again from t = 0");
            return run.execute(None);
        };
        // The solver's state, if saved on as many ranks as now (else it starts afresh).
        let solver = state::read_solver(dir, state.counters.step, world.rank(), world.size());
        let found = crate::parallel::all(world, matches!(solver, Ok(Some(_))));
        match (solver, found) {
            (Ok(Some(s)), true) => run.ts.restore_nonlinear_solver_state(s),
            (Err(e), _) => {
                run.warn(&format!("{e}; the solver starts afresh (the resumed run matches to solver tolerance)"))
            }
            _ => {}
        }
        run.say(&format!(
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
fn petsc_args(scene: &LoadedScene, user: &[String]) -> Vec<String> {
    let mut popts = scene.petsc_args();
    popts.extend(user.iter().cloned());
    if !popts.iter().any(|o| o == "-no_signal_handler") {
        popts.push("-no_signal_handler".into());
    }
    popts
}

/// A run set up: the problem and its time stepper, the state between steps, the observers and
/// the schedule.
struct Run<'w> {
    world: &'w SimpleCommunicator,
    scene: LoadedScene,
    args: RunArgs,
    ts: Ts<PoroProblem>,
    /// U, U before the last step, and the last step's rate (the qp state is the problem's).
    state: StepState,
    /// Probes, experiment, exact columns: what the rows and fields record.
    observers: Observers,
    schedule: Schedule,
    /// Settle under gravity before t = 0.
    settle: bool,
    /// `-poroplast_check_jacobian [eps]`: after each step, compare the assembled Jacobian with
    /// central differences of the residual (`PoroProblem::jacobian_error`, relative step eps,
    /// default 1e-7) and print the errors.
    check_jacobian: Option<f64>,
    setup: SetupInfo,
    /// The run directory's lock, once it is opened.
    lock: Option<rundir::RunLock>,
}

/// What the set-up found and took, for the log, the checkpoints and `timings.txt`.
struct SetupInfo {
    /// The mesh file (given, or generated and cached).
    mesh_path: PathBuf,
    /// The mesh file's node and element counts: the numbering of the run state.
    layout: FileLayout,
    n_global_dofs: usize,
    /// The linear solver policy, for the log.
    solver_line: String,
    /// The solid law loses strong ellipticity under the run's strains (`ellipticity_warning`):
    /// printed at the start, and added to a failed solve's error.
    ellipticity: Option<String>,
    /// When the set-up started, and its wall time.
    started: Instant,
    seconds: f64,
}

impl<'w> Run<'w> {
    /// The run, step by step, from t = 0 or from a checkpoint (`resume`). The first step runs
    /// before anything is written: then every PETSc option has been read, and an unknown one is
    /// an error that leaves no half-made (or, resuming, no truncated) run directory.
    fn execute(&mut self, resume: Option<RunState>) -> Result<PathBuf> {
        let out = self.out_dir();
        let t_start = Instant::now();
        let stages = Stages::register()?;
        let resumed = resume.map(|state| self.restore(state)).transpose()?;
        let mut pg = resumed.as_ref().map_or_else(|| Progress::start(self.schedule.dt0), Progress::resumed);
        let (mut step, initial) = self.first_step(&mut pg, stages, resumed.is_none())?;
        let mut rec = match &resumed {
            Some(c) => self.reopen_output(&out, c)?,
            None => self.open_output(&out)?,
        };
        self.announce(&out);
        if let Some(sample) = initial {
            self.write_initial(&mut rec, sample, t_start, stages)?;
        }
        let stop = StopRequest::install()?;
        let r = (|| -> Result<()> {
            loop {
                self.output_step(&mut rec, &mut pg, step, t_start, stages)?;
                self.progress(&pg, step, t_start);
                self.check_jacobian(&pg, step)?;
                if self.schedule.done(pg.c.t) {
                    return Ok(());
                }
                self.checkpoint_if_due(&rec, &mut pg, &stop, t_start)?;
                step = self.advance(&mut pg, stages)?;
            }
        })();
        // Whatever ended the run, the directory says so, with the timings so far.
        let status = match &r {
            Ok(()) => format!("completed: {} steps, t = {}\n", pg.c.step, pg.c.t),
            Err(e @ Error::Stopped(_)) => format!("{e}\n"),
            Err(e) => format!("failed after step {} (t = {}): {e}\n", pg.c.step, pg.c.t),
        };
        on_root(self.world, || rundir::write_text(&rec.dir, "status.txt", &status))?;
        self.finish(&rec.dir, &pg, t_start, r.is_ok())?;
        r.map(|()| rec.dir)
    }

    fn rank0(&self) -> bool {
        self.world.rank() == 0
    }

    fn say(&self, s: &str) {
        if self.rank0() && self.args.progress {
            println!("{s}");
        }
    }

    /// A warning that `-q` does not silence (rank 0, standard error).
    fn warn(&self, s: &str) {
        if self.rank0() {
            eprintln!("poroplast: warning: {s}");
        }
    }
}

/// Exit code of a run stopped by a signal after writing its checkpoint (EX_TEMPFAIL: try
/// again, with `poroplast resume`).
pub const EXIT_STOPPED: i32 = 75;

/// Default c of the pressure stabilisation: 4 lumps the P1 mass of the undrained constraint
/// exactly (see `fem::kernel::ElementKernel::stab`).
pub const DEFAULT_STABILISATION: f64 = 4.0;
