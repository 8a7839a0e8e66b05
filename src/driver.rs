//! One run: scene → PETSc → mesh → partition → problem → TS loop with output, in a run
//! directory holding the resolved scene, the PETSc options, `history.csv`, `fields.h5/.xdmf`
//! and `timings.txt`. Everything that can fail on bad input is checked before the run directory
//! is touched, so a failed start never damages an earlier run's results.

use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::element::tabulate_tet10;
use crate::fem::quadrature;
use crate::io::fields::{Field, FieldFile, FieldKind, OutputMesh};
use crate::io::history::History;
use crate::io::rundir;
use crate::mesh::{dist, gmsh, partition};
use crate::parallel::{agree, broadcast_u32};
use crate::petsc::{options, DmShell, Mat, Petsc, Stage, Ts, Vector};
use crate::physics::analytic;
use crate::physics::bc;
use crate::physics::linear::LinearPoroelastic;
use crate::physics::model::PointModel;
use crate::physics::probe::Probe;
use crate::physics::problem::PoroProblem;
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
    pub out: Option<PathBuf>,
    pub force: bool,
    pub petsc: Vec<String>,
    /// Print a progress line per step (rank 0).
    pub progress: bool,
}

/// Runs a scene; returns the run directory. PETSc lives exactly as long as this call.
pub fn run(world: &SimpleCommunicator, args: &RunArgs) -> Result<PathBuf> {
    let scene = LoadedScene::load(&args.scene)?;
    let mut popts = scene.petsc_args();
    popts.extend(args.petsc.iter().cloned());
    let petsc = Petsc::init(&popts)?;
    let r = Run::setup(world, &scene, args).and_then(|mut run| run.execute());
    drop(petsc);
    r
}

/// Validates a scene and its mesh without solving (`poroplast check`).
pub fn check(world: &SimpleCommunicator, scene_arg: &str) -> Result<String> {
    let scene = LoadedScene::load(scene_arg)?;
    let path = mesh_file(world, &scene)?;
    let mesh = agree(world, gmsh::read(&path))?;
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
    Ok(format!(
        "{}: ok — mesh {} ({} tets, {} nodes, {} vertices)",
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

fn model_of(scene: &LoadedScene) -> Result<Box<dyn PointModel>> {
    match &scene.scene.material {
        Material::Linear { mu, nu, permeability } => Ok(Box::new(LinearPoroelastic::new(*mu, *nu, *permeability)?)),
    }
}

/// Time steps: geometric growth to dt_max, landing exactly on t_end and the `land_on` times.
#[derive(Debug, Clone)]
pub struct Schedule {
    pub t_end: f64,
    pub dt0: f64,
    pub dt_max: f64,
    pub growth: f64,
    pub land_on: Vec<f64>,
}

impl Schedule {
    fn eps(&self) -> f64 {
        1e-10 * self.t_end
    }
    /// The next landing time after t.
    fn next_landing(&self, t: f64) -> f64 {
        self.land_on.iter().copied().filter(|&l| l > t + self.eps()).fold(self.t_end, f64::min)
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
    /// Nominal size after a step of nominal size `nominal` that actually took `taken`.
    pub fn grow(&self, nominal: f64, taken: f64) -> f64 {
        (nominal * self.growth).min(self.dt_max).min(2.0 * taken.max(nominal * 1e-3))
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
            nominal = self.grow(nominal, dt);
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
}

impl<'w> Run<'w> {
    fn setup(world: &'w SimpleCommunicator, scene: &LoadedScene, args: &RunArgs) -> Result<Run<'w>> {
        let t0 = Instant::now();
        let _stage = Stage::register("Setup")?.push();
        let comm = world.as_raw();
        let s = &scene.scene;
        solver::set_default_options(s.solver.preset.as_deref().unwrap_or("fieldsplit"))?;
        let path = mesh_file(world, scene)?;
        let mesh = agree(world, gmsh::read(&path))?;
        let size = world.size() as usize;
        let mut part = Vec::new();
        let r = if world.rank() == 0 { partition::partition(&mesh, size).map(|p| part = p) } else { Ok(()) };
        agree(world, r)?;
        broadcast_u32(world, 0, &mut part);
        let local = agree(world, dist::distribute(&mesh, &part, size, world.rank() as usize))?;
        drop(mesh);
        let dofs = DofMap::new(&local);
        let model = model_of(scene)?;
        // Degree 2 integrates the linear model exactly on straight elements.
        let q = quadrature::tet(s.fem.quadrature_degree.unwrap_or(2));
        let tab = tabulate_tet10(&q);
        let (cons, ext) = agree(world, bc::build(&s.bc, &local, &dofs, &scene.source))?;
        let probes = s.probe.iter().map(|p| Probe::new(p, &local, world, &scene.source)).collect::<Result<Vec<_>>>()?;
        let pre = dofs.preallocation(&local);
        let mut jac = Mat::aij(comm, dofs.n_owned, &pre.d_nnz, &pre.o_nnz)?;
        jac.set_name("Jacobian")?;
        let schur = Mat::aij(comm, dofs.n_owned_vertices, &pre.schur_d, &pre.schur_o)?;
        let jac_ref = jac.clone_ref()?;
        let mut u = Vector::mpi(comm, dofs.n_owned)?;
        u.set_name("solution")?;
        u.zero()?;
        let f = u.duplicate()?;
        let n_global_dofs = dofs.n_global;
        let mid_edges = mid_edge_nodes(&local);
        let fields = solver::Fields::new(comm, &dofs, &local)?;
        let alpha = s.fem.stabilisation.unwrap_or(DEFAULT_STABILISATION);
        let problem = PoroProblem::new(
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
            alpha,
        )?;
        let dm = DmShell::new(comm, &u, Box::new(fields))?;
        let mut ts = Ts::new(comm, problem, f, jac, None, Some(dm))?;
        let t = &s.time;
        let schedule = Schedule {
            t_end: t.t_end,
            dt0: t.dt,
            dt_max: t.dt_max.unwrap_or(t.t_end),
            growth: t.growth,
            land_on: t.land_on.clone(),
        };
        ts.set_solution(&u)?;
        ts.set_time(0.0)?;
        ts.set_time_step(schedule.step(0.0, schedule.dt0))?;
        ts.set_max_time(t.t_end)?;
        ts.set_max_rejections(t.max_retries)?;
        ts.set_from_options()?;
        let snes = ts.snes()?;
        solver::use_schur_matrix(&snes, &ts.problem().schur)?;
        // One trial linear solve on the first Jacobian: fieldsplit and AMG create their
        // sub-solvers lazily, so only then has every PETSc option been read, and unknown ones
        // can be reported before anything is written.
        let dt = schedule.step(0.0, schedule.dt0);
        let mut zero = u.duplicate()?;
        zero.zero()?;
        ts.problem_mut().assemble_jacobian(dt, 1.0 / dt, &u, &zero, &mut jac_ref.clone_ref()?)?;
        let ksp = snes.ksp()?;
        ksp.set_operators(&jac_ref, &jac_ref)?;
        let mut b = u.duplicate()?;
        b.set(1.0)?;
        ksp.solve(&b, &mut zero)?;
        let unused = options::unused()?;
        let unused: Vec<String> = unused.into_iter().filter(|o| !IGNORED_OPTIONS.contains(&o.as_str())).collect();
        if !unused.is_empty() {
            return Err(Error::Solver(format!(
                "unknown or unused PETSc option(s): {} (check the spelling, or the solver they belong to)",
                unused.join(" ")
            )));
        }
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
        })
    }

    fn rank0(&self) -> bool {
        self.world.rank() == 0
    }

    fn say(&self, s: &str) {
        if self.rank0() && self.args.progress {
            println!("{s}");
        }
    }

    fn execute(&mut self) -> Result<PathBuf> {
        let s = self.scene.scene.clone();
        let out = match &self.args.out {
            Some(o) => o.clone(),
            None => {
                // One clock decides the name.
                let mut name = rundir::default_run_dir(&s.name).to_string_lossy().into_owned().into_bytes();
                crate::parallel::broadcast_bytes(self.world, 0, &mut name);
                PathBuf::from(String::from_utf8_lossy(&name).into_owned())
            }
        };
        agree(self.world, rundir::prepare(&out, self.args.force, self.rank0()))?;
        self.world.barrier();
        if self.rank0() {
            rundir::write_text(
                &out,
                "scene.toml",
                &format!("# resolved from {}\n{}", self.scene.source, self.scene.to_toml()),
            )?;
            rundir::write_text(&out, "petsc_options.txt", &(options::dump()? + "\n"))?;
        }
        let n_ranks = self.world.size();
        let pb = self.ts.problem();
        let mesh = &pb.disc.mesh;
        self.say(&format!(
            "poroplast: scene {} on {} rank(s): {} tets, {} nodes, {} dofs ({} u + {} p), output {}",
            s.name,
            n_ranks,
            mesh.n_global_elems,
            mesh.n_global_nodes,
            self.n_global_dofs,
            3 * mesh.n_global_nodes,
            mesh.n_global_vertices,
            out.display()
        ));
        // Output files.
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
        let mut fields = if s.output.fields { Some(FieldFile::create(&out, self.world, &omesh)?) } else { None };
        let mut cols: Vec<String> = vec!["step".into(), "time".into(), "dt".into()];
        cols.extend(self.probes.iter().map(|p| p.name.clone()));
        let exact = exact_columns(&self.scene)?;
        cols.extend(exact.iter().map(|(n, _)| n.clone()));
        cols.extend(["newton_its", "ksp_its", "wall_s"].map(String::from));
        let colrefs: Vec<&str> = cols.iter().map(|c| c.as_str()).collect();
        let mut history =
            History::create(&out.join("history.csv"), &colrefs, &["step", "newton_its", "ksp_its"], self.rank0())?;

        let stage_solve = Stage::register("Solve")?;
        let stage_out = Stage::register("Output")?;
        let (mut t_solve, mut t_out) = (0.0, 0.0);
        let t_start = Instant::now();
        let mut step = 0usize;
        let mut nominal = self.schedule.dt0;
        let mut t = 0.0;
        let (mut tot_newton, mut tot_ksp) = (0usize, 0usize);
        let mut recent = std::collections::VecDeque::new();
        {
            let _g = stage_out.push();
            let o = Instant::now();
            self.record(&mut history, fields.as_mut(), step, t, 0.0, (0, 0), t_start, true, &exact)?;
            t_out += o.elapsed().as_secs_f64();
        }
        while !self.schedule.done(t) {
            let dt = self.schedule.step(t, nominal);
            self.ts.set_time_step(dt)?;
            let ws = Instant::now();
            {
                let _g = stage_solve.push();
                self.ts.step()?;
            }
            let wall = ws.elapsed().as_secs_f64();
            t_solve += wall;
            let t_new = self.ts.time()?;
            let taken = t_new - t;
            t = t_new;
            step += 1;
            let snes = self.ts.snes()?;
            let its = (snes.iterations()?, snes.linear_iterations()?);
            tot_newton += its.0;
            tot_ksp += its.1;
            nominal = self.schedule.grow(nominal, taken);
            let last = self.schedule.done(t);
            let write_fields = last || (s.output.fields_every > 0 && step.is_multiple_of(s.output.fields_every));
            {
                let _g = stage_out.push();
                let o = Instant::now();
                self.record(&mut history, fields.as_mut(), step, t, taken, its, t_start, write_fields, &exact)?;
                t_out += o.elapsed().as_secs_f64();
            }
            recent.push_back(wall);
            if recent.len() > 5 {
                recent.pop_front();
            }
            let per_step = recent.iter().sum::<f64>() / recent.len() as f64;
            let eta = per_step * self.schedule.remaining(t, nominal) as f64;
            self.say(&format!(
                "step {step:5}  t = {t:.5e}  dt = {taken:.3e}  newton {:2}  ksp {:4} ({:5.1}/newton)  [{:.1} s, eta {}]",
                its.0,
                its.1,
                its.1 as f64 / its.0.max(1) as f64,
                t_start.elapsed().as_secs_f64(),
                human(eta)
            ));
        }
        let timers = self.ts.problem().timers;
        let cuts = self.ts.rejections()?;
        let total = t_start.elapsed().as_secs_f64();
        let summary = format!(
            "# poroplast timings (seconds, rank 0; wall clock)\nranks = {}\ndofs = {}\nsteps = {}\nstep_cuts = {}\nnewton_its = {}\nksp_its = {}\nsetup = {:.3}\nresidual_assembly = {:.3}\nresidual_evaluations = {}\njacobian_assembly = {:.3}\njacobian_evaluations = {}\nsolve_total = {:.3}\nlinear_solve_and_other = {:.3}\noutput = {:.3}\ntotal = {:.3}\n",
            n_ranks,
            self.n_global_dofs,
            step,
            cuts,
            tot_newton,
            tot_ksp,
            self.setup_s,
            timers.residual_s,
            timers.residual_n,
            timers.jacobian_s,
            timers.jacobian_n,
            t_solve,
            t_solve - timers.residual_s - timers.jacobian_s,
            t_out,
            total + self.setup_s
        );
        if self.rank0() {
            rundir::write_text(&out, "timings.txt", &summary)?;
        }
        self.say(&format!(
            "done: {step} steps, {tot_newton} Newton, {tot_ksp} Krylov iterations, {} step cuts, {:.1} s (setup {:.1}, assembly {:.1}, solve {:.1}, output {:.1})",
            cuts,
            total + self.setup_s,
            self.setup_s,
            timers.residual_s + timers.jacobian_s,
            t_solve - timers.residual_s - timers.jacobian_s,
            t_out
        ));
        Ok(out)
    }

    /// One history row (and fields if asked) for the current state.
    #[allow(clippy::too_many_arguments)]
    fn record(
        &mut self,
        history: &mut History,
        fields: Option<&mut FieldFile>,
        step: usize,
        t: f64,
        dt: f64,
        its: (usize, usize),
        t_start: Instant,
        write_fields: bool,
        exact: &[(String, ExactFn)],
    ) -> Result<()> {
        let world = self.world;
        let local = self.ts.problem_mut().localize(&self.u)?;
        let pb = self.ts.problem();
        let (mesh, dofs) = (&pb.disc.mesh, &pb.disc.dofs);
        let mut row = vec![step as f64, t, dt];
        row.extend(self.probes.iter().map(|p| p.value(mesh, dofs, &local, world)));
        row.extend(exact.iter().map(|(_, f)| f(t)));
        row.extend([its.0 as f64, its.1 as f64, t_start.elapsed().as_secs_f64()]);
        history.row(&row)?;
        if let (Some(ff), true) = (fields, write_fields) {
            let n = mesh.n_owned_nodes;
            let u: Vec<f64> = local[..3 * n].to_vec();
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
            ff.write_step(
                t,
                &[
                    Field { name: "u", kind: FieldKind::NodeVector, data: &u },
                    Field { name: "p", kind: FieldKind::NodeScalar, data: &p },
                    Field { name: "rank", kind: FieldKind::CellScalar, data: &rank },
                ],
            )?;
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
    let Material::Linear { mu, nu, permeability } = scene.scene.material.clone();
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
        let s = Schedule { t_end: 10.0, dt0: 0.3, dt_max: 2.0, growth: 1.5, land_on: vec![5.0] };
        let (mut t, mut nom) = (0.0, s.dt0);
        let mut times = vec![];
        while !s.done(t) {
            let dt = s.step(t, nom);
            assert!(dt > 0.0);
            t += dt;
            nom = s.grow(nom, dt);
            times.push(t);
        }
        assert!(times.iter().any(|&x| (x - 5.0).abs() < 1e-12), "{times:?}");
        assert!((t - 10.0).abs() < 1e-12);
        assert!(times.windows(2).all(|w| w[1] - w[0] <= 2.0 * 1.1 + 1e-12));
        assert_eq!(s.remaining(0.0, s.dt0), times.len());
    }
}
