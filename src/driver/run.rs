//! A run set up ([`Run`]: the problem and its time stepper, the state between steps, the
//! observers and the schedule), what `poroplast run` was asked ([`RunArgs`]), and the time loop
//! ([`Run::execute`]). The rest of `Run` lives by concept in the other files of `driver`.

use super::progress::{Progress, Stages};
use super::schedule::Schedule;
use super::signals::StopRequest;
use super::state::StepState;
use crate::error::{Error, Result};
use crate::io::checkpoint::{FileLayout, RunState};
use crate::io::rundir;
use crate::observe::observers::Observers;
use crate::parallel::on_root;
use crate::petsc::Ts;
use crate::physics::problem::PoroProblem;
use crate::scene::LoadedScene;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::PathBuf;
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
    /// What the run prints on rank 0.
    pub log: Log,
}

/// What a run prints on standard output (rank 0). Warnings (standard error) print at every level.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Log {
    /// The scene's notes, the set-up, a progress line per step, the summary.
    Steps,
    /// `-q`: all of it but the per-step progress lines.
    Quiet,
    /// Nothing but warnings: a sweep's case (the sweep tells the scene's notes once, and a
    /// line per case).
    Silent,
}

/// A run set up: the problem and its time stepper, the state between steps, the observers and
/// the schedule.
pub(super) struct Run<'w> {
    pub(super) world: &'w SimpleCommunicator,
    pub(super) scene: LoadedScene,
    pub(super) args: RunArgs,
    pub(super) ts: Ts<PoroProblem>,
    /// U, U before the last step, and the last step's rate (the qp state is the problem's).
    pub(super) state: StepState,
    /// Probes, experiment, exact columns: what the rows and fields record.
    pub(super) observers: Observers,
    pub(super) schedule: Schedule,
    /// Settle under gravity before t = 0.
    pub(super) settle: bool,
    /// `-poroplast_check_jacobian [eps]`: after each step, compare the assembled Jacobian with
    /// central differences of the residual (`PoroProblem::jacobian_error`, relative step eps,
    /// default 1e-7) and print the errors.
    pub(super) jacobian_check: Option<f64>,
    pub(super) setup: SetupInfo,
    /// The run directory's lock, once it is opened.
    pub(super) lock: Option<rundir::RunLock>,
}

/// What the set-up found and took, for the log, the checkpoints and `timings.txt`.
pub(super) struct SetupInfo {
    /// The mesh file (given, or generated and cached).
    pub(super) mesh_path: PathBuf,
    /// The mesh file's node and element counts: the numbering of the run state.
    pub(super) layout: FileLayout,
    pub(super) n_global_dofs: usize,
    /// The linear solver policy, for the log.
    pub(super) solver_line: String,
    /// The solid law loses strong ellipticity under the run's strains (`ellipticity_warning`):
    /// printed at the start, and added to a failed solve's error.
    pub(super) ellipticity: Option<String>,
    /// When the set-up started, and its wall time.
    pub(super) started: Instant,
    pub(super) seconds: f64,
}

impl<'w> Run<'w> {
    /// The run, step by step, from t = 0 or from a checkpoint (`resume`). The first step runs
    /// before anything is written: then every PETSc option has been read, and an unknown one is
    /// an error that leaves no half-made (or, resuming, no truncated) run directory.
    pub(super) fn execute(&mut self, resume: Option<RunState>) -> Result<PathBuf> {
        let out = self.out_dir();
        let t_start = Instant::now();
        let stages = Stages::register()?;
        let resumed = resume.map(|state| self.restore(state)).transpose()?;
        let mut pg = resumed.as_ref().map_or_else(|| Progress::start(self.schedule.dt0), Progress::resumed);
        let (mut step, initial) = self.first_step(&mut pg, stages, resumed.is_none())?;
        // The last moment a stop leaves nothing behind: the outputs open next.
        super::signals::stop_in_setup(self.world, super::signals::NOTHING_WRITTEN)?;
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
                self.report_jacobian_error(&pg, step)?;
                if self.schedule.done(pg.c.t) {
                    return Ok(());
                }
                self.checkpoint_if_due(&rec, &mut pg, &stop, t_start)?;
                step = self.advance(&mut pg, stages)?;
            }
        })();
        // Whatever ended the run, the directory says so, with the timings so far; a completed
        // run with its summary.
        let finished = self.finish(&rec.dir, &pg, t_start, r.is_ok());
        let summary = match (&r, &finished) {
            (Ok(()), Ok(())) => self.summarise(&rec.dir, self.wall_so_far(&pg, t_start), pg.c.step, pg.c.t),
            _ => Ok(None),
        };
        let status = match (&r, &summary) {
            (Ok(()), Ok(Some(s))) => format!("completed: {} steps, t = {}; {}\n", pg.c.step, pg.c.t, s.headline()),
            (Ok(()), _) => format!("completed: {} steps, t = {}\n", pg.c.step, pg.c.t),
            (Err(e @ (Error::Stopped(_) | Error::StoppedInSetup(_))), _) => format!("{e}\n"),
            (Err(e), _) => format!("failed after step {} (t = {}): {e}\n", pg.c.step, pg.c.t),
        };
        on_root(self.world, || rundir::write_text(&rec.dir, "status.txt", &status))?;
        finished?;
        summary?;
        r.map(|()| rec.dir)
    }

    pub(super) fn rank0(&self) -> bool {
        self.world.rank() == 0
    }

    pub(super) fn say(&self, s: &str) {
        if self.rank0() && self.args.log != Log::Silent {
            crate::console::line(s);
        }
    }

    /// A warning that `-q` does not silence (rank 0, standard error).
    pub(super) fn warn(&self, s: &str) {
        if self.rank0() {
            eprintln!("poroplast: warning: {s}");
        }
    }
}

/// Exit code of a run stopped by a signal after writing its checkpoint (EX_TEMPFAIL: try
/// again, with `poroplast resume`); also of a `resume` stopped before it continued.
pub const EXIT_STOPPED: i32 = 75;

/// Exit code of a `run`, `check` or `sweep` stopped by a signal during its set-up, before it
/// wrote anything: there is nothing to resume, run the command again.
pub const EXIT_STOPPED_IN_SETUP: i32 = 76;
