//! A run set up ([`Run`]: its pieces — the stepper, the output, the checkpoints, its voice —
//! with the scene and what the set-up found, [`SetupInfo`]), and the time loop
//! ([`Run::execute`]) that composes the pieces: the steps, their rows and fields,
//! the checkpoints, the log, `timings.txt`, `status.txt` and the summary.

use super::args::RunArgs;
use super::checkpoint::Checkpoints;
use super::output::Output;
use super::progress::{Progress, Stages, Step};
use super::record::RunRecord;
use super::signals::StopRequest;
use super::step::Stepper;
use super::voice::Voice;
use crate::error::{Error, Result};
use crate::io::checkpoint::{Counters, FileLayout, RunState};
use crate::io::recorder::{Recorder, StepRow};
use crate::io::rundir;
use crate::observe::observers::Sample;
use crate::parallel::on_root;
use crate::petsc::SolverState;
use crate::physics::problem::PoroProblem;
use crate::scene::LoadedScene;
use mpi::traits::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What the set-up found and took, for the log and `timings.txt`.
pub(super) struct SetupInfo {
    /// The mesh file (given, or generated and cached).
    pub(crate) mesh_path: PathBuf,
    pub(crate) n_global_dofs: usize,
    /// The linear solver policy, for the log.
    pub(crate) solver_line: String,
    /// The solid law loses strong ellipticity under the run's strains (`ellipticity_warning`):
    /// printed at the start, and added to a failed solve's error.
    pub(crate) ellipticity: Option<String>,
    /// The set-up's wall time.
    pub(crate) seconds: f64,
}

/// A run set up: its pieces, the scene and what the set-up found.
pub(super) struct Run<'w> {
    voice: Voice<'w>,
    scene: LoadedScene,
    args: RunArgs,
    /// The time stepper with the problem, the state between steps and the schedule.
    stepper: Stepper,
    /// The observers and the run directory's outputs.
    output: Output,
    checkpoints: Checkpoints,
    setup: SetupInfo,
}

impl<'w> Run<'w> {
    /// The run of `scene` as `args` asked, from its pieces (`setup::setup` builds them).
    pub(crate) fn new(
        voice: Voice<'w>,
        scene: LoadedScene,
        args: RunArgs,
        stepper: Stepper,
        output: Output,
        checkpoints: Checkpoints,
        setup: SetupInfo,
    ) -> Run<'w> {
        Run { voice, scene, args, stepper, output, checkpoints, setup }
    }

    pub(crate) fn voice(&self) -> &Voice<'w> {
        &self.voice
    }

    pub(crate) fn problem(&self) -> &PoroProblem {
        self.stepper.problem()
    }

    /// What the set-up found and took.
    pub(crate) fn setup_info(&self) -> &SetupInfo {
        &self.setup
    }

    /// The numbering of the run state in checkpoints.
    pub(crate) fn checkpoint_layout(&self) -> FileLayout {
        self.checkpoints.layout()
    }

    /// Continues with the nonlinear solver state saved by a checkpoint (a resume on as many
    /// ranks).
    pub(crate) fn restore_solver_state(&mut self, state: SolverState) {
        self.stepper.restore_solver_state(state);
    }

    /// The nominal size of the first step.
    pub(crate) fn dt0(&self) -> f64 {
        self.stepper.schedule().dt0
    }

    /// The expected accuracy of the plate force (`resolved::accuracy_class`).
    pub(crate) fn accuracy(&self) -> Option<String> {
        super::resolved::accuracy_class(&self.scene.scene, self.stepper.schedule(), self.stepper.problem())
    }

    /// The run, step by step, from t = 0 or from a checkpoint (`resume`). The first step runs
    /// before anything is written: then every PETSc option has been read, and an unknown one is
    /// an error that leaves no half-made (or, resuming, no truncated) run directory.
    pub(crate) fn execute(&mut self, resume: Option<RunState>) -> Result<PathBuf> {
        let out = self.out_dir();
        let t_start = Instant::now();
        let stages = Stages::register()?;
        let resumed = resume.map(|state| self.restore(state)).transpose()?;
        let dt0 = self.stepper.schedule().dt0;
        let mut pg = resumed.as_ref().map_or_else(|| Progress::start(dt0), Progress::resumed);
        let (mut step, initial) = self.first_step(&mut pg, stages, resumed.is_none())?;
        // The last moment a stop leaves nothing behind: the outputs open next.
        super::signals::stop_in_setup(self.voice.world(), super::signals::NOTHING_WRITTEN)?;
        let record = RunRecord::of(&self.args);
        let problem = self.stepper.problem();
        let mut rec = match &resumed {
            Some(c) => self.output.reopen(&self.voice, &out, c, &record, problem)?,
            None => self.output.open(self.voice.world(), &out, self.args.force, &self.scene, &record, problem)?,
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
                self.stepper.report_jacobian_error(&pg, step, &self.voice)?;
                if self.stepper.schedule().done(pg.c.t) {
                    return Ok(());
                }
                self.checkpoint_if_due(&rec, &mut pg, &stop, t_start)?;
                step = self.stepper.advance(&mut pg, stages, self.voice.world())?;
            }
        })();
        // Whatever ended the run, the directory says so, with the timings so far; a completed
        // run with its summary.
        let finished = self.finish(&rec.dir, &pg, t_start, r.is_ok());
        let summary = match (&r, &finished) {
            (Ok(()), Ok(())) => super::summary::summarise(
                &self.voice,
                &self.scene.scene,
                self.accuracy(),
                self.output.observers().pressure_peak,
                &rec.dir,
                (self.wall_so_far(&pg, t_start), pg.c.step, pg.c.t),
            ),
            _ => Ok(None),
        };
        let status = match (&r, &summary) {
            (Ok(()), Ok(Some(s))) => format!("completed: {} steps, t = {}; {}\n", pg.c.step, pg.c.t, s.headline()),
            (Ok(()), _) => format!("completed: {} steps, t = {}\n", pg.c.step, pg.c.t),
            (Err(e @ (Error::Stopped(_) | Error::StoppedInSetup(_))), _) => format!("{e}\n"),
            (Err(e), _) => format!("failed after step {} (t = {}): {e}\n", pg.c.step, pg.c.t),
        };
        on_root(self.voice.world(), || rundir::write_text(&rec.dir, "status.txt", &status))?;
        finished?;
        summary?;
        r.map(|()| rec.dir)
    }

    /// Settling (when starting afresh) and the first step: run before anything is written, so
    /// that every PETSc option has been read and an unknown one is an error. Returns the step,
    /// and when starting afresh the state at t = 0 sampled for its row (with the qp state it
    /// has: the first step commits its own).
    pub(crate) fn first_step(
        &mut self,
        pg: &mut Progress,
        stages: Stages,
        fresh: bool,
    ) -> Result<(Step, Option<Sample>)> {
        let initial = if fresh {
            self.stepper.settle(stages.solve, &self.scene.scene, &self.voice)?;
            // Settling's iterations are not the experiment's.
            pg.totals = self.stepper.solver_totals()?;
            let _g = stages.output.push();
            Some(self.stepper.sample_initial(self.output.observers())?)
        } else {
            None
        };
        let step = self.stepper.advance(pg, stages, self.voice.world())?;
        crate::petsc::options::ensure_all_used()?;
        Ok((step, initial))
    }

    /// The run directory: --out, or runs/<scene>-<UTC time> chosen by rank 0's clock.
    fn out_dir(&self) -> PathBuf {
        match &self.args.out {
            Some(o) => o.clone(),
            None => crate::parallel::broadcast_path(
                self.voice.world(),
                Some(&rundir::default_run_dir(&self.scene.scene.name)),
            ),
        }
    }

    /// Sets the run state of a checkpoint: the step state (U, its rate, the qp state), the
    /// observers' cumulative values and t. Returns the counters.
    fn restore(&mut self, state: RunState) -> Result<Counters> {
        let c = self.stepper.restore(state)?;
        self.output.restore(&c);
        Ok(c)
    }

    /// The run log's opening lines (rank 0).
    fn announce(&self, out: &Path) {
        let mesh = self.stepper.problem().mesh();
        self.voice.say(&format!(
            "poroplast: scene {} on {} rank(s): {} {}, {} nodes, {} dofs ({} u + {} p), output {}",
            self.scene.scene.name,
            self.voice.world().size(),
            mesh.n_global_elems,
            mesh.family.cells_name(),
            mesh.n_global_nodes,
            self.setup.n_global_dofs,
            mesh.family.components() * mesh.n_global_nodes,
            mesh.n_global_vertices,
            out.display()
        ));
        if !self.scene.overrides.is_empty() {
            self.voice.say(&format!("overrides: --set {}", self.scene.overrides.join(" --set ")));
        }
        let s = &self.scene.scene;
        self.voice.say(&super::resolved::discretisation(s, mesh.family, mesh.n_global_elems));
        if let Some(m) = super::resolved::moduli(s) {
            self.voice.say(&m);
        }
        if let Some(a) = self.accuracy() {
            self.voice.say(&a);
        }
        self.voice.say(&self.setup.solver_line);
        if let Some(w) = &self.setup.ellipticity {
            self.voice.say(&format!("warning: {w}"));
        }
    }

    /// The row and fields of the initial state, sampled before the first step; observed after
    /// it (the experiment's outflow takes the drainage gaps of the last step solved).
    fn write_initial(&mut self, rec: &mut Recorder, sample: Sample, t_start: Instant, stages: Stages) -> Result<()> {
        let _g = stages.output.push();
        let world = self.voice.world();
        let observed = self.output.observe(world, self.stepper.problem(), sample, 0.0, 0.0, true);
        let row = StepRow { step: 0, t: 0.0, dt: 0.0, its: (0, 0), wall: t_start.elapsed().as_secs_f64() };
        rec.record(world, &row, &observed)
    }

    /// The row of the step just taken, with fields every `fields_every` steps, at the
    /// `fields_at` times and at the end.
    fn output_step(
        &mut self,
        rec: &mut Recorder,
        pg: &mut Progress,
        step: Step,
        t_start: Instant,
        stages: Stages,
    ) -> Result<()> {
        let o = Instant::now();
        {
            let _g = stages.output.push();
            let (n, t) = (pg.c.step, pg.c.t);
            let schedule = self.stepper.schedule();
            let fields = self.output.writes_fields(n, t, schedule.done(t), schedule.t_end);
            let sample = self.stepper.sample(self.output.observers(), t, step.dt, fields)?;
            let world = self.voice.world();
            let observed = self.output.observe(world, self.stepper.problem(), sample, t, step.dt, fields);
            let wall = pg.c.wall_s + t_start.elapsed().as_secs_f64();
            let row = StepRow { step: n, t, dt: step.dt, its: step.its, wall };
            rec.record(world, &row, &observed)?;
        }
        pg.c.output_s += o.elapsed().as_secs_f64();
        Ok(())
    }

    /// The progress line of a step (rank 0).
    fn progress(&self, pg: &Progress, step: Step, t_start: Instant) {
        if !self.voice.steps() {
            return;
        }
        let per_step = pg.recent.iter().sum::<f64>() / pg.recent.len().max(1) as f64;
        let eta = per_step * self.stepper.schedule().remaining(pg.c.t, pg.c.nominal) as f64;
        let (taken, its) = (step.dt, step.its);
        self.voice.say(&format!(
            "step {:5}  t = {:.5e}  dt = {:.3e}  newton {:2}  ksp {:4} ({:5.1}/newton)  [{:.1} s, eta {}]",
            pg.c.step,
            pg.c.t,
            taken,
            its.0,
            its.1,
            its.1 as f64 / its.0.max(1) as f64,
            t_start.elapsed().as_secs_f64(),
            crate::io::fmt_duration(eta)
        ));
    }

    /// A checkpoint after the step just recorded, if one is due; a stop signal writes one and
    /// ends the run (`Error::Stopped`).
    fn checkpoint_if_due(
        &mut self,
        rec: &Recorder,
        pg: &mut Progress,
        stop: &StopRequest,
        t_start: Instant,
    ) -> Result<()> {
        let world = self.voice.world();
        let stopping = stop.requested(world);
        let Some(due) = self.checkpoints.due(world, pg, stopping) else { return Ok(()) };
        let counters = self.output.counters(Counters {
            cuts: pg.c.cuts + self.stepper.rejections()?,
            wall_s: self.wall_so_far(pg, t_start),
            fields_written: rec.fields_written(),
            ..pg.c.clone()
        });
        let path = self.checkpoints.write(world, &mut self.stepper, rec, counters, due)?;
        pg.checkpointed = Some(Instant::now());
        if !stopping {
            return Ok(());
        }
        Err(Error::Stopped(format!(
            "stopped by a signal after step {} (t = {} s); checkpoint {}; continue with `{}`",
            pg.c.step,
            crate::io::fmt_time(pg.c.t),
            path.display(),
            crate::launch::command(world.size() as usize, &["resume", &rec.dir.display().to_string()])
        )))
    }

    /// Wall time of the run so far (s): the set-up, the sessions before this one (a resume), and
    /// this one's loop since `t_start`.
    fn wall_so_far(&self, pg: &Progress, t_start: Instant) -> f64 {
        pg.c.wall_s + t_start.elapsed().as_secs_f64() + self.setup.seconds
    }

    /// timings.txt, and the closing line of a completed run.
    fn finish(&self, dir: &Path, pg: &Progress, t_start: Instant, completed: bool) -> Result<()> {
        let world = self.voice.world();
        let timers = self.stepper.problem().timers();
        let cuts = pg.c.cuts + self.stepper.rejections()?;
        let total = self.wall_so_far(pg, t_start);
        let assembly = timers.residual_s + timers.jacobian_s;
        let rss = crate::parallel::max(world, peak_rss_mib());
        let summary = format!(
            "# poroplast timings (seconds, rank 0; wall clock; after a resume the stage times are this session's,\n# the counts and the total the whole run's)\nranks = {}\ndofs = {}\nsteps = {}\nstep_cuts = {}\nerror_rejections = {}\nnewton_its = {}\nksp_its = {}\nsetup = {:.3}\nresidual_assembly = {:.3}\nresidual_evaluations = {}\njacobian_assembly = {:.3}\njacobian_evaluations = {}\nhistory_commit = {:.3}\nsolve_total = {:.3}\nlinear_solve_and_other = {:.3}\noutput = {:.3}\ntotal = {:.3}\nmax_rss_mib = {:.1}\n",
            world.size(),
            self.setup.n_global_dofs,
            pg.c.step,
            cuts,
            pg.c.rejected,
            pg.c.newton,
            pg.c.ksp,
            self.setup.seconds,
            timers.residual_s,
            timers.residual_n,
            timers.jacobian_s,
            timers.jacobian_n,
            timers.qp_commit_s,
            pg.c.solve_s,
            pg.c.solve_s - assembly,
            pg.c.output_s,
            total,
            rss
        );
        on_root(world, || rundir::write_text(dir, "timings.txt", &summary))?;
        if !completed {
            return Ok(());
        }
        self.voice.say(&format!(
            "done: {} steps, {} Newton, {} Krylov iterations, {} step cuts, {} rejected by the error estimate, {:.1} s (setup {:.1}, assembly {:.1}, solve {:.1}, output {:.1})",
            pg.c.step,
            pg.c.newton,
            pg.c.ksp,
            cuts,
            pg.c.rejected,
            total,
            self.setup.seconds,
            assembly,
            pg.c.solve_s - assembly,
            pg.c.output_s
        ));
        Ok(())
    }
}

/// Peak resident memory of this process (MiB), from Linux's /proc/self/status (VmHWM); NaN
/// where that is not available.
fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

/// Exit code of a run stopped by a signal after writing its checkpoint (EX_TEMPFAIL: try
/// again, with `poroplast resume`); also of a `resume` stopped before it continued.
pub const EXIT_STOPPED: i32 = 75;

/// Exit code of a `run`, `check` or `sweep` stopped by a signal during its set-up, before it
/// wrote anything: there is nothing to resume, run the command again.
pub const EXIT_STOPPED_IN_SETUP: i32 = 76;
