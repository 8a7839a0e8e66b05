//! One run: scene → PETSc → mesh → partition → problem → TS loop with output, in a run
//! directory holding the resolved scene, the PETSc options, `history.csv`, `fields.h5/.xdmf`
//! and `timings.txt`. Everything that can fail on bad input is checked before the run directory
//! is touched, so a failed start never damages an earlier run's results.

mod schedule;

pub use schedule::Schedule;

use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::element::tabulate_tet10;
use crate::fem::kernel::Stabilisation;
use crate::fem::quadrature;
use crate::io::recorder::{Observers, Recorder, StepRow};
use crate::io::rundir;
use crate::mesh::source::{mesh_file, read_mesh};
use crate::mesh::{dist, partition};
use crate::parallel::{agree, broadcast_u32};
use crate::petsc::{options, DmShell, Mat, Petsc, Stage, Ts, Vector};
use crate::physics::bc;
use crate::physics::contact::{PlateHistory, Plates, DEFAULT_SEAL_GAP};
use crate::physics::experiment::Experiment;
use crate::physics::factory::{ellipticity_warning, model_of};
use crate::physics::probe::Probe;
use crate::physics::problem::{mean_element_size, PoroProblem};
use crate::physics::verification::exact_columns;
use crate::scene::{LoadedScene, Material};
use crate::solver;
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
    let mut popts = scene.petsc_args();
    popts.extend(args.petsc.iter().cloned());
    let petsc = Petsc::init(&popts)?;
    let r = Run::setup(world, &scene, args).and_then(|mut run| run.execute());
    drop(petsc);
    r
}

/// Validates a scene and its mesh without solving (`poroplast check`).
pub fn check(world: &SimpleCommunicator, scene_arg: &str, set: &[String]) -> Result<String> {
    let scene = LoadedScene::load(scene_arg, set)?;
    let path = mesh_file(world, &scene)?;
    let mesh = agree(world, read_mesh(&path, &scene))?;
    let ctx = scene.source.clone();
    for bcnd in &scene.scene.bc {
        let known = mesh.face_groups.iter().any(|(n, _)| *n == bcnd.group)
            || mesh.point_groups.iter().any(|(n, _)| *n == bcnd.group);
        if !known {
            let names: Vec<&str> =
                mesh.face_groups.iter().chain(mesh.point_groups.iter()).map(|(n, _)| n.as_str()).collect();
            return Err(Error::Mesh {
                path: path.display().to_string(),
                msg: format!("{ctx}: physical group \"{}\" not found (the mesh has: {})", bcnd.group, names.join(", ")),
            });
        }
    }
    model_of(&scene)?;
    let warning = ellipticity_warning(&scene)?.map(|w| format!("\nwarning: {w}")).unwrap_or_default();
    Ok(format!(
        "{}: ok — mesh {} ({} tets, {} nodes, {} vertices){warning}",
        scene.source,
        path.display(),
        mesh.tets.len(),
        mesh.coords.len(),
        mesh.n_vertices()
    ))
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
    recent: std::collections::VecDeque<f64>,
}

impl<'w> Run<'w> {
    fn setup(world: &'w SimpleCommunicator, scene: &LoadedScene, args: &RunArgs) -> Result<Run<'w>> {
        let t0 = Instant::now();
        let _stage = Stage::register("Setup")?.push();
        let comm = world.as_raw();
        let s = &scene.scene;
        if s.plates.is_some() {
            // Contact: the active-set Newton of `solver::active_set` (unless -snes_type names a
            // PETSc VI solver, e.g. vinewtonrsls).
            // Full Newton steps: with the active set and drainage switching, the residual is
            // only piecewise smooth and backtracking stalls; a failed step is cut by TS instead.
            options::set_default("snes_linesearch_type", Some("basic"))?;
            // Each change of the active set costs an iteration; a step still cycling after 50
            // is cut by TS.
            options::set_default("snes_max_it", Some("50"))?;
        }
        let path = mesh_file(world, scene)?;
        let mesh = agree(world, read_mesh(&path, scene))?;
        let size = world.size() as usize;
        let mut part = Vec::new();
        let r = if world.rank() == 0 { partition::partition(&mesh, size).map(|p| part = p) } else { Ok(()) };
        agree(world, r)?;
        broadcast_u32(world, 0, &mut part);
        let local = agree(world, dist::distribute(&mesh, &part, size, world.rank() as usize))?;
        drop(mesh);
        let dofs = DofMap::new(&local);
        // Scene-specific defaults above win over the preset's (set_default keeps the first).
        let preset = s.solver.preset.as_deref().unwrap_or("auto");
        let policy = solver::set_default_options(preset, dofs.n_global)?;
        let mut solver_line = policy.describe(dofs.n_global, preset == "auto");
        if let Some(k) = crate::petsc::blas::kernel() {
            let why = if std::env::var_os("OPENBLAS_CORETYPE").is_some() { " (OPENBLAS_CORETYPE)" } else { "" };
            solver_line.push_str(&format!("; BLAS: OpenBLAS {k} kernels{why}"));
        }
        let model = model_of(scene)?;
        // Degree 2 integrates the linear model exactly on straight elements; the finite-strain
        // model (exponential energy, curved elements) gets the 8-point degree-3 rule.
        let default_degree = if model.is_linear() { 2 } else { 3 };
        let q = quadrature::tet(s.fem.quadrature_degree.unwrap_or(default_degree));
        let tab = tabulate_tet10(&q);
        let (mut cons, ext) = agree(world, bc::build(&s.bc, &local, &dofs, &scene.source))?;
        // Frictionless plates leave x, y translation and the rotation about z free unless
        // displacement constraints block them: the free ones are the Jacobian's null space.
        let constrained_u: Vec<usize> = cons.iter().map(|c| c.local).filter(|&l| l < 3 * dofs.n_nodes).collect();
        let free_modes = match s.plates {
            Some(_) => solver::FreeRigidModes::find(world, &dofs, &local, &constrained_u),
            None => None,
        };
        if let Some(m) = &free_modes {
            solver_line.push_str(&format!(
                "\nrigid modes left free by the plates (the Jacobian's null space): {}",
                m.describe()
            ));
            // MUMPS: factor the singular system, leaving the null pivots to the Krylov method.
            options::set_default("mat_mumps_icntl_24", Some("1"))?;
        }
        if matches!(s.material, Material::HolmesMow { drained: true, .. }) {
            cons.extend((0..local.n_vertices()).map(|v| bc::Constraint { local: dofs.p_local(v), value: 0.0 }));
        }
        // The plates and the surface faces that can touch them (also the experiment's).
        let plates = match &s.plates {
            Some(ps) => {
                let ctx = format!("{}: [plates]", scene.source);
                let faces = agree(world, bc::face_group(&local, &ps.group, &ctx))?.to_vec();
                let anchor = agree(world, bc::point_group(&local, &ps.anchor, &ctx))?.first().map(|&n| n as usize);
                let history =
                    PlateHistory { u_max: ps.compression * 2.0 * ps.radius, t_ramp: ps.t_ramp, t_end: ps.t_end };
                // Free-surface drainage conductance: γ k0 / h (a stiff Robin condition, p ≈ 0).
                let beta_max = ps.drainage_penalty * model.conductivity() / mean_element_size(world, &local);
                let seal_gap = ps.seal_gap.unwrap_or(DEFAULT_SEAL_GAP * ps.radius);
                Some((
                    Plates::new(
                        history,
                        ps.radius,
                        &local,
                        &faces,
                        anchor,
                        ps.drainage,
                        beta_max,
                        seal_gap,
                        ps.drainage_gap,
                    ),
                    faces,
                ))
            }
            None => None,
        };
        let probes = s.probe.iter().map(|p| Probe::new(p, &local, world, &scene.source)).collect::<Result<Vec<_>>>()?;
        let pre = dofs.preallocation(&local);
        let mut jac = Mat::aij(comm, dofs.n_owned, &pre.d_nnz, &pre.o_nnz)?;
        jac.set_name("Jacobian")?;
        let schur = Mat::aij(comm, dofs.n_owned_vertices, &pre.schur_d, &pre.schur_o)?;
        let mut u = Vector::mpi(comm, dofs.n_owned)?;
        u.set_name("solution")?;
        u.zero()?;
        if let Some(init) = &s.initial {
            let g = &init.displacement_gradient;
            let mut w = u.write()?;
            for n in 0..local.n_nodes() {
                let x = local.coords[n];
                for (c, row) in g.iter().enumerate() {
                    if let Some(i) = dofs.local_to_owned(dofs.u_local(n, c)) {
                        w[i] = row[0] * x[0] + row[1] * x[1] + row[2] * x[2];
                    }
                }
            }
        }
        let f = u.duplicate()?;
        let n_global_dofs = dofs.n_global;
        let fields = solver::Fields::new(world, &dofs, &local)?;
        let c = s.fem.stabilisation.unwrap_or(DEFAULT_STABILISATION);
        let stabilisation = Stabilisation::new(c, s.fem.stabilisation_fade, model.as_ref());
        let mut problem = PoroProblem::new(
            world.duplicate(),
            local,
            dofs,
            model,
            tab,
            q.points.clone(),
            cons,
            ext,
            &u,
            schur,
            stabilisation,
        )?;
        if s.fem.equal_order() {
            problem.tie_displacement();
        }
        let plate_faces = match plates {
            Some((pl, faces)) => {
                problem.attach_plates(pl, &u)?;
                Some(faces)
            }
            None => None,
        };
        let dm = DmShell::new(comm, &u, Box::new(fields))?;
        let mut ts = Ts::new(comm, problem, f, jac, None, Some(dm))?;
        let t = &s.time;
        let schedule = Schedule {
            t_end: t.t_end,
            dt0: t.dt,
            dt_max: t.dt_max.unwrap_or(t.t_end),
            growth: t.growth,
            land_on: t.land_on.iter().chain(&s.output.fields_at).copied().collect(),
            kinks: ts.problem().plates.iter().flat_map(|p| p.history.kinks()).collect(),
            tol: t.error_tolerance,
            dt_min: t.dt_min.unwrap_or(1e-6 * t.dt),
        };
        ts.set_solution(&u)?;
        ts.set_time(0.0)?;
        ts.set_time_step(schedule.step(0.0, schedule.dt0))?;
        ts.set_max_time(t.t_end)?;
        ts.set_max_rejections(t.max_retries)?;
        ts.set_from_options()?;
        // The finite-strain mixture's fluid-content rate is the backward-Euler difference
        // (J(F) − J(F − Δt Grad u̇))/Δt (docs/numerics.md): another integrator's u̇ would make
        // it inconsistent (measured with -ts_type bdf: F(35 s) 0.6–1% below every BE run).
        let ts_type = ts.type_name()?;
        if !ts.problem().disc.model.is_linear() && ts_type != "beuler" {
            return Err(Error::Solver(format!(
                "-ts_type {ts_type}: the finite-strain model's fluid-content rate is discretised for backward Euler only"
            )));
        }
        let snes = ts.snes()?;
        if let Some((lo, hi)) = &ts.problem().bounds {
            if options::has("snes_type")? {
                snes.set_vi_bounds(lo, hi)?;
            } else {
                let ksp = snes.ksp()?;
                ksp.use_dm_of(&snes)?;
                ksp.set_from_options()?;
                // Reusing a preconditioner needs a Krylov method to absorb the difference.
                let mut lag = if ksp.type_name()? == "preonly" { solver::Lag::NEVER } else { policy.lag };
                // No chord iterations when the Jacobian check assembles into the solve matrix
                // between steps.
                if options::has("poroplast_check_jacobian")? {
                    lag.chord = 0.0;
                }
                let mut newton = solver::ActiveSetNewton::new(world, lo, hi, ts.problem().u_row_scale(), lag)?;
                newton.monitor = options::has("poroplast_newton_monitor")?;
                newton.free_modes = free_modes;
                ts.set_nonlinear_solver(Box::new(newton))?;
            }
        }
        ts.problem_mut().schur_needed = solver::use_schur_matrix(&snes, &ts.problem().schur)?;
        let experiment = match (&s.plates, plate_faces) {
            (Some(ps), Some(faces)) => {
                let mesh = &ts.problem().disc.mesh;
                let volume = crate::parallel::sum(world, straight_volume(mesh));
                let phi = ts.problem().disc.model.solid_fraction();
                Some(Experiment::new(mesh, faces, ps.radius, volume, phi, world, &scene.source)?)
            }
            _ => None,
        };
        let settle = s.plates.is_some()
            && matches!(&s.material, Material::HolmesMow { gravity, .. } if gravity.iter().any(|g| *g != 0.0));
        let remodelling = !ts.problem().disc.history.is_empty();
        Ok(Run {
            world,
            scene: scene.clone(),
            args: args.clone(),
            ts,
            u,
            observers: Some(Observers {
                probes,
                experiment,
                exact: exact_columns(scene)?,
                remodelling,
                fields: s.output.fields,
            }),
            schedule,
            n_global_dofs,
            setup_s: t0.elapsed().as_secs_f64(),
            solver_line,
            settle,
            ellipticity: ellipticity_warning(scene)?,
            check_jacobian: match options::get_string("poroplast_check_jacobian")? {
                Some(v) if v.is_empty() => Some(1e-7),
                Some(v) => Some(v.parse().map_err(|_| {
                    Error::Solver(format!("-poroplast_check_jacobian {v}: expected a relative step like 1e-7"))
                })?),
                None => None,
            },
        })
    }

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

    /// The run directory: --out, or runs/<scene>-<UTC time> chosen by rank 0's clock.
    fn out_dir(&self) -> PathBuf {
        match &self.args.out {
            Some(o) => o.clone(),
            None => {
                let mut name =
                    rundir::default_run_dir(&self.scene.scene.name).to_string_lossy().into_owned().into_bytes();
                crate::parallel::broadcast_bytes(self.world, 0, &mut name);
                PathBuf::from(String::from_utf8_lossy(&name).into_owned())
            }
        }
    }

    /// Gravity settling: one drained step from t = −T to 0 with T huge (so J̇ ≈ 0 and the fluid
    /// is at rest): the equilibrium resting on the lower plate, the state at t = 0.
    fn settle(&mut self, stage: Stage) -> Result<()> {
        const T: f64 = 1e6;
        if !self.settle {
            return Ok(());
        }
        let _g = stage.push();
        // B_p(X, 0⁻) = I: no remodelling while settling.
        self.ts.problem_mut().disc.evolve = false;
        // From the undeformed sphere the whole weight comes down on one contact point: a full
        // Newton step can overshoot there (J < Φs) for soft solids (µ = 3 kPa); the active-set
        // Newton halves such steps.
        self.ts.set_time(-T)?;
        self.ts.set_time_step(T)?;
        self.ts.step()?;
        self.ts.problem_mut().disc.evolve = true;
        self.ts.set_time(0.0)
    }

    /// Every PETSc option must have been read once a step has run; report the others.
    fn check_options(&self) -> Result<()> {
        let unused: Vec<String> =
            options::unused()?.into_iter().filter(|o| !IGNORED_OPTIONS.contains(&o.as_str())).collect();
        if unused.is_empty() {
            return Ok(());
        }
        Err(Error::Solver(format!(
            "unknown or unused PETSc option(s): {} (check the spelling, or the solver they belong to)",
            unused.join(" ")
        )))
    }

    /// Creates the run directory and its files (nothing is written before this point).
    fn open_output(&mut self, dir: &Path) -> Result<Recorder> {
        agree(self.world, rundir::prepare(dir, self.args.force, self.rank0()))?;
        self.world.barrier();
        if self.rank0() {
            rundir::write_text(
                dir,
                "scene.toml",
                &format!("# resolved from {}\n{}", self.scene.source, self.scene.to_toml()),
            )?;
            rundir::write_text(dir, "petsc_options.txt", &(options::dump()? + "\n"))?;
        }
        let obs = self.observers.take().expect("the run directory opens once");
        Recorder::create(self.world, dir, &self.ts.problem().disc.mesh, obs)
    }

    /// A failed solve's error, with the likely cause when the solid law is not elliptic.
    fn explain(&self, e: Error) -> Error {
        match (e, &self.ellipticity) {
            (Error::Solver(m), Some(w)) => Error::Solver(format!("{m}. Likely cause: {w}")),
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
                return Err(self.explain(Error::Solver(format!(
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
        let its = (totals.0 - pg.newton, totals.1 - pg.ksp);
        (pg.newton, pg.ksp) = totals;
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

    /// The run, step by step (the first step runs before anything is written: then every
    /// PETSc option has been read, and an unknown one is an error that leaves no half-made run
    /// directory).
    fn execute(&mut self) -> Result<PathBuf> {
        let out = self.out_dir();
        let t_start = Instant::now();
        let stages = (Stage::register("Solve")?, Stage::register("Output")?);
        let mut pg = Progress { nominal: self.schedule.dt0, ..Default::default() };
        self.settle(stages.0)?;
        // Settling's iterations are not the experiment's.
        (pg.newton, pg.ksp) = self.ts.solver_totals()?;
        let initial = self.u.copy()?;
        // The history at t = 0, for the first row: the first step commits its own.
        let history0 = self.ts.problem().disc.history.clone();
        let mut prev = self.u.duplicate()?;
        let first = self.advance(&mut pg, &mut prev, stages.0)?;
        self.check_options()?;
        let mut rec = self.open_output(&out)?;
        self.announce(&out);
        let initial_row = StepRow { step: 0, t: 0.0, dt: 0.0, its: (0, 0), wall: t_start.elapsed().as_secs_f64() };
        self.write_initial(&mut rec, &initial, history0, &initial_row, stages.1)?;
        let mut cur = self.u.duplicate()?;
        let mut step = first;
        loop {
            self.output_step(&mut rec, &mut pg, &mut cur, &prev, step, t_start, stages.1)?;
            self.progress(&pg, step.0, step.1, t_start);
            self.check_jacobian(&pg, step.0, &cur, &prev)?;
            if self.schedule.done(pg.t) {
                break;
            }
            step = self.advance(&mut pg, &mut prev, stages.0)?;
        }
        self.finish(&rec.dir, &pg, t_start)?;
        Ok(rec.dir)
    }

    /// The run log's opening lines (rank 0).
    fn announce(&self, out: &Path) {
        let mesh = &self.ts.problem().disc.mesh;
        self.say(&format!(
            "poroplast: scene {} on {} rank(s): {} tets, {} nodes, {} dofs ({} u + {} p), output {}",
            self.scene.scene.name,
            self.world.size(),
            mesh.n_global_elems,
            mesh.n_global_nodes,
            self.n_global_dofs,
            3 * mesh.n_global_nodes,
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

    /// The row (and fields) of the initial state, recorded with the history it had.
    fn write_initial(
        &mut self,
        rec: &mut Recorder,
        initial: &Vector,
        mut history0: crate::fem::qp_store::QpStore,
        row: &StepRow,
        stage: Stage,
    ) -> Result<()> {
        let _g = stage.push();
        std::mem::swap(&mut self.ts.problem_mut().disc.history, &mut history0);
        let r = rec.record(self.world, self.ts.problem_mut(), initial, initial, row, true);
        std::mem::swap(&mut self.ts.problem_mut().disc.history, &mut history0);
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
            let row = StepRow { step: pg.step, t: pg.t, dt: taken, its, wall: t_start.elapsed().as_secs_f64() };
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

    /// timings.txt and the closing line.
    fn finish(&self, dir: &Path, pg: &Progress, t_start: Instant) -> Result<()> {
        let timers = self.ts.problem().timers;
        let cuts = self.ts.rejections()?;
        let total = t_start.elapsed().as_secs_f64() + self.setup_s;
        let assembly = timers.residual_s + timers.jacobian_s;
        let rss = crate::parallel::max(self.world, peak_rss_mib());
        let summary = format!(
            "# poroplast timings (seconds, rank 0; wall clock)\nranks = {}\ndofs = {}\nsteps = {}\nstep_cuts = {}\nerror_rejections = {}\nnewton_its = {}\nksp_its = {}\nsetup = {:.3}\nresidual_assembly = {:.3}\nresidual_evaluations = {}\njacobian_assembly = {:.3}\njacobian_evaluations = {}\nhistory_commit = {:.3}\nsolve_total = {:.3}\nlinear_solve_and_other = {:.3}\noutput = {:.3}\ntotal = {:.3}\nmax_rss_mib = {:.1}\n",
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
            timers.history_s,
            pg.solve_s,
            pg.solve_s - assembly,
            pg.output_s,
            total,
            rss
        );
        if self.rank0() {
            rundir::write_text(dir, "timings.txt", &summary)?;
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

/// Σ of the straight (vertex) tetrahedra volumes of the local elements.
fn straight_volume(mesh: &dist::LocalMesh) -> f64 {
    mesh.tets
        .iter()
        .map(|t| {
            let x = |i: usize| mesh.coords[t[i] as usize];
            let e = |i: usize| [x(i)[0] - x(0)[0], x(i)[1] - x(0)[1], x(i)[2] - x(0)[2]];
            let (a, b, c) = (e(1), e(2), e(3));
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                .abs()
                / 6.0
        })
        .sum()
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

fn human(s: f64) -> String {
    if s < 60.0 {
        format!("{s:.0}s")
    } else if s < 3600.0 {
        format!("{}m{:02}s", (s / 60.0) as u64, (s % 60.0) as u64)
    } else {
        format!("{}h{:02}m", (s / 3600.0) as u64, ((s % 3600.0) / 60.0) as u64)
    }
}
