//! Setting a run up ([`setup`]): scene → mesh (partitioned) → dofs → solver policy → model →
//! the problem's parts, each complete (constraints and loads, plates, surface tension, Schur
//! matrix) → problem → time stepper and its solver → observers → the run's pieces. Everything
//! that can fail on bad input fails here, before the run directory is touched.

use super::args::RunArgs;
use super::checkpoint::Checkpoints;
use super::output::Output;
use super::run::{Run, SetupInfo};
use super::schedule::Schedule;
use super::state::StepState;
use super::step::Stepper;
use super::tool_setup;
use super::voice::Voice;
use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::element::tabulate_cell;
use crate::fem::kernel::{Fade, Stabilisation};
use crate::fem::point::PointModel;
use crate::fem::quadrature;
use crate::io::checkpoint::FileLayout;
use crate::io::rundir::RunLock;
use crate::mesh::dist::{self, LocalMesh};
use crate::mesh::partition;
use crate::mesh::source::{mesh_file, read_mesh};
use crate::observe::experiment::Experiment;
use crate::observe::observers::{mid_edge_nodes, Observers};
use crate::observe::probe::Probe;
use crate::observe::verification::exact_columns;
use crate::parallel::{agree, broadcast_vec, on_root};
use crate::petsc::{DmShell, Mat, Stage, Ts, Vector};
use crate::physics::bc::{self, Constraint};
use crate::physics::contact::{PlateLoading, Plates};
use crate::physics::drainage::{Drainage, DrainageGap, SurfaceDrainage};
use crate::physics::factory::{ellipticity_warning, model_of};
use crate::physics::medium::Medium;
use crate::physics::problem::untouched;
use crate::physics::problem::{PoroProblem, ProblemParts};
use crate::physics::suction::Suction;
use crate::physics::surface_tension::{Adhesion, SurfaceTension};
use crate::physics::tools::protocol::{Mode, ToolProtocol};
use crate::physics::tools::{Tool, ToolSet};
use crate::reference_cell::Family;
use crate::scene::LoadedScene;
use crate::solver;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::time::Instant;

/// The mesh partitioned and distributed, with the mesh file's node and element counts (the
/// numbering of the run state).
pub(super) struct Distributed {
    pub(crate) local: LocalMesh,
    pub(crate) path: std::path::PathBuf,
    pub(crate) layout: FileLayout,
}

/// A plate scene's mesh with fewer cells than `MIN_CELLS` is refused (sizes in the wrong unit:
/// a radius in mm and sizes in µm gave 3 triangles), with fewer than `FEW_CELLS` warned of (the
/// tests' deliberately coarse meridians have 18 to 97).
const MIN_CELLS: usize = 10;
const FEW_CELLS: usize = 100;

/// Reads (or generates) the scene's mesh, partitions it on rank 0 and distributes it; a plate
/// scene's mesh has at least `MIN_CELLS` cells (`FEW_CELLS`: a warning).
pub(super) fn distribute_mesh(world: &SimpleCommunicator, scene: &LoadedScene) -> Result<Distributed> {
    let spec = &scene.scene.mesh;
    let path = mesh_file(world, scene.mesh_source(), &spec.params, &scene.source)?;
    let mesh = agree(world, read_mesh(&path, spec.geometry.family(), &spec.mirror))?;
    if let Some(p) = scene.scene.plates.as_ref().filter(|_| mesh.cells.len() < FEW_CELLS) {
        let sizes: Vec<String> = spec.params.iter().map(|(k, v)| format!("{k} = {v}")).collect();
        let msg = format!(
            "the mesh has {} cells, fewer than {}: its sizes ({}) are coarse for an aggregate of radius R = {} µm \
             (lengths are µm; mesh.relative_sizes gives them as fractions of R)",
            mesh.cells.len(),
            if mesh.cells.len() < MIN_CELLS { MIN_CELLS } else { FEW_CELLS },
            sizes.join(", "),
            p.radius()
        );
        if mesh.cells.len() < MIN_CELLS {
            return Err(Error::Scene { path: scene.source.clone(), msg });
        }
        if world.rank() == 0 {
            eprintln!("poroplast: warning: {}: {msg}", scene.source);
        }
    }
    let size = world.size() as usize;
    if mesh.cells.len() < size {
        return Err(Error::Mesh {
            path: path.display().to_string(),
            msg: format!(
                "{} elements, fewer than the {size} ranks: run on at most {} ranks",
                mesh.cells.len(),
                mesh.cells.len()
            ),
        });
    }
    let mut part = on_root(world, || partition::partition(&mesh, size))?.unwrap_or_default();
    broadcast_vec(world, 0, &mut part);
    let local = agree(world, dist::distribute(&mesh, &part, size, world.rank() as usize))?;
    let layout = FileLayout { n_nodes: mesh.coords.len(), n_elems: mesh.cells.len() };
    Ok(Distributed { local, path, layout })
}

/// The scene's boundary conditions as constraints and loads; with plates, the rigid modes
/// they leave free.
fn constraints(
    world: &SimpleCommunicator,
    scene: &LoadedScene,
    local: &LocalMesh,
    dofs: &DofMap,
) -> Result<(Vec<Constraint>, Vec<f64>, Option<solver::FreeRigidModes>)> {
    let s = &scene.scene;
    let (mut cons, ext) = agree(world, bc::build(&s.bc, local, dofs, &scene.source))?;
    // Frictionless plates leave x, y translation and the rotation about z free unless
    // displacement constraints block them.
    let constrained_u: Vec<usize> = cons.iter().map(|c| c.local).filter(|&l| l < dofs.n_u_local()).collect();
    let free_modes = match s.plates {
        Some(_) => solver::FreeRigidModes::find(world, dofs, local, &constrained_u),
        None => {
            held(world, scene, local, &constrained_u)?;
            None
        }
    };
    if s.material.mixture().is_some_and(|m| m.drained) {
        cons.extend((0..local.n_vertices()).map(|v| Constraint { local: dofs.p_local(v), value: 0.0 }));
    }
    Ok((cons, ext, free_modes))
}

/// Without plates, the `[[bc]]` entries or tools pressing from both sides must hold the body: a
/// translation nothing blocks (along z on the meridian, any axis in 3-D) leaves the Newton system singular,
/// which would surface as a diverged first step (SNES reason -3) with no word of the cause.
fn held(world: &SimpleCommunicator, scene: &LoadedScene, local: &LocalMesh, constrained_u: &[usize]) -> Result<()> {
    let nc = local.family.components();
    let axes: Vec<usize> = if local.family.axisymmetric() { vec![nc - 1] } else { (0..nc).collect() };
    // Tools pressing from both sides along a direction hold it (while they touch).
    let opposed = |d: usize| {
        let along = |sign: f64| scene.scene.tools.iter().any(|t| sign * t.unit_axis()[d] > 0.5);
        along(1.0) && along(-1.0)
    };
    let free: Vec<&str> = axes
        .into_iter()
        .filter(|&c| {
            let here = f64::from(u8::from(constrained_u.iter().any(|&l| l % nc == c)));
            crate::parallel::max(world, here) == 0.0 && !opposed(local.family.axes()[c])
        })
        .map(|c| ["x", "y", "z"][local.family.axes()[c]])
        .collect();
    if free.is_empty() {
        return Ok(());
    }
    Err(Error::Scene {
        path: scene.source.clone(),
        msg: format!(
            "nothing holds the body along {}: the scene has no [plates], no [[bc]] displacement or roller and no \
             two [[tools]] pressing from both sides block that translation, so the first step cannot converge (add [plates], or a [[bc]] such as \
             `group = \"pole_bottom\"`, `displacement = {{ {} = 0.0 }}`)",
            free.join(", "),
            free[0]
        ),
    })
}

/// The plates and the surface faces that can touch them (also the experiment's).
fn plates(
    world: &SimpleCommunicator,
    scene: &LoadedScene,
    local: &LocalMesh,
    model: &dyn PointModel,
) -> Result<Option<(Plates, Vec<u32>)>> {
    let Some(ps) = &scene.scene.plates else { return Ok(None) };
    let ctx = format!("{}: [plates]", scene.source);
    // The plates are z = 0 and z = 2 radius at the start: the aggregate must rest between them.
    let (lo, hi) = local.coords.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x[2]), b.max(x[2])));
    let (z0, z1) = (-crate::parallel::max(world, -lo), crate::parallel::max(world, hi));
    let radius = ps.radius();
    let tol = 0.01 * radius;
    if (z0).abs() > tol || (z1 - 2.0 * radius).abs() > tol {
        return Err(Error::Scene {
            path: scene.source.clone(),
            msg: format!(
                "plates.radius = {}: the plates are at z = 0 and z = 2 radius = {}, but the mesh spans z = [{z0:.6}, \
                 {z1:.6}] (they must agree to 1% of the radius: set plates.radius to the aggregate's radius, or \
                 leave it out to take mesh.params.R)",
                radius,
                2.0 * radius
            ),
        });
    }
    let faces = agree(world, bc::face_group(local, &ps.group, &ctx))?.to_vec();
    let anchor = agree(world, bc::point_group(local, &ps.anchor, &ctx))?.first().map(|&n| n as usize);
    let loading = PlateLoading::table(ps.path().iter().map(|r| (r[0], r[1] * 2.0 * radius)).collect());
    // Free-surface drainage conductance: γ k0 / h (a stiff Robin condition, p ≈ 0).
    let beta_max = ps.drainage_penalty * model.conductivity() / local.mean_size(world);
    let drain = Drainage {
        on: ps.drainage,
        beta_max,
        // The paper's slightly permeable plates: a Robin outflow k_β / L through the contact area.
        beta_plate: ps.permeability.zip(ps.thickness).map_or(0.0, |(k, l)| k / l),
        // Filled in when the scene is loaded (`PlatesSpec::resolve`).
        seal_gap: ps.seal_gap.ok_or_else(|| Error::Scene {
            path: scene.source.clone(),
            msg: "plates.seal_gap was not resolved".into(),
        })?,
        gap: ps.drainage_gap,
    };
    let upper = ps.upper.as_deref().map_or_else(ToolProtocol::fixed, ToolProtocol::from_rows);
    let plates = Plates::new((loading, upper), radius, local, &faces, anchor, drain, scene.scene.fem.equal_order());
    // Force control from the start: the upper plate must touch the body at t = 0 (later
    // switches are checked when they are reached, `PoroProblem::predict`).
    if let Mode::Force(_) = plates.upper.at(f64::MIN_POSITIVE, 0.0) {
        let top = plates.nodes.iter().map(|&n| local.coords[n][2]).fold(f64::NEG_INFINITY, f64::max);
        let gap = plates.z_upper() - crate::parallel::max(world, top);
        if gap > plates.drain.seal_gap {
            return Err(Error::Scene {
                path: scene.source.clone(),
                msg: format!("plates.upper: {}", untouched(0.0, gap)),
            });
        }
    }
    Ok(Some((plates, faces)))
}

/// The surface's drainage (`physics::drainage`): the plates' (their faces and keys), or without
/// plates a `[drainage]` section's (its group; the iterate's gaps, as no predictor runs); None:
/// sealed.
fn drainage(
    world: &SimpleCommunicator,
    scene: &LoadedScene,
    local: &LocalMesh,
    model: &dyn PointModel,
    plates: Option<(&Plates, &[u32])>,
) -> Result<Option<SurfaceDrainage>> {
    let equal_order = scene.scene.fem.equal_order();
    if let Some((p, faces)) = plates {
        return Ok(Some(SurfaceDrainage::new(p.drain, local, faces, equal_order)));
    }
    let Some(spec) = &scene.scene.drainage else { return Ok(None) };
    let ctx = format!("{}: [drainage]", scene.source);
    let faces = agree(world, bc::face_group(local, &spec.group, &ctx))?;
    let params = Drainage {
        on: true,
        // A stiff Robin condition γ k0 / h, as for the plates.
        beta_max: spec.penalty * model.conductivity() / local.mean_size(world),
        beta_plate: 0.0,
        seal_gap: spec.seal_gap,
        gap: DrainageGap::Current,
    };
    Ok(Some(SurfaceDrainage::new(params, local, faces, equal_order)))
}

/// The stabilisation's fade τ₀ of the run: the scene's for Taylor–Hood; none (the constant
/// weight) for equal-order P1–P1, noted in the log line `solver_line` if the scene asked for one.
///
/// Why: for Taylor–Hood the term only keeps the undrained limit monotone, and a step that
/// resolves the drainage layer no longer needs it. P1–P1 fails the inf–sup condition itself:
/// the projection term is what controls its spurious pressure modes (Dohrmann & Bochev), and
/// the Darcy term k Δt ∫ ∇p·∇q, which also damps them once τ = c_v Δt / h² is of order one,
/// does not yet at the fade's τ₀ (0.03 in the reference scene): a faded P1–P1 step would have
/// neither.
fn stabilisation_fade(s: &crate::scene::Scene, solver_line: &mut String) -> Option<f64> {
    match (s.fem.equal_order(), s.fem.stabilisation_fade) {
        (true, Some(t)) => {
            solver_line.push_str(&format!(
                "\nfem.element = \"P1-P1\": pressure stabilisation at constant weight (fem.stabilisation_fade = {t} \
                 is for Taylor-Hood; equal order needs the term for inf-sup stability)"
            ));
            None
        }
        (_, fade) => fade,
    }
}

/// The initial state: zero, or the scene's affine displacement u = G X.
fn initial_state(
    comm: crate::petsc::ffi::MPI_Comm,
    scene: &LoadedScene,
    local: &LocalMesh,
    dofs: &DofMap,
) -> Result<Vector> {
    let mut u = Vector::mpi(comm, dofs.n_owned)?;
    u.set_name("solution")?;
    u.zero()?;
    if let Some(init) = &scene.scene.initial {
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
    Ok(u)
}

/// The time steps of the scene (landing on the loading's kinks and the output times).
fn schedule(scene: &LoadedScene, kinks: Vec<f64>) -> Schedule {
    let (t, o) = (&scene.scene.time, &scene.scene.output);
    let replay = !t.steps.is_empty();
    Schedule {
        t_end: t.t_end,
        // Given steps: each nominal step reaches the next landing time.
        dt0: if replay { f64::INFINITY } else { t.dt },
        dt_max: t.dt_max(),
        growth: t.growth,
        land_on: t.land_on.iter().chain(&o.fields_at).chain(&t.steps).copied().collect(),
        kinks,
        cap: t.dt_max_ramp.zip(scene.scene.plates.as_ref()).map(|(m, p)| (p.protocol().ramp, m)),
        tol: t.error_tolerance.filter(|_| !replay),
        dt_min: t.dt_min(),
        replay,
    }
}

/// The finite-strain mixture's fluid-content rate is the backward-Euler difference
/// (J(F) − J(F − Δt Grad u̇))/Δt (docs/numerics.md): another integrator's u̇ would make it
/// inconsistent (measured with -ts_type bdf: F(35 s) 0.6–1% below every BE run).
fn refuse_other_integrators(ts: &Ts<PoroProblem>) -> Result<()> {
    let ts_type = ts.type_name()?;
    if !ts.problem().model().is_linear() && ts_type != "beuler" {
        return Err(Error::Options(format!(
            "-ts_type {ts_type}: the finite-strain model's fluid-content rate is discretised for backward Euler \
             only (accepted: beuler, the default)"
        )));
    }
    Ok(())
}

/// The surface tension of the boundary, if the scene has it (γ = 0 costs nothing: no surface
/// term at all).
fn surface_tension(
    world: &SimpleCommunicator,
    scene: &LoadedScene,
    local: &LocalMesh,
) -> Result<Option<SurfaceTension>> {
    let Some(sf) = scene.scene.surface.as_ref().filter(|sf| sf.tension > 0.0) else { return Ok(None) };
    let ctx = format!("{}: [surface]", scene.source);
    let faces = agree(world, bc::face_group(local, &sf.group, &ctx))?.to_vec();
    // The work of adhesion to the plates (its range filled in with the seal distance).
    let adhesion = sf.adhesion_range.map(|range| Adhesion { work: sf.adhesion, range });
    Ok(Some(SurfaceTension::new(sf.tension, adhesion, local, &faces)))
}

/// The medium on the boundary, if the scene has it (its density resolved, its material a
/// mixture: the scene checks both).
fn medium(world: &SimpleCommunicator, scene: &LoadedScene, local: &LocalMesh, dofs: &DofMap) -> Result<Option<Medium>> {
    let (Some(md), Some(mix)) = (scene.scene.medium.as_ref(), scene.scene.material.mixture()) else { return Ok(None) };
    let ctx = format!("{}: [medium]", scene.source);
    let faces = agree(world, bc::face_group(local, &md.group, &ctx))?.to_vec();
    let tools = &scene.scene.tools;
    let suctions = md
        .suction_tables(tools)
        .map(|(k, table)| Ok(Suction::new(Tool::from_spec(&tools[k], &scene.source)?, k, table)))
        .collect::<Result<Vec<_>>>()?;
    let medium = Medium::new(md.density.unwrap_or(mix.rho_f), mix.gravity, local, &faces).with_suctions(suctions);
    Ok(Some(if md.viscosity > 0.0 { medium.with_drag(md.viscosity, local, dofs, world) } else { medium }))
}

/// Sets the run of `scene` up as `args` ask, holding `lock` if the run directory was locked
/// before (a resume): every part built complete, then the problem from its parts, the time
/// stepper with its solver, and the run from its pieces.
pub(super) fn setup<'w>(
    world: &'w SimpleCommunicator,
    scene: &LoadedScene,
    args: &RunArgs,
    lock: Option<RunLock>,
) -> Result<Run<'w>> {
    let t0 = Instant::now();
    let _stage = Stage::register("Setup")?.push();
    let comm = world.as_raw();
    let s = &scene.scene;
    if s.plates.is_some() || !s.tools.is_empty() {
        solver::set_contact_defaults()?;
    }
    let Distributed { local, path: mesh_path, layout } = distribute_mesh(world, scene)?;
    let dofs = DofMap::new(&local);
    let (policy, mut solver_line) = solver::policy(s.solver.preset.unwrap_or_default(), dofs.n_global)?;
    let model = model_of(scene)?;
    // On the meridian dV = 2πR dA adds a degree.
    let degree = s.fem.degree(model.is_linear());
    let q = match local.family {
        Family::Tet10 => quadrature::tet(degree),
        Family::Tri6 => quadrature::tri(degree + 1),
    };
    let (cons, ext, free_modes) = constraints(world, scene, &local, &dofs)?;
    let (mut plates, plate_faces) = plates(world, scene, &local, model.as_ref())?.unzip();
    let tools = tool_setup::tools(world, scene, &local, &dofs, &cons, plates.as_mut())?;
    if let Some(set) = &tools {
        for note in tool_setup::coarse_rims(world, set, &local, &scene.scene.tools) {
            solver_line.push_str(&format!("\n{note}"));
        }
    }
    let drainage = drainage(world, scene, &local, model.as_ref(), plates.as_ref().zip(plate_faces.as_deref()))?;
    let surface = surface_tension(world, scene, &local)?;
    let medium = medium(world, scene, &local, &dofs)?;
    let probes = s.probe.iter().map(|p| Probe::new(p, &local, world, &scene.source)).collect::<Result<Vec<_>>>()?;

    let pre = dofs.preallocation(&local);
    let mut jac = Mat::aij(comm, dofs.n_owned, &pre.d_nnz, &pre.o_nnz)?;
    jac.set_name("Jacobian")?;
    let schur = Mat::aij(comm, dofs.n_owned_vertices, &pre.schur_d, &pre.schur_o)?;
    let u = initial_state(comm, scene, &local, &dofs)?;
    let n_global_dofs = dofs.n_global;
    let fields = solver::Fields::new(world, &dofs, &local)?;
    let c = s.fem.stabilisation_c();
    let steps = s.fem.fade_steps();
    let fade = stabilisation_fade(s, &mut solver_line).map(|tau0| Fade { tau0, dt0: s.time.dt, steps });
    let stab = Stabilisation::new(c, fade, model.as_ref());
    let tab = tabulate_cell(local.family, &q);
    let kinks = plates
        .iter()
        .flat_map(|p| p.loading.kinks().into_iter().chain(p.upper.kinks()))
        .chain(tools.iter().flat_map(ToolSet::kinks))
        .chain(medium.iter().flat_map(Medium::kinks))
        .collect();
    let parts = ProblemParts {
        mesh: local,
        dofs,
        model,
        tab,
        xi: q.points.clone(),
        stab,
        equal_order: s.fem.equal_order(),
        constraints: cons,
        loads: ext,
        surface,
        medium,
        plates,
        tools,
        drainage,
        schur,
    };
    let problem = PoroProblem::new(world.duplicate(), parts, &u)?;

    let dm = DmShell::new(comm, &u, Box::new(fields))?;
    let mut ts = Ts::new(comm, problem, u.duplicate()?, jac, None, Some(dm))?;
    let schedule = schedule(scene, kinks);
    ts.set_solution(&u)?;
    ts.set_time(0.0)?;
    ts.set_time_step(schedule.step(0.0, schedule.dt0))?;
    ts.set_max_time(s.time.t_end)?;
    ts.set_max_rejections(s.time.max_retries)?;
    ts.set_from_options()?;
    refuse_other_integrators(&ts)?;
    // The preconditioner is read from the options by the time stepper, which holds the problem:
    // only now is it known whether it uses the Schur approximation.
    let border = ts.problem_mut().take_border();
    let schur_used =
        solver::configure(world, &mut ts, &policy, free_modes, border, &mut solver_line, |p| solver::ProblemView {
            bounds: p.bounds(),
            u_row_scale: p.u_row_scale(),
            schur: p.schur(),
            curved: p.curved_contact(),
        })?;
    ts.problem_mut().set_schur_used(schur_used);

    let experiment = match (&s.plates, plate_faces) {
        (Some(ps), Some(faces)) => {
            let mesh = ts.problem().mesh();
            let volume = mesh.volume(world);
            let phi = ts.problem().model().solid_fraction();
            Some(Experiment::new(mesh, faces, ps.radius(), ps.probe_point, volume, phi, world, &scene.source)?)
        }
        _ => None,
    };
    let observers = Observers {
        probes,
        experiment,
        tools: s.tool_names().map(str::to_string).collect(),
        force_control: ts.problem().plates().is_some_and(|p| p.upper.has_force()),
        medium: crate::observe::aspiration::columns(s.medium.as_ref()),
        exact: exact_columns(scene)?,
        remodelling: ts.problem().has_qp_state(),
        fields: s.output.fields,
        pressure_peak: Default::default(),
        mid_edges: if s.output.fields { mid_edge_nodes(ts.problem().mesh()) } else { Vec::new() },
    };
    let settle = s.plates.is_some() && s.material.mixture().is_some_and(|m| m.gravity.iter().any(|g| *g != 0.0));
    let ellipticity = ellipticity_warning(scene)?;
    let stepper =
        Stepper::new(ts, StepState::new(u)?, schedule, settle, solver::jacobian_check_step()?, ellipticity.clone());
    let output = Output::new(observers, s.output.clone(), lock);
    let checkpoints = Checkpoints::new(&s.output, t0, layout);
    let info = SetupInfo { mesh_path, n_global_dofs, solver_line, ellipticity, seconds: t0.elapsed().as_secs_f64() };
    Ok(Run::new(Voice::new(world, args.log), scene.clone(), args.clone(), stepper, output, checkpoints, info))
}
