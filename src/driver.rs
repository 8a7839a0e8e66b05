//! One run: scene → PETSc → mesh → partition → problem → TS loop with output, in a run
//! directory holding the resolved scene, the PETSc options, `history.csv`, `fields.h5/.xdmf`
//! and `timings.txt`. Everything that can fail on bad input is checked before the run directory
//! is touched, so a failed start never damages an earlier run's results.

use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::element::tabulate_tet10;
use crate::fem::kernel::Stabilisation;
use crate::fem::point::PointModel;
use crate::fem::quadrature;
use crate::io::fields::{Field, FieldFile, FieldKind, OutputMesh};
use crate::io::history::History;
use crate::io::rundir;
use crate::material::{ellipticity, HolmesMow};
use crate::mesh::{dist, gmsh, partition};
use crate::parallel::{agree, broadcast_u32};
use crate::petsc::{options, DmShell, Mat, Petsc, Stage, Ts, Vector};
use crate::physics::analytic;
use crate::physics::bc;
use crate::physics::biphasic::Biphasic;
use crate::physics::contact::{PlateHistory, Plates, DEFAULT_SEAL_GAP};
use crate::physics::experiment::{self, Experiment};
use crate::physics::linear::LinearPoroelastic;
use crate::physics::probe::Probe;
use crate::physics::problem::{mean_element_size, PoroProblem};
use crate::scene::{LoadedScene, Material, Verification};
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

/// Where generated meshes are cached.
fn cache_dir() -> PathBuf {
    if let Ok(d) = std::env::var("POROPLAST_CACHE") {
        return PathBuf::from(d);
    }
    if let Ok(d) = std::env::var("XDG_CACHE_HOME") {
        return Path::new(&d).join("poroplast");
    }
    if let Ok(h) = std::env::var("HOME") {
        return Path::new(&h).join(".cache/poroplast");
    }
    std::env::temp_dir().join("poroplast-cache")
}

/// The `.msh` file of a scene: given, or generated from its `.geo` by rank 0 (cached).
fn mesh_file(world: &SimpleCommunicator, scene: &LoadedScene) -> Result<PathBuf> {
    let spec = &scene.scene.mesh;
    if let Some(f) = &spec.file {
        return Ok(scene.resolve(f));
    }
    let geo = spec.geo.as_deref().unwrap_or_default();
    let local = scene.resolve(geo);
    let (name, source) = if local.exists() {
        let text = std::fs::read_to_string(&local).map_err(|e| Error::io(&local, e))?;
        (local.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(), text)
    } else if let Some((n, text)) = crate::scene::BUILTIN_GEO.iter().find(|(n, _)| *n == geo) {
        (n.to_string(), text.to_string())
    } else {
        return Err(Error::mesh(&local, "geometry source not found (not a file, nor a shipped .geo)"));
    };
    let params: Vec<(String, f64)> = spec.params.iter().map(|(k, v)| (k.clone(), *v)).collect();
    let mut path = Vec::new();
    let r = if world.rank() == 0 {
        crate::mesh::generate::cached(&name, &source, &params, 2, &cache_dir())
            .map(|p| path = p.to_string_lossy().into_owned().into_bytes())
    } else {
        Ok(())
    };
    agree(world, r)?;
    crate::parallel::broadcast_bytes(world, 0, &mut path);
    Ok(PathBuf::from(String::from_utf8_lossy(&path).into_owned()))
}

/// Reads the mesh file and applies the scene's reflections.
fn read_mesh(path: &Path, scene: &LoadedScene) -> Result<crate::mesh::Mesh> {
    let mut mesh = gmsh::read(path)?;
    for plane in &scene.scene.mesh.mirror {
        mesh = crate::mesh::mirror::mirror(&mesh, plane)?;
    }
    Ok(mesh)
}

/// The Holmes–Mow solid of a scene: from (µ, ν) by (56), or from its α's.
fn holmes_mow(mu: Option<f64>, nu: Option<f64>, alpha: &Option<[f64; 3]>, phi_s: f64) -> Result<HolmesMow> {
    match (mu, nu, alpha) {
        (Some(mu), Some(nu), _) => HolmesMow::from_mu_nu(mu, nu, phi_s),
        (_, _, Some(a)) => HolmesMow::new(phi_s, a[0], a[1], a[2], 1.0),
        _ => unreachable!("validated"),
    }
}

/// A warning for a solid law that loses strong ellipticity under the strains of a compression
/// experiment (`material::ellipticity`): there the solve stops converging, on every mesh.
fn ellipticity_warning(scene: &LoadedScene) -> Result<Option<String>> {
    let Material::HolmesMow { mu, nu, alpha, phi_s, .. } = &scene.scene.material else {
        return Ok(None);
    };
    let solid = holmes_mow(*mu, *nu, alpha, *phi_s)?;
    Ok(ellipticity::isochoric_compression_limit(&solid, 0.5)?.map(|lam| {
        format!(
            "the Holmes–Mow solid (alpha1 = {:.3} < 0{}) loses strong ellipticity beyond {:.1}% isochoric \
             compression: strains above that localise, and the solve stops converging there on any mesh \
             (docs/studies.md, stability (f))",
            solid.alpha1,
            nu.map(|n| format!(": nu = {n} > 1/3")).unwrap_or_default(),
            100.0 * (1.0 - lam)
        )
    }))
}

fn model_of(scene: &LoadedScene) -> Result<Box<dyn PointModel>> {
    use crate::material::{CompactionPenalty, FlowForm, Integrator, Permeability, PermeabilityModel, Remodelling};
    let ctx = |e: Error| Error::Scene { path: scene.source.clone(), msg: format!("[material]: {e}") };
    match &scene.scene.material {
        Material::Linear { mu, nu, permeability } => Ok(Box::new(LinearPoroelastic::new(*mu, *nu, *permeability)?)),
        Material::HolmesMow {
            mu,
            nu,
            alpha,
            phi_s,
            k0,
            kappa,
            m0,
            permeability_c,
            penalty,
            rho_s,
            rho_f,
            gravity,
            remodelling,
            ..
        } => {
            let solid = holmes_mow(*mu, *nu, alpha, *phi_s).map_err(ctx)?;
            let pen = penalty
                .as_ref()
                .map(|p| CompactionPenalty::new(*phi_s, p.u0, p.j_cr, p.q, p.r))
                .transpose()
                .map_err(ctx)?;
            let model = match permeability_c {
                Some(c) => PermeabilityModel::RemodellingDependent { c: *c },
                None => PermeabilityModel::Isotropic,
            };
            let perm = Permeability::new(*k0, *phi_s, *kappa, *m0, model).map_err(ctx)?;
            let mut model = Biphasic::new(solid, pen, perm, *rho_s, *rho_f, *gravity).map_err(ctx)?;
            if let Some(r) = remodelling {
                let form = if r.form == "40a" { FlowForm::Spatial } else { FlowForm::Referential };
                let integrator = if r.integrator == "explicit" { Integrator::Explicit } else { Integrator::Implicit };
                let law = Remodelling::new(r.lambda_p, r.sigma_y).map_err(ctx)?;
                model = model.with_remodelling(law.with_form(form).with_integrator(integrator));
            }
            Ok(Box::new(model))
        }
    }
}

/// Time steps: chosen by a local error estimate (with `tol`) or by geometric growth, up to
/// dt_max, landing exactly on t_end and the `land_on` times, and restarting from dt0 after each
/// of the `kinks` (times where the loading rate jumps).
#[derive(Debug, Clone)]
pub struct Schedule {
    pub t_end: f64,
    pub dt0: f64,
    pub dt_max: f64,
    pub growth: f64,
    pub land_on: Vec<f64>,
    pub kinks: Vec<f64>,
    /// Error tolerance of the step controller (None: geometric growth).
    pub tol: Option<f64>,
    /// A step cut below this by failed solves is an error (see `TimeSpec::dt_min`).
    pub dt_min: f64,
}

/// The step controller's limits: a step may grow by at most `MAX_GROWTH` and shrink by at
/// most `MIN_SHRINK`; an estimate above `REJECT` (relative to the tolerance) rejects the step.
const MAX_GROWTH: f64 = 2.0;
const MIN_SHRINK: f64 = 0.2;
const REJECT: f64 = 2.0;

impl Schedule {
    fn eps(&self) -> f64 {
        1e-10 * self.t_end
    }
    /// The next landing time after t.
    fn next_landing(&self, t: f64) -> f64 {
        self.land_on.iter().chain(&self.kinks).copied().filter(|&l| l > t + self.eps()).fold(self.t_end, f64::min)
    }
    /// True if t is one of the kinks.
    pub fn at_kink(&self, t: f64) -> bool {
        self.kinks.iter().any(|&l| (t - l).abs() <= self.eps())
    }
    /// The step from t with nominal size `nominal`: cut to land on the next landing time, and
    /// stretched by up to 10% instead of leaving a sliver before it.
    pub fn step(&self, t: f64, nominal: f64) -> f64 {
        let land = self.next_landing(t);
        let gap = land - t;
        if nominal >= gap * (1.0 - 0.1) {
            gap
        } else if nominal > 0.5 * gap {
            0.5 * gap
        } else {
            nominal
        }
    }
    /// Nominal size after a step of nominal size `nominal` that actually took `taken` and ended
    /// at `t`. After landing on a kink of the loading the rate of change jumps: restart from
    /// the first step size and grow again.
    ///
    /// With an error estimate `err` (relative to the tolerance) the next step is the one that
    /// would meet the tolerance, 0.9 dt err^(−1/2) (BE: local error ∝ dt²), within
    /// [MIN_SHRINK, MAX_GROWTH] × dt; it does not shrink below the nominal step while the error
    /// is within tolerance (a step shortened to land on a time is not a sign of trouble).
    pub fn grow(&self, nominal: f64, taken: f64, t: f64, err: Option<f64>) -> f64 {
        if self.at_kink(t) {
            return self.dt0;
        }
        let next = match err {
            Some(e) => {
                let f = (0.9 / e.max(1e-12).sqrt()).clamp(MIN_SHRINK, MAX_GROWTH);
                if f >= 1.0 {
                    (taken * f).max(nominal)
                } else {
                    taken * f
                }
            }
            None => nominal * self.growth,
        };
        next.min(self.dt_max).min(2.0 * taken.max(nominal * 1e-3))
    }
    /// Whether an error estimate rejects the step, and the step to retry with.
    pub fn reject(&self, taken: f64, err: Option<f64>) -> Option<f64> {
        match err {
            Some(e) if e > REJECT && taken > 1e-3 * self.dt0 => Some(taken * (0.9 / e.sqrt()).max(MIN_SHRINK)),
            _ => None,
        }
    }
    pub fn done(&self, t: f64) -> bool {
        t >= self.t_end - self.eps()
    }
    /// Steps left from t (no retries), for the ETA.
    pub fn remaining(&self, mut t: f64, mut nominal: f64) -> usize {
        let mut n = 0;
        while !self.done(t) && n < 1_000_000 {
            let dt = self.step(t, nominal);
            t += dt;
            nominal = self.grow(nominal, dt, t, None);
            n += 1;
        }
        n
    }
}

struct Run<'w> {
    world: &'w SimpleCommunicator,
    scene: LoadedScene,
    args: RunArgs,
    ts: Ts<PoroProblem>,
    u: Vector,
    probes: Vec<Probe>,
    schedule: Schedule,
    mid_edges: Vec<(usize, usize, usize)>,
    n_global_dofs: usize,
    setup_s: f64,
    /// The linear solver policy, for the log.
    solver_line: String,
    /// Observables of the plates experiment, if the scene has plates.
    experiment: Option<Experiment>,
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

/// The open outputs of a run.
struct Output {
    dir: PathBuf,
    fields: Option<FieldFile>,
    history: History,
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
        let mid_edges = mid_edge_nodes(&local);
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
        Ok(Run {
            world,
            scene: scene.clone(),
            args: args.clone(),
            ts,
            u,
            probes,
            schedule,
            mid_edges,
            n_global_dofs,
            setup_s: t0.elapsed().as_secs_f64(),
            solver_line,
            experiment,
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

    /// The model keeps per-point history (remodelling): its observables and fields are written.
    fn remodelling(&self) -> bool {
        !self.ts.problem().disc.history.is_empty()
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
    fn settle(&mut self) -> Result<()> {
        const T: f64 = 1e6;
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
    fn open_output(&self, dir: &Path) -> Result<Output> {
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
        let mesh = &self.ts.problem().disc.mesh;
        let cells: Vec<[u32; 10]> =
            mesh.tets.iter().map(|t| std::array::from_fn(|a| mesh.node_global[t[a] as usize])).collect();
        let coords: Vec<[f64; 3]> = mesh.coords[..mesh.n_owned_nodes].to_vec();
        let omesh = OutputMesh {
            n_global_nodes: mesh.n_global_nodes,
            node_offset: mesh.node_offset,
            coords: &coords,
            n_global_cells: mesh.n_global_elems,
            cell_offset: mesh.elem_offset,
            cells: &cells,
        };
        let fields =
            if self.scene.scene.output.fields { Some(FieldFile::create(dir, self.world, &omesh)?) } else { None };
        let mut cols: Vec<String> = vec!["step".into(), "time".into(), "dt".into()];
        if self.experiment.is_some() {
            cols.extend(experiment::COLUMNS.iter().map(|c| c.to_string()));
        }
        if self.remodelling() {
            cols.extend(crate::physics::remodelling::COLUMNS.iter().map(|c| c.to_string()));
        }
        cols.extend(self.probes.iter().map(|p| p.name.clone()));
        cols.extend(exact_columns(&self.scene)?.into_iter().map(|(n, _)| n));
        cols.extend(["newton_its", "ksp_its", "wall_s"].map(String::from));
        let colrefs: Vec<&str> = cols.iter().map(|c| c.as_str()).collect();
        let ints: Vec<&str> = ["step", "newton_its", "ksp_its", "contact_nodes_upper", "contact_nodes_lower"]
            .into_iter()
            .filter(|c| colrefs.contains(c))
            .collect();
        let history = History::create(&dir.join("history.csv"), &colrefs, &ints, self.rank0())?;
        Ok(Output { dir: dir.to_path_buf(), fields, history })
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

    fn execute(&mut self) -> Result<PathBuf> {
        let out = self.out_dir();
        let t_start = Instant::now();
        let (stage_solve, stage_out) = (Stage::register("Solve")?, Stage::register("Output")?);
        let mut pg = Progress { nominal: self.schedule.dt0, ..Default::default() };
        if self.settle {
            let _g = stage_solve.push();
            self.settle()?;
        }
        // Settling's iterations are not the experiment's.
        (pg.newton, pg.ksp) = self.ts.solver_totals()?;
        let initial = self.u.copy()?;
        let mut prev = self.u.duplicate()?;
        // The first step runs before anything is written: then every PETSc option has been
        // read, and an unknown one is an error that leaves no half-made run directory.
        // (The history at t = 0, for the first row: the first step commits its own.)
        let mut history0 = self.ts.problem().disc.history.clone();
        let first = self.advance(&mut pg, &mut prev, stage_solve)?;
        self.check_options()?;
        let mut io = self.open_output(&out)?;
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
        let exact = exact_columns(&self.scene)?;
        let o = Instant::now();
        {
            let _g = stage_out.push();
            std::mem::swap(&mut self.ts.problem_mut().disc.history, &mut history0);
            self.record(&mut io, &initial, &initial, 0, 0.0, 0.0, (0, 0), t_start, true, &exact)?;
            std::mem::swap(&mut self.ts.problem_mut().disc.history, &mut history0);
            self.progress(&pg, first.0, first.1, t_start);
            let last = self.schedule.done(pg.t);
            let every = self.scene.scene.output.fields_every;
            let wf = last || (every > 0 && 1 % every == 0) || self.output_time(pg.t);
            let cur = self.u.copy()?;
            self.record(&mut io, &cur, &prev, 1, pg.t, first.0, first.1, t_start, wf, &exact)?;
        }
        pg.output_s += o.elapsed().as_secs_f64();
        let mut cur = self.u.duplicate()?;
        while !self.schedule.done(pg.t) {
            let (taken, its) = self.advance(&mut pg, &mut prev, stage_solve)?;
            let o = Instant::now();
            {
                let _g = stage_out.push();
                let every = self.scene.scene.output.fields_every;
                let wf =
                    self.schedule.done(pg.t) || (every > 0 && pg.step.is_multiple_of(every)) || self.output_time(pg.t);
                cur.copy_from(&self.u)?;
                self.record(&mut io, &cur, &prev, pg.step, pg.t, taken, its, t_start, wf, &exact)?;
            }
            pg.output_s += o.elapsed().as_secs_f64();
            self.progress(&pg, taken, its, t_start);
            if let Some(eps) = self.check_jacobian {
                let (problem, jac) = self.ts.problem_and_jacobian();
                let (eu, ep) = problem.jacobian_error(pg.t, taken, &cur, &prev, jac, eps)?;
                if self.rank0() {
                    println!(
                        "jacobian check: step {} t = {:.6e}: rel. error u rows {eu:.3e}, p rows {ep:.3e}",
                        pg.step, pg.t
                    );
                }
            }
        }
        self.finish(&io, &pg, t_start)?;
        Ok(io.dir)
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
    fn finish(&self, io: &Output, pg: &Progress, t_start: Instant) -> Result<()> {
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
            rundir::write_text(&io.dir, "timings.txt", &summary)?;
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

    /// One history row (and fields if asked) for state `u` reached from `prev` in a step dt.
    #[allow(clippy::too_many_arguments)]
    fn record(
        &mut self,
        io: &mut Output,
        u: &Vector,
        prev: &Vector,
        step: usize,
        t: f64,
        dt: f64,
        its: (usize, usize),
        t_start: Instant,
        write_fields: bool,
        exact: &[(String, ExactFn)],
    ) -> Result<()> {
        let world = self.world;
        let write_fields = write_fields && io.fields.is_some();
        // The post-processing element loop (reactions, cell fields) only when something reads
        // it; probes and history alone need just the local state.
        let post = if self.experiment.is_some() || write_fields || self.remodelling() {
            let dt_eff = if dt > 0.0 { dt } else { 1.0 };
            let udot = crate::physics::problem::rate(u, prev, dt_eff)?;
            Some(self.ts.problem_mut().post_process(dt_eff, u, &udot)?)
        } else {
            None
        };
        let localized;
        let local: &[f64] = match &post {
            Some(p) => &p.local,
            None => {
                localized = self.ts.problem_mut().localize(u)?;
                &localized
            }
        };
        let pb = self.ts.problem();
        let (mesh, dofs) = (&pb.disc.mesh, &pb.disc.dofs);
        let mut row = vec![step as f64, t, dt];
        let obs = match (&mut self.experiment, &pb.plates, &post) {
            (Some(ex), Some(pl), Some(post)) => {
                Some(ex.observe(t, dt, pl, mesh, dofs, post, pb.drainage_gaps(), world))
            }
            _ => None,
        };
        if let Some(o) = &obs {
            row.extend(o.values);
        }
        if let (Some(post), true) = (&post, !pb.disc.history.is_empty()) {
            row.extend(crate::physics::remodelling::observe(post, world));
        }
        row.extend(self.probes.iter().map(|p| p.value(mesh, dofs, local, world)));
        row.extend(exact.iter().map(|(_, f)| f(t)));
        row.extend([its.0 as f64, its.1 as f64, t_start.elapsed().as_secs_f64()]);
        io.history.row(&row)?;
        if let (Some(ff), Some(post), true) = (io.fields.as_mut(), &post, write_fields) {
            let n = mesh.n_owned_nodes;
            let uo: Vec<f64> = local[..3 * n].to_vec();
            let mut p = vec![0.0; n];
            for (node, pv) in p.iter_mut().enumerate() {
                let v = mesh.vertex_of_node[node];
                if v >= 0 {
                    *pv = local[dofs.p_local(v as usize)];
                }
            }
            for &(m, a, b) in &self.mid_edges {
                let pa = local[dofs.p_local(mesh.vertex_of_node[a] as usize)];
                let pb_ = local[dofs.p_local(mesh.vertex_of_node[b] as usize)];
                p[m] = 0.5 * (pa + pb_);
            }
            let rank = vec![world.rank() as f64; mesh.tets.len()];
            let mut fields = vec![
                Field { name: "u", kind: FieldKind::NodeVector, data: &uo },
                Field { name: "p", kind: FieldKind::NodeScalar, data: &p },
                Field { name: "J", kind: FieldKind::CellScalar, data: &post.cell_j },
                Field { name: "von_mises", kind: FieldKind::CellScalar, data: &post.cell_von_mises },
                Field { name: "darcy_flux", kind: FieldKind::CellVector, data: &post.cell_darcy },
                Field { name: "rank", kind: FieldKind::CellScalar, data: &rank },
            ];
            if pb.disc.model.solid_fraction().is_some() {
                fields.push(Field { name: "porosity", kind: FieldKind::CellScalar, data: &post.cell_porosity });
            }
            if let Some(o) = &obs {
                fields.push(Field { name: "contact", kind: FieldKind::NodeScalar, data: &o.node_contact });
            }
            if !pb.disc.history.is_empty() {
                fields.push(Field { name: "norm_ep", kind: FieldKind::CellScalar, data: &post.cell_norm_ep });
            }
            ff.write_step(t, &fields)?;
        }
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

type ExactFn = Box<dyn Fn(f64) -> f64>;

/// Exact-solution columns of a verification scene.
fn exact_columns(scene: &LoadedScene) -> Result<Vec<(String, ExactFn)>> {
    let Some(v) = &scene.scene.verification else { return Ok(vec![]) };
    let Material::Linear { mu, nu, permeability } = scene.scene.material.clone() else {
        return Err(Error::Scene {
            path: scene.source.clone(),
            msg: "[verification] needs material.model = \"linear\"".into(),
        });
    };
    let m = analytic::Drained::new(mu, nu, permeability)?;
    Ok(match v.clone() {
        Verification::Terzaghi { height, load } => vec![
            (
                "p_bottom_exact".into(),
                Box::new(
                    move |t| if t > 0.0 { analytic::terzaghi_pressure(0.0, t, height, load, &m) / load } else { 0.0 },
                ) as ExactFn,
            ),
            (
                "settlement_exact".into(),
                Box::new(move |t| if t > 0.0 { analytic::terzaghi_settlement(t, height, load, &m) } else { 0.0 }),
            ),
        ],
        Verification::Cryer { radius, load: _ } => {
            let series = analytic::CryerSeries::new(nu, 1e-6)?;
            let c = m.consolidation_coefficient();
            vec![(
                "p_center_exact".into(),
                Box::new(move |t| if t > 0.0 { series.center_pressure(c * t / (radius * radius)) } else { 0.0 })
                    as ExactFn,
            )]
        }
    })
}

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

/// (mid-edge node, end a, end b) for owned mid-edge nodes, to show P1 pressure on P2 nodes.
fn mid_edge_nodes(mesh: &dist::LocalMesh) -> Vec<(usize, usize, usize)> {
    let mut seen = vec![false; mesh.n_owned_nodes];
    let mut out = Vec::new();
    for t in &mesh.tets {
        for (e, &(a, b)) in crate::fem::element::TET10_EDGES.iter().enumerate() {
            let m = t[4 + e] as usize;
            if m < mesh.n_owned_nodes && !seen[m] {
                seen[m] = true;
                out.push((m, t[a] as usize, t[b] as usize));
            }
        }
    }
    out
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

#[cfg(test)]
mod tests {
    use super::Schedule;

    #[test]
    fn schedule_lands_on_kinks_and_end() {
        let s = Schedule {
            t_end: 10.0,
            dt0: 0.3,
            dt_max: 2.0,
            growth: 1.5,
            land_on: vec![7.7],
            kinks: vec![5.0],
            tol: None,
            dt_min: 1e-9,
        };
        let (mut t, mut nom) = (0.0, s.dt0);
        let mut times = vec![];
        while !s.done(t) {
            let dt = s.step(t, nom);
            assert!(dt > 0.0);
            t += dt;
            nom = s.grow(nom, dt, t, None);
            times.push(t);
        }
        assert!(times.iter().any(|&x| (x - 5.0).abs() < 1e-12), "{times:?}");
        // A plain landing time is hit without restarting the growth.
        let j = times.iter().position(|&x| (x - 7.7).abs() < 1e-12).expect("lands on 7.7");
        assert!(times[j + 1] - times[j] > 0.3 + 1e-9, "{times:?}");
        // After the kink the steps restart from dt0.
        let i = times.iter().position(|&x| (x - 5.0).abs() < 1e-12).unwrap();
        assert!((times[i + 1] - times[i] - 0.3).abs() < 1e-12, "{times:?}");
        assert!((t - 10.0).abs() < 1e-12);
        assert!(times.windows(2).all(|w| w[1] - w[0] <= 2.0 * 1.1 + 1e-12));
        assert_eq!(s.remaining(0.0, s.dt0), times.len());
    }

    #[test]
    fn controller_follows_the_error_estimate() {
        let s = Schedule {
            t_end: 100.0,
            dt0: 0.01,
            dt_max: 4.0,
            growth: 1.3,
            land_on: vec![],
            kinks: vec![35.0],
            tol: Some(1e-3),
            dt_min: 1e-9,
        };
        // BE: error ∝ dt², so the step meeting the tolerance is 0.9 dt / √err, within [0.2, 2] dt.
        assert!((s.grow(0.1, 0.1, 1.0, Some(0.81)) - 0.1).abs() < 1e-12);
        assert!((s.grow(0.1, 0.1, 1.0, Some(0.09)) - 0.2).abs() < 1e-12);
        assert!((s.grow(0.1, 0.1, 1.0, Some(1e-8)) - 0.2).abs() < 1e-12);
        assert!((s.grow(0.1, 0.1, 1.0, Some(1.8)) - 0.1 * 0.9 / 1.8f64.sqrt()).abs() < 1e-12);
        assert!((s.grow(3.0, 3.0, 1.0, Some(0.01)) - 4.0).abs() < 1e-12, "capped at dt_max");
        // A step shortened to land on a time does not shrink the next one while within tolerance.
        assert!((s.grow(0.5, 0.05, 1.0, Some(0.5)) - 0.5f64.min(0.1)).abs() < 1e-12);
        // No estimate (first step after a kink): geometric growth; on the kink: dt0.
        assert!((s.grow(0.1, 0.1, 1.0, None) - 0.13).abs() < 1e-12);
        assert!((s.grow(0.1, 0.1, 35.0, Some(0.5)) - 0.01).abs() < 1e-12);
        // Rejection above twice the tolerance, retrying with the step that would meet it.
        assert_eq!(s.reject(0.1, Some(1.9)), None);
        assert_eq!(s.reject(0.1, None), None);
        let r = s.reject(0.1, Some(4.0)).expect("rejected");
        assert!((r - 0.045).abs() < 1e-12);
        assert!((s.reject(0.1, Some(1e4)).unwrap() - 0.02).abs() < 1e-12, "at most ×0.2");
    }
}
