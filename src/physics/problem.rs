//! The discrete u–p problem F(t, U, U̇) = 0 that TS integrates: the element loop over the local
//! cells (`fem::assembly`, either family), surface loads, drainage and constraint rows, assembled
//! into PETSc vectors and matrices.
//!
//! Constraints (prescribed u components or p) replace their rows by s (U_i − g_i) with a scale s
//! comparable to the neighbouring diagonal; their columns are dropped from the Jacobian so the
//! u block stays symmetric for AMG. That is exact Newton whenever U already satisfies the
//! constraints, which holds from the first iterate on (the initial state satisfies them and
//! the identity rows enforce them in one step otherwise).
//!
//! Failures inside the element loop are made collective (one all-reduce per assembly), so a
//! rank never leaves the others waiting in a collective call: an inadmissible state anywhere
//! becomes a domain error on every rank, which TS answers by cutting the step.

use super::bc::Constraint;
use super::contact::{DrainageGap, Plates};
use crate::error::{Error, Result};
pub use crate::fem::assembly::Discretization;
use crate::fem::assembly::QpStateUse;
use crate::fem::dofmap::DofMap;
use crate::fem::element::{Tabulation, MAX_DOF};
use crate::fem::equal_order;
use crate::fem::insert::{ElementInserter, GhostRows};
use crate::fem::kernel::Stabilisation;
use crate::fem::point::PointModel;
use crate::fem::qp_store::QpStore;
use crate::mesh::dist::LocalMesh;
use crate::petsc::{IndexSet, Int, Mat, Scatter, TsProblem, TsRef, Vector};
use crate::reference_cell::shape::MAX_NODES;
use crate::reference_cell::Family;
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::time::Instant;

/// Wall-clock totals of the expensive callbacks.
#[derive(Debug, Default, Clone, Copy)]
pub struct Timers {
    pub residual_s: f64,
    pub residual_n: usize,
    pub jacobian_s: f64,
    pub jacobian_n: usize,
    /// Committing the qp state of accepted steps (timings.txt: `history_commit`).
    pub qp_commit_s: f64,
}

pub struct PoroProblem {
    pub world: SimpleCommunicator,
    pub disc: Discretization,
    /// Owned constrained dofs with their values, each with its position among the owned dofs.
    constraints: Vec<(usize, Constraint)>,
    /// External loads (traction, prescribed flux) in the local layout, already integrated.
    external: Vec<f64>,
    scatter: Scatter,
    u_loc: Vector,
    udot_loc: Vector,
    f_loc: Vector,
    /// Fixed-stress Schur approximation on the pressure space.
    pub schur: Mat,
    /// Whether the preconditioner uses `schur` (a Schur fieldsplit): else it is not assembled.
    pub schur_needed: bool,
    /// Offsets for direct CSR insertion, built after the first assembly.
    inserter: Option<ElementInserter>,
    ghosts: GhostRows,
    /// Shift of the last assembled Jacobian (reused as is for linear models).
    assembled_shift: Option<f64>,
    /// Mean element size, for constraint-row scaling.
    h: f64,
    /// Rigid plates (contact bounds, drainage out of contact), if the scene has them.
    pub plates: Option<Plates>,
    /// SNESVI lower/upper bounds (SNES keeps references; refreshed at every stage time).
    pub bounds: Option<(Vector, Vector)>,
    /// (start, stage) time of the step being solved, for the contact predictor.
    stage: (f64, f64),
    /// The velocity the predictor of the step being solved extrapolates with (the driver's
    /// last step rate, `driver::rate`; None: no extrapolation, as after a loading kink).
    extrapolation: Option<Vector>,
    /// The predictor of the step being solved (local layout), whose gaps set the drainage when
    /// the plates drain by the predicted gap (`DrainageGap::Predicted`).
    predicted: Option<Vec<f64>>,
    pub timers: Timers,
}

/// The scales of the local error estimate of a step (`PoroProblem::error_scales`).
#[derive(Debug, Clone, Copy)]
pub struct ErrorScales {
    /// Owned dofs before the first p dof (the owned layout is u, then p).
    pub n_u_owned: usize,
    /// Floors of the u and p magnitudes the error is measured against.
    pub u_floor: f64,
    pub p_floor: f64,
}

/// "No bound" for SNESVI (PETSc's PETSC_INFINITY).
pub const INFINITY: f64 = f64::MAX / 4.0;

/// Post-processing of a converged state.
pub struct Post {
    /// The state, owned + ghost entries (local layout).
    pub local: Vec<f64>,
    /// Raw residual — internal minus external forces on u rows, mass balance on p rows — with
    /// no constraint rows: the reactions of constrained and contact dofs. Owned entries.
    pub reaction: Vec<f64>,
    /// The pressure part of the u-row reactions (p entries zero). Owned entries.
    pub reaction_pressure: Vec<f64>,
    /// Per local element: J, porosity, von Mises, Darcy flux (3 per element).
    pub cell_j: Vec<f64>,
    pub cell_porosity: Vec<f64>,
    pub cell_von_mises: Vec<f64>,
    pub cell_darcy: Vec<f64>,
    /// Per local element: mean ‖E_p‖ (empty without qp state).
    pub cell_norm_ep: Vec<f64>,
    /// Σ over local elements of ∫ J dV.
    pub volume_j: f64,
    /// Σ over local elements of ∫ dV, ∫ σ_sc dV and ∫ ‖E_p‖ dV.
    pub volume: f64,
    pub int_cauchy: [[f64; 3]; 3],
    pub int_norm_ep: f64,
    /// Largest von Mises stress, ‖E_p‖ and |det B_p − 1| at the local quadrature points.
    pub max_von_mises: f64,
    pub max_norm_ep: f64,
    pub max_det_bp_dev: f64,
}

impl PoroProblem {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        world: SimpleCommunicator,
        mesh: LocalMesh,
        dofs: DofMap,
        model: Box<dyn PointModel>,
        tab: Tabulation<MAX_NODES>,
        xi: Vec<[f64; 3]>,
        constraints: Vec<Constraint>,
        external: Vec<f64>,
        global_template: &Vector,
        schur: Mat,
        stab: Stabilisation,
    ) -> Result<PoroProblem> {
        let n_local = dofs.n_local();
        let comm = world.as_raw();
        let from = IndexSet::general(comm, &dofs.l2g)?;
        let u_loc = Vector::seq(n_local)?;
        let scatter = Scatter::new(global_template, &from, &u_loc)?;
        let (udot_loc, f_loc) = (Vector::seq(n_local)?, Vector::seq(n_local)?);
        let constraints = sync_constraints(&scatter, global_template, n_local, &constraints)?;
        let mut constrained = vec![false; n_local];
        for c in &constraints {
            constrained[c.local] = true;
        }
        let owned: Vec<(usize, Constraint)> =
            constraints.into_iter().filter_map(|c| dofs.local_to_owned(c.local).map(|i| (i, c))).collect();
        let h = mean_element_size(&world, &mesh);
        let qp_state = QpStore::new(mesh.cells.len(), xi.len(), model.qp_state_len(), |v| model.initial_qp_state(v));
        Ok(PoroProblem {
            world,
            disc: Discretization {
                stab,
                qp_state,
                evolve: true,
                equal_order: false,
                mesh,
                dofs,
                model,
                tab,
                xi,
                constrained,
            },
            constraints: owned,
            external,
            scatter,
            u_loc,
            udot_loc,
            f_loc,
            schur,
            schur_needed: true,
            inserter: None,
            ghosts: GhostRows::default(),
            assembled_shift: None,
            h,
            plates: None,
            bounds: None,
            stage: (0.0, 0.0),
            extrapolation: None,
            predicted: None,
            timers: Timers::default(),
        })
    }

    /// Scale of the u and p constraint rows at time-derivative shift `shift`.
    fn scales(&self, shift: f64) -> (f64, f64) {
        let m = &self.disc.model;
        let su = m.p_wave_modulus() * self.h;
        let sp = m.conductivity() * self.h + shift * self.h.powi(3) / m.drained_bulk_modulus();
        (su, sp)
    }

    /// Scale of a u row of the Jacobian (for rows replaced by the identity).
    pub fn u_row_scale(&self) -> f64 {
        self.scales(0.0).0
    }

    fn scale_of(&self, local: usize, scales: (f64, f64)) -> f64 {
        if local < self.disc.dofs.n_u_local() {
            scales.0
        } else {
            scales.1
        }
    }

    /// Adds rigid plates: contact bounds on the surface u_z dofs (vectors like `template`,
    /// ±∞ elsewhere) and drainage out of contact. Returns the bounds for `SNESVISetVariableBounds`.
    pub fn attach_plates(&mut self, plates: Plates, template: &Vector) -> Result<(&Vector, &Vector)> {
        let (mut lo, mut hi) = (template.duplicate()?, template.duplicate()?);
        lo.set(-INFINITY)?;
        hi.set(INFINITY)?;
        {
            let (mut l, mut h) = (lo.write()?, hi.write()?);
            plates.fill_bounds(0.0, &self.disc.dofs, &mut l, &mut h);
        }
        self.plates = Some(plates);
        let (lo, hi) = self.bounds.insert((lo, hi));
        Ok((lo, hi))
    }

    /// Makes a per-rank outcome collective: if any rank failed, every rank returns an error
    /// naming the first failure (its rank's message), a domain error if the failure anywhere
    /// was one, so TS can cut the step.
    fn collective(&self, local: Result<()>) -> Result<()> {
        let code: i32 = match &local {
            Ok(()) => 0,
            Err(Error::Domain { .. }) => 1,
            Err(_) => 2,
        };
        let mut worst = 0i32;
        self.world.all_reduce_into(&code, &mut worst, SystemOperation::max());
        match (worst, crate::parallel::agree(&self.world, local)) {
            (_, Ok(())) => Ok(()),
            (1, Err(Error::Elsewhere { rank, msg })) => {
                Err(Error::Domain { cell: 0, point: 0, j: f64::NAN, msg: format!("on rank {rank}: {msg}") })
            }
            (_, Err(e)) => Err(e),
        }
    }

    /// Scatters U and U̇ to the local (owned + ghost) work vectors.
    fn load_state(&mut self, u: &Vector, udot: &Vector) -> Result<()> {
        self.scatter.forward(u, &mut self.u_loc)?;
        self.scatter.forward(udot, &mut self.udot_loc)
    }

    /// Residual of the current step at (t, U, U̇) with step size dt.
    pub fn assemble_residual(&mut self, t: f64, dt: f64, u: &Vector, udot: &Vector, f: &mut Vector) -> Result<()> {
        let t0 = Instant::now();
        self.load_state(u, udot)?;
        let r = self.residual_with(t, dt, f);
        self.timers.residual_s += t0.elapsed().as_secs_f64();
        self.timers.residual_n += 1;
        r
    }

    fn residual_with(&mut self, t: f64, dt: f64, f: &mut Vector) -> Result<()> {
        let outcome = {
            let ul = self.u_loc.read()?;
            let udl = self.udot_loc.read()?;
            let mut fl = self.f_loc.write()?;
            fl.iter_mut().for_each(|x| *x = 0.0);
            let disc = &self.disc;
            let res = disc.add_residual(&ul, &udl, dt, &mut fl);
            // Drainage through the surface off the plates: outflow c(g) p (contact module).
            if let Some(pl) = &self.plates {
                for d in pl.drainage(&disc.mesh, &disc.dofs, self.predicted.as_deref().unwrap_or(&ul), t) {
                    fl[d.p] += d.conductance * ul[d.p];
                }
            }
            for (l, x) in fl.iter_mut().enumerate() {
                if disc.constrained[l] {
                    *x = 0.0;
                } else {
                    *x -= self.external[l];
                }
            }
            res
        };
        self.collective(outcome)?;
        f.zero()?;
        self.scatter.reverse_add(&self.f_loc, f)?;
        let scales = self.scales(1.0 / dt);
        {
            let ul = self.u_loc.read()?;
            let mut fw = f.write()?;
            for &(i, ref c) in &self.constraints {
                fw[i] = self.scale_of(c.local, scales) * (ul[c.local] - c.value);
            }
        }
        Ok(())
    }

    /// Jacobian dF/dU + shift dF/dU̇ into `jac`, and the Schur approximation into `self.schur`
    /// if the preconditioner uses it (`schur_needed`).
    /// The first assembly inserts through `MatSetValues` and fixes the pattern; later ones
    /// write into the CSR arrays directly (see `fem::insert`).
    pub fn assemble_jacobian(
        &mut self,
        t: f64,
        dt: f64,
        shift: f64,
        u: &Vector,
        udot: &Vector,
        jac: &mut Mat,
    ) -> Result<()> {
        // A linear model's Jacobian depends only on the shift (unless contact changes the
        // drained set): leaving the matrix untouched lets PETSc keep the preconditioner too.
        if self.disc.model.is_linear() && self.plates.is_none() && self.assembled_shift == Some(shift) {
            return Ok(());
        }
        let t0 = Instant::now();
        self.load_state(u, udot)?;
        let r = self.jacobian_with(t, dt, shift, jac);
        self.timers.jacobian_s += t0.elapsed().as_secs_f64();
        self.timers.jacobian_n += 1;
        r
    }

    fn jacobian_with(&mut self, t: f64, dt: f64, shift: f64, jac: &mut Mat) -> Result<()> {
        jac.zero_entries()?;
        let needed = self.schur_needed;
        if needed {
            self.schur.zero_entries()?;
        }
        let outcome = {
            let ul = self.u_loc.read()?;
            let udl = self.udot_loc.read()?;
            let (disc, ghosts) = (&self.disc, &mut self.ghosts);
            let schur = needed.then_some(&mut self.schur);
            match &self.inserter {
                Some(ins) => jac.with_local_csr(|csr| {
                    disc.jacobian_loop(&ul, &udl, dt, shift, schur, |e, d, k| {
                        ins.add(csr, e, d, &disc.dofs.l2g, k, ghosts)
                    })
                }),
                None => {
                    let n = disc.ndof();
                    let mut rows = [0 as Int; MAX_DOF];
                    let mut sorted = vec![0.0; n * n];
                    disc.jacobian_loop(&ul, &udl, dt, shift, schur, |_, d, k| {
                        // Increasing global indices let PETSc merge each row in one pass.
                        let mut order: Vec<usize> = (0..n).collect();
                        order.sort_unstable_by_key(|&a| disc.dofs.l2g[d[a]]);
                        for (a, &o) in order.iter().enumerate() {
                            rows[a] = disc.dofs.l2g[d[o]];
                            for (b, &c) in order.iter().enumerate() {
                                sorted[a * n + b] = k[o][c];
                            }
                        }
                        jac.add_values(&rows[..n], &rows[..n], &sorted)
                    })
                }
            }
        };
        self.collective(outcome)?;
        self.ghosts.flush(jac)?;
        let scales = self.scales(shift);
        // Drainage: d(c p)/dp = c on the diagonal, d(c p)/du_z = c' p (not with the predicted
        // gap, fixed during the step); and c in the Schur block.
        if let Some(pl) = &self.plates {
            let ul = self.u_loc.read()?;
            let l2g = &self.disc.dofs.l2g;
            let gaps = self.predicted.as_deref();
            for d in pl.drainage(&self.disc.mesh, &self.disc.dofs, gaps.unwrap_or(&ul), t) {
                if self.disc.constrained[d.p] {
                    continue;
                }
                let dc_du = if gaps.is_some() { 0.0 } else { d.d_conductance * ul[d.p] };
                jac.add_values(&[l2g[d.p]], &[l2g[d.p], l2g[d.uz]], &[d.conductance, dc_du])?;
                let gv = self.disc.mesh.vertex_global[d.p - self.disc.dofs.n_u_local()] as Int;
                if needed {
                    self.schur.add_values(&[gv], &[gv], &[d.conductance])?;
                }
            }
        }
        let rows: Vec<usize> = self.constraints.iter().map(|(_, c)| c.local).collect();
        for l in rows {
            let g = self.disc.dofs.l2g[l];
            let s = self.scale_of(l, scales);
            jac.add_values(&[g], &[g], &[s])?;
            if l >= self.disc.dofs.n_u_local() {
                let lv = l - self.disc.dofs.n_u_local();
                let gv = self.disc.mesh.vertex_global[lv] as Int;
                if needed {
                    self.schur.add_values(&[gv], &[gv], &[s])?;
                }
            }
        }
        jac.assemble()?;
        if needed {
            self.schur.assemble()?;
        }
        if self.inserter.is_none() {
            let disc = &self.disc;
            self.inserter = Some(ElementInserter::build(jac, &disc.dofs, disc.family(), disc.mesh.cells.len(), |e| {
                disc.element_dofs(e)
            })?);
        }
        self.assembled_shift = Some(shift);
        Ok(())
    }

    /// Sets the velocity the predictor of the next steps extrapolates with (copied; None: the
    /// previous state, as after a loading kink). Only the plates' predictor uses it.
    pub fn set_extrapolation(&mut self, velocity: Option<&Vector>) -> Result<()> {
        match (velocity, &self.plates) {
            (Some(v), Some(_)) => match &mut self.extrapolation {
                Some(x) => x.copy_from(v)?,
                None => self.extrapolation = Some(v.copy()?),
            },
            _ => self.extrapolation = None,
        }
        Ok(())
    }

    /// The scales of the local error estimate (`driver::rate`): the owned u dofs come first;
    /// the floors of the fields' magnitudes are h for u and 10% of the drained bulk modulus
    /// for p, so that a field decaying to zero does not force ever smaller steps.
    pub fn error_scales(&self) -> ErrorScales {
        ErrorScales {
            n_u_owned: self.disc.dofs.n_u_owned(),
            u_floor: self.h,
            p_floor: 0.1 * self.disc.model.drained_bulk_modulus(),
        }
    }

    /// Commits the end-of-step qp state of the accepted step from `prev` to `u` (size dt): the
    /// update every evaluation of that step computed, now stored. Nothing without qp state, or
    /// while it is frozen (settling).
    pub fn commit(&mut self, prev: &Vector, u: &Vector, dt: f64) -> Result<()> {
        if self.disc.qp_state.is_empty() || !self.disc.evolve {
            return Ok(());
        }
        let t0 = Instant::now();
        self.load_state(u, &rate(u, prev, dt)?)?;
        let outcome = {
            let (ul, udl) = (self.u_loc.read()?, self.udot_loc.read()?);
            self.disc.advanced_qp_state(&ul, &udl, dt).map(|next| self.disc.qp_state = next)
        };
        self.timers.qp_commit_s += t0.elapsed().as_secs_f64();
        self.collective(outcome)
    }

    /// Reactions, their pressure part and cell fields at the state (U, U̇) of a step of size dt.
    pub fn post_process(&mut self, dt: f64, u: &Vector, udot: &Vector) -> Result<Post> {
        self.load_state(u, udot)?;
        let n_el = self.disc.mesh.cells.len();
        let mut post = Post {
            local: self.u_loc.read()?.to_vec(),
            reaction: Vec::new(),
            reaction_pressure: Vec::new(),
            cell_j: Vec::with_capacity(n_el),
            cell_porosity: Vec::with_capacity(n_el),
            cell_von_mises: Vec::with_capacity(n_el),
            cell_darcy: Vec::with_capacity(3 * n_el),
            cell_norm_ep: Vec::new(),
            volume_j: 0.0,
            volume: 0.0,
            int_cauchy: [[0.0; 3]; 3],
            int_norm_ep: 0.0,
            max_von_mises: 0.0,
            max_norm_ep: 0.0,
            max_det_bp_dev: 0.0,
        };
        let with_qp_state = !self.disc.qp_state.is_empty();
        let n_local = self.disc.dofs.n_local();
        let mut pres_loc = Vector::seq(n_local)?;
        let outcome = {
            let udl = self.udot_loc.read()?;
            let mut fl = self.f_loc.write()?;
            let mut pl = pres_loc.write()?;
            fl.iter_mut().for_each(|x| *x = 0.0);
            pl.iter_mut().for_each(|x| *x = 0.0);
            let disc = &self.disc;
            let (kernel, n, nu) = (disc.kernel(), disc.ndof(), disc.dofs.nc * disc.family().cell_nodes());
            let mut run = || -> Result<()> {
                // The end-of-step qp state is already committed: hold it.
                disc.each_element(&post.local, &udl, dt, QpStateUse::Held, |_, d, input| {
                    let ep = kernel.post(input)?;
                    for k in 0..n {
                        fl[d[k]] += ep.r[k];
                    }
                    for k in 0..nu {
                        pl[d[k]] += ep.r_pressure[k];
                    }
                    post.cell_j.push(ep.j);
                    post.cell_porosity.push(ep.porosity);
                    post.cell_von_mises.push(ep.von_mises);
                    post.cell_darcy.extend(ep.darcy);
                    post.volume_j += ep.volume_j;
                    post.volume += ep.volume;
                    for (a, b) in post.int_cauchy.iter_mut().flatten().zip(ep.int_cauchy.iter().flatten()) {
                        *a += b;
                    }
                    post.int_norm_ep += ep.norm_ep * ep.volume;
                    post.max_von_mises = post.max_von_mises.max(ep.max_von_mises);
                    post.max_norm_ep = post.max_norm_ep.max(ep.max_norm_ep);
                    post.max_det_bp_dev = post.max_det_bp_dev.max(ep.max_det_bp_dev);
                    if with_qp_state {
                        post.cell_norm_ep.push(ep.norm_ep);
                    }
                    Ok(())
                })
            };
            let r = run();
            for (x, ext) in fl.iter_mut().zip(&self.external) {
                *x -= ext;
            }
            r
        };
        self.collective(outcome)?;
        let mut g = u.duplicate()?;
        g.zero()?;
        self.scatter.reverse_add(&self.f_loc, &mut g)?;
        post.reaction = g.read()?.to_vec();
        g.zero()?;
        self.scatter.reverse_add(&pres_loc, &mut g)?;
        post.reaction_pressure = g.read()?.to_vec();
        Ok(post)
    }

    /// Switches to equal-order P1–P1 (`fem::equal_order`): ties the displacement's mid-edge
    /// nodes to their edges' vertices and moves their loads there. Before the first assembly.
    pub fn tie_displacement(&mut self) {
        self.disc.equal_order = true;
        equal_order::tie_loads(&mut self.external, &self.disc.mesh);
    }

    /// Equal order: puts the mid-edge displacements of `x` (owned entries) back on their edges,
    /// where the plates' predictor moved only vertices (`fem::equal_order::tie_nodes`). Why:
    /// the tie rows would restore them in the first Newton step anyway, but the guess's
    /// compaction check and first residual would see elements bent by the predictor's jump.
    /// Nothing for Taylor–Hood.
    fn retie(&mut self, x: &mut Vector) -> Result<()> {
        if !self.disc.equal_order {
            return Ok(());
        }
        self.scatter.forward(x, &mut self.u_loc)?;
        let mut ul = self.u_loc.write()?;
        equal_order::tie_nodes(&mut ul, &self.disc.mesh);
        let mut xw = x.write()?;
        for (l, &v) in ul.iter().enumerate().take(self.disc.dofs.n_u_local()) {
            if let Some(i) = self.disc.dofs.local_to_owned(l) {
                xw[i] = v;
            }
        }
        Ok(())
    }

    /// The state whose gaps set the last step's drainage (local layout), if not its solution:
    /// the predictor's, with `DrainageGap::Predicted`.
    pub fn drainage_gaps(&self) -> Option<&[f64]> {
        self.predicted.as_deref()
    }

    /// Local copy (owned + ghost) of a global vector, for post-processing.
    pub fn localize(&mut self, u: &Vector) -> Result<Vec<f64>> {
        self.scatter.forward(u, &mut self.u_loc)?;
        Ok(self.u_loc.read()?.to_vec())
    }

    /// Whether J > Φs at every point in the state `x` (true for models without a solid
    /// fraction). Collective.
    fn compaction_admissible(&mut self, x: &Vector) -> Result<bool> {
        let Some(phi_s) = self.disc.model.solid_fraction() else { return Ok(true) };
        self.scatter.forward(x, &mut self.u_loc)?;
        let ok = self.disc.min_j(&self.u_loc.read()?).is_ok_and(|j| j > phi_s);
        Ok(crate::parallel::all(&self.world, ok))
    }
}

/// What the driver and the output read of the discretisation, and the committed qp state the
/// problem holds for its assembly (captured into and applied from a checkpoint through these).
impl PoroProblem {
    pub fn mesh(&self) -> &LocalMesh {
        &self.disc.mesh
    }

    pub fn dofs(&self) -> &DofMap {
        &self.disc.dofs
    }

    pub fn model(&self) -> &dyn PointModel {
        self.disc.model.as_ref()
    }

    /// Scales the model's gravity (settling ramps it up).
    pub fn set_gravity_factor(&mut self, factor: f64) {
        self.disc.model.set_gravity_factor(factor);
    }

    /// Whether the model keeps qp state (remodelling).
    pub fn has_qp_state(&self) -> bool {
        !self.disc.qp_state.is_empty()
    }

    /// Holds the qp state at its committed value in the steps solved (settling before t = 0,
    /// where B_p(X, 0⁻) = I holds by definition), or lets it evolve.
    pub fn freeze_qp_state(&mut self, frozen: bool) {
        self.disc.evolve = !frozen;
    }

    /// Values of committed qp state per element (0 without).
    pub fn qp_state_per_elem(&self) -> usize {
        self.disc.qp_state.element(0).len()
    }

    /// The committed qp state of the local elements, by original element id.
    pub fn qp_state_by_original(&self) -> impl Iterator<Item = (u32, &[f64])> {
        self.disc.qp_state.export(&self.disc.mesh.cell_original)
    }

    /// Sets the committed qp state from all elements' values by original id
    /// ([`Self::qp_state_per_elem`] per element).
    pub fn set_qp_state_by_original(&mut self, values: &[f64]) -> Result<()> {
        let per_elem = self.qp_state_per_elem();
        if per_elem == 0 {
            return Ok(());
        }
        let disc = &mut self.disc;
        disc.qp_state.import(&disc.mesh.cell_original, |o| {
            values.get(o as usize * per_elem..(o as usize + 1) * per_elem).map(<[f64]>::to_vec)
        })
    }
}

/// Constraints are found from this rank's boundary faces, but every rank holding a copy of a
/// constrained dof must know (its elements drop that row and column): sum flags and values
/// over the copies through the global vector and read them back.
fn sync_constraints(
    scatter: &Scatter,
    template: &Vector,
    n_local: usize,
    raw: &[Constraint],
) -> Result<Vec<Constraint>> {
    let (mut flag_l, mut val_l) = (Vector::seq(n_local)?, Vector::seq(n_local)?);
    {
        let (mut f, mut v) = (flag_l.write()?, val_l.write()?);
        f.iter_mut().for_each(|x| *x = 0.0);
        v.iter_mut().for_each(|x| *x = 0.0);
        for c in raw {
            f[c.local] += 1.0;
            v[c.local] += c.value;
        }
    }
    let (mut flag_g, mut val_g) = (template.duplicate()?, template.duplicate()?);
    flag_g.zero()?;
    val_g.zero()?;
    scatter.reverse_add(&flag_l, &mut flag_g)?;
    scatter.reverse_add(&val_l, &mut val_g)?;
    scatter.forward(&flag_g, &mut flag_l)?;
    scatter.forward(&val_g, &mut val_l)?;
    let (f, v) = (flag_l.read()?, val_l.read()?);
    Ok((0..n_local).filter(|&l| f[l] > 0.0).map(|l| Constraint { local: l, value: v[l] / f[l] }).collect())
}

/// The backward-Euler rate (u − prev) / dt of a step.
pub fn rate(u: &Vector, prev: &Vector, dt: f64) -> Result<Vector> {
    let mut r = u.copy()?;
    r.axpy(-1.0, prev)?;
    r.scale(1.0 / dt)?;
    Ok(r)
}

/// Mean edge-length scale (volume^(1/3) of the vertex tetrahedra, area^(1/2) of the vertex
/// triangles on the meridian), over all ranks.
pub fn mean_element_size(world: &SimpleCommunicator, mesh: &LocalMesh) -> f64 {
    let mut sum = 0.0;
    for t in &mesh.cells {
        let x = |i: usize| mesh.coords[t[i] as usize];
        let m = crate::reference_cell::straight_measure(mesh.family, x);
        sum += match mesh.family {
            Family::Tet10 => m.cbrt(),
            Family::Tri6 => m.sqrt(),
        };
    }
    let local = [sum, mesh.cells.len() as f64];
    let mut global = [0.0; 2];
    world.all_reduce_into(&local[..], &mut global[..], SystemOperation::sum());
    if global[1] > 0.0 {
        global[0] / global[1]
    } else {
        1.0
    }
}

impl PoroProblem {
    /// Directional finite-difference check of the assembled Jacobian at state `u` of a backward
    /// Euler step of size dt from `prev`: ‖J v − (F(u + εv) − F(u − εv)) / 2ε‖ / ‖J v‖ over the u
    /// rows and over the p rows, for a fixed pseudo-random direction v (all unconstrained dofs;
    /// contact and drainage included), ε = `rel_eps` ‖u‖∞. Central differences: truncation
    /// O(ε²) where F is smooth, but O(ε) at vertices exactly on a plate, where the drainage
    /// smoothstep's second derivative jumps; round-off O(1e-16 / ε). A wrong Jacobian entry
    /// shows as an error that does not shrink with ε.
    /// `jac` must be the matrix of the solves (assembly reuses its pattern).
    pub fn jacobian_error(
        &mut self,
        t: f64,
        dt: f64,
        u: &Vector,
        prev: &Vector,
        jac: &mut Mat,
        rel_eps: f64,
    ) -> Result<(f64, f64)> {
        let dofs = &self.disc.dofs;
        let (offset, u_end) = (dofs.offset, dofs.u_range().1);
        let mut v = u.duplicate()?;
        {
            let mut w = v.write()?;
            for (i, x) in w.iter_mut().enumerate() {
                // A fixed hash of the global index: the same direction on any number of ranks.
                let h = ((offset + i) as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
                *x = (h >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            }
            // Constrained dofs never move (their Jacobian columns are dropped, module docs).
            for (l, _) in self.disc.constrained.iter().enumerate().filter(|(_, &c)| c) {
                if let Some(i) = dofs.local_to_owned(l) {
                    w[i] = 0.0;
                }
            }
        }
        let eps = rel_eps * u.norm_inf()?.max(1.0);
        // F at u + s v, with udot = (u + s v − prev) / dt.
        let mut eval = |s: f64, out: &mut Vector| -> Result<()> {
            let mut x = u.copy()?;
            x.axpy(s, &v)?;
            self.assemble_residual(t, dt, &x, &rate(&x, prev, dt)?, out)
        };
        let (mut fp, mut fm) = (u.duplicate()?, u.duplicate()?);
        eval(eps, &mut fp)?;
        eval(-eps, &mut fm)?;
        self.assemble_jacobian(t, dt, 1.0 / dt, u, &rate(u, prev, dt)?, jac)?;
        let mut jv = u.duplicate()?;
        jac.mult(&v, &mut jv)?;
        let mut sums = [0.0f64; 4]; // |Jv − fd|² and |Jv|² on u rows, then on p rows
        {
            let (jv, fp, fm) = (jv.read()?, fp.read()?, fm.read()?);
            for i in 0..jv.len() {
                let fd = (fp[i] - fm[i]) / (2.0 * eps);
                let k = if offset + i < u_end { 0 } else { 2 };
                sums[k] += (jv[i] - fd).powi(2);
                sums[k + 1] += jv[i].powi(2);
            }
        }
        let mut tot = [0.0f64; 4];
        self.world.all_reduce_into(&sums[..], &mut tot[..], SystemOperation::sum());
        Ok(((tot[0] / tot[1]).sqrt(), (tot[2] / tot[3].max(f64::MIN_POSITIVE)).sqrt()))
    }
}

impl TsProblem for PoroProblem {
    fn residual(&mut self, ts: TsRef, t: f64, u: &Vector, udot: &Vector, f: &mut Vector) -> Result<()> {
        let dt = ts.time_step()?;
        self.assemble_residual(t, dt, u, udot, f)
    }

    fn jacobian(
        &mut self,
        ts: TsRef,
        t: f64,
        u: &Vector,
        udot: &Vector,
        shift: f64,
        jac: &mut Mat,
        _pre: &mut Mat,
    ) -> Result<()> {
        let dt = ts.time_step()?;
        self.assemble_jacobian(t, dt, shift, u, udot, jac)
    }

    /// Moves the lower plate's bound to the stage time (also on a retried step).
    fn pre_stage(&mut self, ts: TsRef, t: f64) -> Result<()> {
        if let (Some(pl), Some((lo, hi))) = (&self.plates, &mut self.bounds) {
            let (mut l, mut h) = (lo.write()?, hi.write()?);
            pl.fill_bounds(t, &self.disc.dofs, &mut l, &mut h);
            self.stage = (ts.time()?, t);
        }
        Ok(())
    }

    /// Predictor: the previous state extrapolated with the last step's velocity (the driver's,
    /// `set_extrapolation`; none if the loading has a kink at the step start), and the nodes on
    /// the lower plate moved with it (see `Plates::predict`). Why: moving only the contact nodes compacts their (already
    /// compacted) elements below J = Φs in the initial guess; the extrapolated field moves the
    /// bulk consistently with the plate.
    ///
    /// Where the extrapolation compacts a point of the mixture to its solid fraction (J ≤ Φs:
    /// near the plates J approaches Φs ever more slowly, and a linear extrapolation over a
    /// grown step overshoots it), the isochoric affine guess (`Plates::predict_isochoric`)
    /// replaces it if that one is admissible. Without this the Newton solve starts from an
    /// inadmissible state and TS has to cut the step by 4 (docs/performance.md).
    fn initial_guess(&mut self, ts: TsRef, x: &mut Vector) -> Result<()> {
        let (t0, t1) = self.stage;
        let Some(pl) = &self.plates else { return Ok(()) };
        // From the start of the step, whatever the integrator put in x (BDF extrapolates).
        let start = ts.solution()?;
        x.copy_from(&start)?;
        let x0 = start.read()?.to_vec();
        if let Some(v) = &self.extrapolation {
            x.axpy(t1 - t0, v)?;
        }
        pl.predict(t0, t1, &self.disc.dofs, &x0, &mut x.write()?);
        let predicted_gap = pl.drain.gap == DrainageGap::Predicted;
        self.retie(x)?;
        // The drainage gaps are the extrapolation's, whatever guess the Newton solve starts from.
        if predicted_gap {
            self.scatter.forward(x, &mut self.u_loc)?;
            let predicted = self.predicted.get_or_insert_with(Vec::new);
            predicted.clear();
            predicted.extend_from_slice(&self.u_loc.read()?);
        }
        if self.extrapolation.is_some() && !self.compaction_admissible(x)? {
            let Some(pl) = &self.plates else { return Ok(()) };
            let mut affine = x.duplicate()?;
            affine.copy_from(&start)?;
            let n = self.disc.dofs.n_owned_nodes;
            pl.predict_isochoric(
                t0,
                t1,
                &self.disc.mesh.coords[..n],
                self.disc.family().axes(),
                &x0,
                &mut affine.write()?,
            );
            pl.predict(t0, t1, &self.disc.dofs, &x0, &mut affine.write()?);
            self.retie(&mut affine)?;
            if self.compaction_admissible(&affine)? {
                x.copy_from(&affine)?;
            }
        }
        Ok(())
    }
}
