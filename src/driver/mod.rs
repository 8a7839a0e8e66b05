//! One run: scene → PETSc → mesh → partition → problem → TS loop with output, in a run
//! directory holding the resolved scene, the PETSc options, `history.csv`, `fields.h5/.xdmf`
//! and `timings.txt`. Everything that can fail on bad input is checked before the run directory
//! is touched, so a failed start never damages an earlier run's results.

mod schedule;
mod setup;
pub(crate) mod signals;
pub mod state;

pub use schedule::Schedule;
use signals::StopRequest;
use state::{Checkpoint, Counters, RunState};

use crate::error::{Error, Result};
use crate::io::recorder::{Observers, Recorder, StepRow};
use crate::io::rundir;
use crate::parallel::{agree, on_root};
use crate::petsc::{options, Petsc, Stage, Ts, Vector};
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
        let per_elem = run.ts.problem().disc.qp_state.element(0).len();
        let fingerprint = state::mesh_fingerprint(world, &run.ts.problem().disc.mesh);
        // The last checkpoint that can be read (a damaged one is passed over, with a warning).
        let mut found = None;
        for path in checkpoints.iter().rev() {
            match RunState::read(world, path, run.n_file_nodes, run.n_file_elems, per_elem, fingerprint)? {
                Checkpoint::Read(state) => {
                    found = Some((path.clone(), state));
                    break;
                }
                Checkpoint::Damaged(e) => run.warn(&format!("{e}; trying the checkpoint before it")),
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

/// How a run was started (`DIR/run.toml`): what `resume` needs to set it up again.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct RunRecord {
    /// The scene argument (a file, made absolute, or a shipped scene's name).
    scene: String,
    set: Vec<String>,
    petsc: Vec<String>,
}

impl RunRecord {
    const FILE: &'static str = "run.toml";

    fn of(args: &RunArgs) -> RunRecord {
        let p = Path::new(&args.scene);
        let scene = if p.exists() {
            std::fs::canonicalize(p).map(|a| a.display().to_string()).unwrap_or_else(|_| args.scene.clone())
        } else {
            args.scene.clone()
        };
        RunRecord { scene, set: args.set.clone(), petsc: args.petsc.clone() }
    }

    fn read(dir: &Path) -> Result<RunRecord> {
        let path = dir.join(Self::FILE);
        let text =
            std::fs::read_to_string(&path).map_err(|e| Error::io(&path, format!("not a run directory ({e})")))?;
        toml::from_str(&text).map_err(|e| Error::io(&path, e.message().to_string()))
    }

    /// The scene, loaded as at the start; it must still resolve to the run's `scene.toml`.
    fn scene(&self, dir: &Path) -> Result<LoadedScene> {
        let scene = LoadedScene::load(&self.scene, &self.set)?;
        let path = dir.join("scene.toml");
        let was = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        let body = was.split_once('\n').map_or("", |(_, b)| b);
        if body != scene.to_toml()? {
            return Err(Error::io(
                &path,
                format!("{} no longer resolves to this run's scene (was it edited?): cannot resume", scene.source),
            ));
        }
        Ok(scene)
    }
}

/// Validates a scene as `run` does (`poroplast check`): the set-up — scene, mesh (orientation,
/// folded elements), groups, plates against the mesh, anchor, probes, material — and the first
/// step, after which every PETSc option has been read; nothing is written.
pub fn check(world: &SimpleCommunicator, scene_arg: &str, set: &[String], petsc: &[String]) -> Result<String> {
    let scene = LoadedScene::load(scene_arg, set)?;
    let args = RunArgs {
        scene: scene_arg.into(),
        set: set.to_vec(),
        out: None,
        force: false,
        petsc: petsc.to_vec(),
        progress: false,
    };
    with_petsc(world, &petsc_args(&scene, petsc), || {
        let mut run = Run::setup(world, &scene, &args)?;
        // The same first step as `run` (settling included), into no directory: then the PETSc
        // options have all been read, and the first solve has worked.
        let mut pg = Progress { nominal: run.schedule.dt0, ..Default::default() };
        let mut prev = run.u.duplicate()?;
        run.first_step(&mut pg, &mut prev, Stage::register("Solve")?, true)?;
        let mesh = &run.ts.problem().disc.mesh;
        let warning = run.ellipticity.as_ref().map(|w| format!("\nwarning: {w}")).unwrap_or_default();
        Ok(format!(
            "{}: ok — mesh {} ({} {}, {} nodes, {} vertices; {} dofs), first step taken\n{}{warning}",
            scene.source,
            run.mesh_path.display(),
            mesh.n_global_elems,
            mesh.family.cells_name(),
            mesh.n_global_nodes,
            mesh.n_global_vertices,
            run.n_global_dofs,
            run.solver_line
        ))
    })
}

struct Run<'w> {
    world: &'w SimpleCommunicator,
    scene: LoadedScene,
    args: RunArgs,
    ts: Ts<PoroProblem>,
    u: Vector,
    /// Probes, experiment and exact columns: moved into the recorder when the run directory opens.
    observers: Option<Observers>,
    schedule: Schedule,
    n_global_dofs: usize,
    setup_s: f64,
    /// The linear solver policy, for the log.
    solver_line: String,
    /// Settle under gravity before t = 0.
    settle: bool,
    /// The solid law loses strong ellipticity under the run's strains (`ellipticity_warning`):
    /// printed at the start, and added to a failed solve's error.
    ellipticity: Option<String>,
    /// `-poroplast_check_jacobian [eps]`: after each step, compare the assembled Jacobian with
    /// central differences of the residual (`PoroProblem::jacobian_error`, relative step eps,
    /// default 1e-7) and print the errors.
    check_jacobian: Option<f64>,
    /// The mesh file (given, or generated and cached).
    mesh_path: PathBuf,
    /// Nodes and elements of the mesh file: the numbering of the run state.
    n_file_nodes: usize,
    n_file_elems: usize,
    /// history.csv rows and fields steps written up to the checkpoint (a resumed run).
    resumed: Option<(usize, usize)>,
    /// The run directory's lock, once it is opened.
    lock: Option<rundir::RunLock>,
    started: Instant,
}

/// Where the time loop stands.
#[derive(Default)]
struct Progress {
    step: usize,
    t: f64,
    nominal: f64,
    newton: usize,
    ksp: usize,
    /// Steps rejected by the error estimate (solver failures are TS's step cuts).
    rejected: usize,
    solve_s: f64,
    output_s: f64,
    /// The solver's iteration totals after the last step (this process), to count a step's.
    totals: (usize, usize),
    /// Step cuts and wall time of the sessions before a resume.
    cuts_before: usize,
    wall_before: f64,
    /// Wall time of the last checkpoint (this process).
    checkpointed: Option<Instant>,
    recent: std::collections::VecDeque<f64>,
}

impl Progress {
    /// The loop's position after a resume from `c` (stage times count again: timings.txt gives
    /// this session's, with the whole run's counts and total).
    fn resumed(c: &Counters) -> Progress {
        Progress {
            step: c.step,
            t: c.t,
            nominal: c.nominal,
            newton: c.newton,
            ksp: c.ksp,
            rejected: c.rejected,
            cuts_before: c.cuts,
            wall_before: c.wall_s,
            ..Default::default()
        }
    }
}

impl<'w> Run<'w> {
    fn rank0(&self) -> bool {
        self.world.rank() == 0
    }

    /// t is one of the scene's `output.fields_at` times.
    fn output_time(&self, t: f64) -> bool {
        self.scene.scene.output.fields_at.iter().any(|&a| (t - a).abs() <= 1e-10 * self.schedule.t_end)
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

    /// The run directory: --out, or runs/<scene>-<UTC time> chosen by rank 0's clock.
    fn out_dir(&self) -> PathBuf {
        match &self.args.out {
            Some(o) => o.clone(),
            None => crate::parallel::broadcast_path(self.world, Some(&rundir::default_run_dir(&self.scene.scene.name))),
        }
    }

    /// Gravity settling: one drained step from t = −T to 0 with T huge (so J̇ ≈ 0 and the fluid
    /// is at rest): the equilibrium resting on the lower plate, the state at t = 0.
    ///
    /// From the undeformed sphere the whole weight comes down on one contact point: a full Newton
    /// step can overshoot there (J < Φs) for soft solids (µ = 3 kPa); the active-set Newton halves
    /// such steps. Where that is not enough — pole elements of a micrometre or less, which the
    /// weight alone compacts below Φs before a contact patch forms — the weight is applied in
    /// stages (`SETTLE_RAMP`), each settled state the start of the next.
    fn settle(&mut self, stage: Stage) -> Result<()> {
        const SETTLE_RAMP: [f64; 4] = [0.01, 0.1, 0.4, 1.0];
        if !self.settle {
            return Ok(());
        }
        let _g = stage.push();
        // B_p(X, 0⁻) = I: no remodelling while settling.
        self.ts.problem_mut().disc.evolve = false;
        let start = self.u.copy()?;
        if let Err(e) = self.settle_under(1.0) {
            self.warn(&format!("settling with the whole weight at once failed ({e}); applying it in stages"));
            self.u.copy_from(&start)?;
            for factor in SETTLE_RAMP {
                self.settle_under(factor)?;
            }
        }
        self.ts.problem_mut().disc.evolve = true;
        self.ts.set_time(0.0)
    }

    /// One settling step under `factor` times the scene's gravity.
    fn settle_under(&mut self, factor: f64) -> Result<()> {
        const T: f64 = 1e6;
        self.ts.problem_mut().disc.model.set_gravity_factor(factor);
        self.ts.set_time(-T)?;
        self.ts.set_time_step(T)?;
        let r = self.ts.step().map_err(|e| {
            self.explain(Error::Diverged(format!(
                "settling under gravity (the static equilibrium on the lower plate, before t = 0; \
                 {factor} of the weight) failed: {e}. Can the solid carry its weight (material.mu, material.gravity)?"
            )))
        });
        self.ts.problem_mut().disc.model.set_gravity_factor(1.0);
        r
    }

    /// Every PETSc option must have been read once a step has run; report the others.
    fn check_options(&self) -> Result<()> {
        let unused: Vec<String> =
            options::unused()?.into_iter().filter(|o| !IGNORED_OPTIONS.contains(&o.as_str())).collect();
        if unused.is_empty() {
            return Ok(());
        }
        Err(Error::Options(format!(
            "unknown or unused PETSc option(s): {} (check the spelling, or the solver they belong to)",
            unused.join(" ")
        )))
    }

    /// Creates the run directory and its files (nothing is written before this point).
    fn open_output(&mut self, dir: &Path) -> Result<Recorder> {
        agree(self.world, rundir::prepare(dir, self.args.force, self.rank0()))?;
        if self.lock.is_none() {
            self.lock = Some(agree(self.world, rundir::lock(dir, self.rank0()))?);
        }
        // Rank 0 writes; every rank learns whether it could (else the others would go on into
        // the collective creation of the fields file, and wait there).
        let options = options::dump()?;
        on_root(self.world, || {
            // An earlier run's checkpoints and status (--force) are not this run's.
            let old = dir.join(state::DIR);
            if old.is_dir() {
                std::fs::remove_dir_all(&old).map_err(|e| Error::io(&old, e))?;
            }
            let status = dir.join("status.txt");
            if status.exists() {
                std::fs::remove_file(&status).map_err(|e| Error::io(&status, e))?;
            }
            let scene = format!("# resolved from {}\n{}", self.scene.source, self.scene.to_toml()?);
            rundir::write_text(dir, "scene.toml", &scene)?;
            rundir::write_text(dir, "petsc_options.txt", &(options + "\n"))?;
            self.write_record(dir)
        })?;
        let obs = self.take_observers(dir)?;
        Recorder::create(self.world, dir, &self.ts.problem().disc.mesh, obs)
    }

    /// Reopens the run directory of a resumed run: history.csv and the fields continue after
    /// the checkpoint's step (later rows and steps, from after the checkpoint, are dropped).
    fn reopen_output(&mut self, dir: &Path) -> Result<Recorder> {
        // The options given to `resume` join the record, for the next resume.
        on_root(self.world, || self.write_record(dir))?;
        let obs = self.take_observers(dir)?;
        let counts = self.resumed.ok_or_else(|| {
            Error::io(dir, "the run directory was reopened for a resume, but no checkpoint was loaded")
        })?;
        let backup = state::fields_backup(dir);
        let (rec, warning) = Recorder::reopen(self.world, dir, &self.ts.problem().disc.mesh, obs, counts, &backup)?;
        if let Some(w) = warning {
            self.warn(&w);
        }
        Ok(rec)
    }

    /// The probes, experiment and exact columns, for the recorder of the run directory `dir`
    /// (which opens once per run).
    fn take_observers(&mut self, dir: &Path) -> Result<Observers> {
        self.observers
            .take()
            .ok_or_else(|| Error::io(dir, "the run directory was opened a second time in the same run"))
    }

    /// `run.toml`: how to set this run up again (rank 0).
    fn write_record(&self, dir: &Path) -> Result<()> {
        let record = toml::to_string(&RunRecord::of(&self.args))
            .map_err(|e| Error::io(dir.join(RunRecord::FILE), format!("cannot write the run record: {e}")))?;
        rundir::write_text(
            dir,
            RunRecord::FILE,
            &format!("# how this run was started, for `poroplast resume`\n{record}"),
        )
    }

    /// A failed solve's error, with the likely cause when the solid law is not elliptic.
    fn explain(&self, e: Error) -> Error {
        match (e, &self.ellipticity) {
            (Error::Diverged(m), Some(w)) => Error::Diverged(format!("{m}. Likely cause: {w}")),
            (e, _) => e,
        }
    }

    /// One time step from the current state; `prev` receives the state before it.
    fn advance(&mut self, pg: &mut Progress, prev: &mut Vector, stage: Stage) -> Result<(f64, (usize, usize))> {
        prev.copy_from(&self.u)?;
        let ws = Instant::now();
        let (taken, err) = loop {
            let dt = self.schedule.step(pg.t, pg.nominal);
            self.ts.set_time_step(dt)?;
            {
                let _g = stage.push();
                self.ts.step().map_err(|e| self.explain(e))?;
            }
            let taken = self.ts.time()? - pg.t;
            if taken < self.schedule.dt_min && taken < dt {
                let last =
                    self.ts.domain_errors().1.map(|d| format!("; last inadmissible state: {d}")).unwrap_or_default();
                return Err(self.explain(Error::Diverged(format!(
                    "failed solves cut the step from t = {} to {taken:.3e} s, below time.dt_min = {:.3e} s: \
                     the solve does not converge here{last}",
                    pg.t, self.schedule.dt_min
                ))));
            }
            let err = match self.schedule.tol {
                Some(tol) => self.ts.problem().step_error(prev, &self.u, taken, tol)?,
                None => None,
            };
            match self.schedule.reject(taken, err) {
                Some(retry) => {
                    // Too large an error: back to the start of the step, with a shorter one.
                    self.ts.roll_back()?;
                    pg.nominal = retry;
                    pg.rejected += 1;
                }
                None => break (taken, err),
            }
        };
        let wall = ws.elapsed().as_secs_f64();
        pg.solve_s += wall;
        pg.t = self.ts.time()?;
        pg.step += 1;
        let totals = self.ts.solver_totals()?;
        let its = (totals.0 - pg.totals.0, totals.1 - pg.totals.1);
        pg.totals = totals;
        pg.newton += its.0;
        pg.ksp += its.1;
        pg.nominal = self.schedule.grow(pg.nominal, taken, pg.t, err);
        let kink = self.schedule.at_kink(pg.t);
        // The step's rate serves the contact predictor and the error estimate; not across a kink.
        let keep_rate = !kink && (self.ts.problem().plates.is_some() || self.schedule.tol.is_some());
        self.ts.problem_mut().end_step(prev, &self.u, taken, keep_rate)?;
        if kink {
            self.ts.restart_step()?;
        }
        pg.recent.push_back(wall);
        if pg.recent.len() > 5 {
            pg.recent.pop_front();
        }
        Ok((taken, its))
    }

    /// The run, step by step, from t = 0 or from a checkpoint (`resume`). The first step runs
    /// before anything is written: then every PETSc option has been read, and an unknown one is
    /// an error that leaves no half-made (or, resuming, no truncated) run directory.
    fn execute(&mut self, resume: Option<RunState>) -> Result<PathBuf> {
        let out = self.out_dir();
        let t_start = Instant::now();
        let stages = (Stage::register("Solve")?, Stage::register("Output")?);
        let resuming = resume.is_some();
        let mut pg = match resume {
            Some(state) => self.restore(state)?,
            None => Progress { nominal: self.schedule.dt0, ..Default::default() },
        };
        let mut prev = self.u.duplicate()?;
        let (mut step, initial, qp_state0) = self.first_step(&mut pg, &mut prev, stages.0, !resuming)?;
        let mut rec = if resuming { self.reopen_output(&out)? } else { self.open_output(&out)? };
        self.announce(&out);
        if let Some(h0) = qp_state0 {
            let row = StepRow { step: 0, t: 0.0, dt: 0.0, its: (0, 0), wall: t_start.elapsed().as_secs_f64() };
            self.write_initial(&mut rec, &initial, h0, &row, stages.1)?;
        }
        let stop = StopRequest::install()?;
        let r = (|| -> Result<()> {
            let mut cur = self.u.duplicate()?;
            loop {
                self.output_step(&mut rec, &mut pg, &mut cur, &prev, step, t_start, stages.1)?;
                self.progress(&pg, step.0, step.1, t_start);
                self.check_jacobian(&pg, step.0, &cur, &prev)?;
                if self.schedule.done(pg.t) {
                    return Ok(());
                }
                let stopping = stop.requested(self.world);
                let every = self.scene.scene.output.checkpoint_every;
                let periodic = every > 0 && pg.step.is_multiple_of(every);
                if stopping || periodic || self.checkpoint_due(&pg) {
                    let path = self.checkpoint(&rec, &mut pg, t_start, periodic)?;
                    if stopping {
                        return Err(Error::Stopped(format!(
                            "stopped by a signal after step {} (t = {}); checkpoint {}; continue with \
                             `poroplast resume {}`",
                            pg.step,
                            pg.t,
                            path.display(),
                            rec.dir.display()
                        )));
                    }
                }
                step = self.advance(&mut pg, &mut prev, stages.0)?;
            }
        })();
        // Whatever ended the run, the directory says so, with the timings so far.
        let status = match &r {
            Ok(()) => format!("completed: {} steps, t = {}\n", pg.step, pg.t),
            Err(e @ Error::Stopped(_)) => format!("{e}\n"),
            Err(e) => format!("failed after step {} (t = {}): {e}\n", pg.step, pg.t),
        };
        on_root(self.world, || rundir::write_text(&rec.dir, "status.txt", &status))?;
        self.finish(&rec.dir, &pg, t_start, r.is_ok())?;
        r.map(|()| rec.dir)
    }

    /// A checkpoint by wall time is due after this step: `output.checkpoint_minutes` after the
    /// last (rank 0's clock decides).
    fn checkpoint_due(&self, pg: &Progress) -> bool {
        let o = &self.scene.scene.output;
        if o.checkpoint_minutes <= 0.0 {
            return false;
        }
        let since = pg.checkpointed.map_or(self.started.elapsed(), |c| c.elapsed()).as_secs_f64();
        let mut due = u8::from(since >= 60.0 * o.checkpoint_minutes);
        self.world.process_at_rank(0).broadcast_into(&mut due);
        due == 1
    }

    /// Writes the run state after the step just recorded (collective), and makes the next
    /// solve start as it would after resuming from this checkpoint, so that a resumed run
    /// repeats the uninterrupted one.
    fn checkpoint(&mut self, rec: &Recorder, pg: &mut Progress, t_start: Instant, periodic: bool) -> Result<PathBuf> {
        let counters = Counters {
            step: pg.step,
            t: pg.t,
            nominal: pg.nominal,
            newton: pg.newton,
            ksp: pg.ksp,
            rejected: pg.rejected,
            cuts: pg.cuts_before + self.ts.rejections()?,
            solve_s: pg.solve_s,
            output_s: pg.output_s,
            wall_s: pg.wall_before + t_start.elapsed().as_secs_f64() + self.setup_s,
            fields_written: rec.fields_written(),
            outflow: rec.outflow(),
        };
        let pb = self.ts.problem_mut();
        let u_local = pb.localize(&self.u)?;
        let v_local = match pb.velocity() {
            Some((v, dt)) => {
                let v = v.copy()?;
                Some((pb.localize(&v)?, dt))
            }
            None => None,
        };
        let pb = self.ts.problem();
        let mesh = &pb.disc.mesh;
        let per_elem = pb.disc.qp_state.element(0).len();
        let state = RunState::gather(
            self.world,
            mesh,
            &pb.disc.dofs,
            self.n_file_nodes,
            self.n_file_elems,
            counters,
            &u_local,
            v_local.as_ref().map(|(v, dt)| (v.as_slice(), *dt)),
            pb.disc.qp_state.export(&mesh.cell_original),
            per_elem,
        );
        // The solver's state between steps (the kept factorised Jacobian), per rank: a run
        // resumed on as many ranks continues exactly as this one. Where it cannot be saved the
        // solver starts afresh here, as a resumed run will.
        let solver = agree(self.world, self.ts.nonlinear_solver_state())?;
        let saved = crate::parallel::all(self.world, solver.is_some());
        let solver_written = match (&solver, saved) {
            (Some(s), true) => state::write_solver(&rec.dir, pg.step, self.world.rank(), self.world.size(), s),
            _ => Ok(()),
        };
        agree(self.world, solver_written)?;
        // The fields as of now, for a resume that finds fields.h5 damaged; before the state,
        // so that every checkpoint has a copy with at least its steps.
        rec.backup_fields(&state::fields_backup(&rec.dir))?;
        // Only at the checkpoints every N steps, which every run of the scene takes at the same
        // steps: restarting at wall-clock ones would make uninterrupted runs differ.
        if !saved && periodic {
            self.ts.restart_nonlinear_solver();
        }
        let path = crate::parallel::path_from_root(self.world, || state.write(&rec.dir))?;
        pg.checkpointed = Some(Instant::now());
        Ok(path)
    }

    /// Sets the run state of a checkpoint: U, the velocity, the qp state, t and the schedule.
    fn restore(&mut self, state: RunState) -> Result<Progress> {
        let c = state.counters.clone();
        let pb = self.ts.problem_mut();
        let (mesh, dofs) = (&pb.disc.mesh, &pb.disc.dofs);
        state::to_owned(mesh, dofs, &state.state, &mut self.u)?;
        let velocity = match &state.velocity {
            Some((v, dt)) => {
                let mut x = self.u.duplicate()?;
                state::to_owned(mesh, dofs, v, &mut x)?;
                Some((x, *dt))
            }
            None => None,
        };
        let per_elem = pb.disc.qp_state.element(0).len();
        if per_elem > 0 {
            let h = &state.qp_state;
            let original = mesh.cell_original.clone();
            pb.disc
                .qp_state
                .import(&original, |o| Some(h[o as usize * per_elem..(o as usize + 1) * per_elem].to_vec()))?;
        }
        pb.set_velocity(velocity);
        if let Some(ex) = self.observers.as_mut().and_then(|o| o.experiment.as_mut()) {
            ex.set_outflow(c.outflow);
        }
        self.ts.set_time(c.t)?;
        // Rows of steps 0..=step.
        self.resumed = Some((c.step + 1, c.fields_written));
        Ok(Progress::resumed(&c))
    }

    /// Settling (when starting afresh) and the first step: run before anything is written, so
    /// that every PETSc option has been read and an unknown one is an error. Returns the step,
    /// and when starting afresh the state and qp state at t = 0 (for the first row: the first
    /// step commits its own qp state).
    #[allow(clippy::type_complexity)]
    fn first_step(
        &mut self,
        pg: &mut Progress,
        prev: &mut Vector,
        stage: Stage,
        fresh: bool,
    ) -> Result<((f64, (usize, usize)), Vector, Option<crate::fem::qp_store::QpStore>)> {
        let qp_state0 = if fresh {
            self.settle(stage)?;
            // Settling's iterations are not the experiment's.
            pg.totals = self.ts.solver_totals()?;
            Some(self.ts.problem().disc.qp_state.clone())
        } else {
            None
        };
        let initial = self.u.copy()?;
        let step = self.advance(pg, prev, stage)?;
        self.check_options()?;
        Ok((step, initial, qp_state0))
    }

    /// The run log's opening lines (rank 0).
    fn announce(&self, out: &Path) {
        let mesh = &self.ts.problem().disc.mesh;
        self.say(&format!(
            "poroplast: scene {} on {} rank(s): {} {}, {} nodes, {} dofs ({} u + {} p), output {}",
            self.scene.scene.name,
            self.world.size(),
            mesh.n_global_elems,
            mesh.family.cells_name(),
            mesh.n_global_nodes,
            self.n_global_dofs,
            mesh.family.components() * mesh.n_global_nodes,
            mesh.n_global_vertices,
            out.display()
        ));
        if !self.scene.overrides.is_empty() {
            self.say(&format!("overrides: --set {}", self.scene.overrides.join(" --set ")));
        }
        self.say(&self.solver_line);
        if let Some(w) = &self.ellipticity {
            self.say(&format!("warning: {w}"));
        }
    }

    /// The row (and fields) of the initial state, recorded with the qp state it had.
    fn write_initial(
        &mut self,
        rec: &mut Recorder,
        initial: &Vector,
        mut qp_state0: crate::fem::qp_store::QpStore,
        row: &StepRow,
        stage: Stage,
    ) -> Result<()> {
        let _g = stage.push();
        std::mem::swap(&mut self.ts.problem_mut().disc.qp_state, &mut qp_state0);
        let r = rec.record(self.world, self.ts.problem_mut(), initial, initial, row, true);
        std::mem::swap(&mut self.ts.problem_mut().disc.qp_state, &mut qp_state0);
        r
    }

    /// The row of the step just taken, with fields every `fields_every` steps, at the
    /// `fields_at` times and at the end.
    #[allow(clippy::too_many_arguments)]
    fn output_step(
        &mut self,
        rec: &mut Recorder,
        pg: &mut Progress,
        cur: &mut Vector,
        prev: &Vector,
        (taken, its): (f64, (usize, usize)),
        t_start: Instant,
        stage: Stage,
    ) -> Result<()> {
        let o = Instant::now();
        {
            let _g = stage.push();
            let every = self.scene.scene.output.fields_every;
            let fields =
                self.schedule.done(pg.t) || (every > 0 && pg.step.is_multiple_of(every)) || self.output_time(pg.t);
            cur.copy_from(&self.u)?;
            let wall = pg.wall_before + t_start.elapsed().as_secs_f64();
            let row = StepRow { step: pg.step, t: pg.t, dt: taken, its, wall };
            rec.record(self.world, self.ts.problem_mut(), cur, prev, &row, fields)?;
        }
        pg.output_s += o.elapsed().as_secs_f64();
        Ok(())
    }

    /// `-poroplast_check_jacobian`: the assembled Jacobian of the step against central
    /// differences (rank 0 prints the errors).
    fn check_jacobian(&mut self, pg: &Progress, taken: f64, cur: &Vector, prev: &Vector) -> Result<()> {
        let Some(eps) = self.check_jacobian else { return Ok(()) };
        let (problem, jac) = self.ts.problem_and_jacobian();
        let (eu, ep) = problem.jacobian_error(pg.t, taken, cur, prev, jac, eps)?;
        if self.rank0() {
            println!("jacobian check: step {} t = {:.6e}: rel. error u rows {eu:.3e}, p rows {ep:.3e}", pg.step, pg.t);
        }
        Ok(())
    }

    /// The progress line of a step (rank 0).
    fn progress(&self, pg: &Progress, taken: f64, its: (usize, usize), t_start: Instant) {
        let per_step = pg.recent.iter().sum::<f64>() / pg.recent.len().max(1) as f64;
        let eta = per_step * self.schedule.remaining(pg.t, pg.nominal) as f64;
        self.say(&format!(
            "step {:5}  t = {:.5e}  dt = {:.3e}  newton {:2}  ksp {:4} ({:5.1}/newton)  [{:.1} s, eta {}]",
            pg.step,
            pg.t,
            taken,
            its.0,
            its.1,
            its.1 as f64 / its.0.max(1) as f64,
            t_start.elapsed().as_secs_f64(),
            human(eta)
        ));
    }

    /// timings.txt, and the closing line of a completed run.
    fn finish(&self, dir: &Path, pg: &Progress, t_start: Instant, completed: bool) -> Result<()> {
        let timers = self.ts.problem().timers;
        let cuts = pg.cuts_before + self.ts.rejections()?;
        let total = pg.wall_before + t_start.elapsed().as_secs_f64() + self.setup_s;
        let assembly = timers.residual_s + timers.jacobian_s;
        let rss = crate::parallel::max(self.world, peak_rss_mib());
        let summary = format!(
            "# poroplast timings (seconds, rank 0; wall clock; after a resume the stage times are this session's,\n# the counts and the total the whole run's)\nranks = {}\ndofs = {}\nsteps = {}\nstep_cuts = {}\nerror_rejections = {}\nnewton_its = {}\nksp_its = {}\nsetup = {:.3}\nresidual_assembly = {:.3}\nresidual_evaluations = {}\njacobian_assembly = {:.3}\njacobian_evaluations = {}\nhistory_commit = {:.3}\nsolve_total = {:.3}\nlinear_solve_and_other = {:.3}\noutput = {:.3}\ntotal = {:.3}\nmax_rss_mib = {:.1}\n",
            self.world.size(),
            self.n_global_dofs,
            pg.step,
            cuts,
            pg.rejected,
            pg.newton,
            pg.ksp,
            self.setup_s,
            timers.residual_s,
            timers.residual_n,
            timers.jacobian_s,
            timers.jacobian_n,
            timers.qp_commit_s,
            pg.solve_s,
            pg.solve_s - assembly,
            pg.output_s,
            total,
            rss
        );
        on_root(self.world, || rundir::write_text(dir, "timings.txt", &summary))?;
        if !completed {
            return Ok(());
        }
        self.say(&format!(
            "done: {} steps, {} Newton, {} Krylov iterations, {} step cuts, {} rejected by the error estimate, {:.1} s (setup {:.1}, assembly {:.1}, solve {:.1}, output {:.1})",
            pg.step,
            pg.newton,
            pg.ksp,
            cuts,
            pg.rejected,
            total,
            self.setup_s,
            assembly,
            pg.solve_s - assembly,
            pg.output_s
        ));
        Ok(())
    }
}

/// Exit code of a run stopped by a signal after writing its checkpoint (EX_TEMPFAIL: try
/// again, with `poroplast resume`).
pub const EXIT_STOPPED: i32 = 75;

/// Default c of the pressure stabilisation: 4 lumps the P1 mass of the undrained constraint
/// exactly (see `fem::kernel::ElementKernel::stab`).
pub const DEFAULT_STABILISATION: f64 = 4.0;

/// Options PETSc reads outside object set-up (at init/finalize) that `options_left` may list.
const IGNORED_OPTIONS: &[&str] = &[
    "-log_view",
    "-options_left",
    "-malloc_dump",
    "-malloc_debug",
    "-info",
    "-log_trace",
    "-on_error_abort",
    "-no_signal_handler",
];

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

fn human(s: f64) -> String {
    if s < 60.0 {
        format!("{s:.0}s")
    } else if s < 3600.0 {
        format!("{}m{:02}s", (s / 60.0) as u64, (s % 60.0) as u64)
    } else {
        format!("{}h{:02}m", (s / 3600.0) as u64, ((s % 3600.0) / 60.0) as u64)
    }
}
