//! The discrete u–p problem F(t, U, U̇) = 0 that TS integrates: the element loop over the local
//! cells (`fem::assembly`, either family), surface loads, drainage and constraint rows, assembled
//! into PETSc vectors and matrices. This file holds the problem's state, its set-up, the qp
//! state it commits, and what TS calls; the rest is by concern, a file each: `residual`,
//! `jacobian`, `constraints`, the plates' bounds and predictor (`predictor`), post-processing
//! (`post`) and the finite-difference check of the Jacobian (`fd_check`).
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

mod constraints;
mod fd_check;
mod jacobian;
mod post;
mod predictor;
mod residual;

pub use post::Post;

use super::bc::Constraint;
use super::contact::Plates;
use super::surface_tension::SurfaceTension;
use crate::error::{Error, Result};
pub use crate::fem::assembly::Discretization;
use crate::fem::dofmap::DofMap;
use crate::fem::element::Tabulation;
use crate::fem::insert::{ElementInserter, GhostRows};
use crate::fem::kernel::Stabilisation;
use crate::fem::point::PointModel;
use crate::fem::qp_store::QpStore;
use crate::mesh::dist::LocalMesh;
use crate::petsc::{IndexSet, Mat, Scatter, TsProblem, TsRef, Vector};
use crate::reference_cell::shape::MAX_NODES;
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
    /// Surface tension of the boundary, if the scene has it.
    pub surface: Option<SurfaceTension>,
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
        let constraints = PoroProblem::synced(&scatter, global_template, n_local, &constraints)?;
        let mut constrained = vec![false; n_local];
        for c in &constraints {
            constrained[c.local] = true;
        }
        let owned: Vec<(usize, Constraint)> =
            constraints.into_iter().filter_map(|c| dofs.local_to_owned(c.local).map(|i| (i, c))).collect();
        let h = mesh.mean_size(&world);
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
            surface: None,
            bounds: None,
            stage: (0.0, 0.0),
            extrapolation: None,
            predicted: None,
            timers: Timers::default(),
        })
    }

    /// Makes a per-rank outcome collective: if any rank failed, every rank returns an error
    /// naming the first failure (its rank's message), a domain error if the failure anywhere
    /// was one, so TS can cut the step.
    fn collective(&self, local: Result<()>) -> Result<()> {
        let class = |e: &Error| if matches!(e, Error::Domain { .. }) { 1 } else { 2 };
        match crate::parallel::agree_ranked(&self.world, local, class) {
            (Ok(()), _) => Ok(()),
            (Err(Error::Elsewhere { rank, msg }), 1) => {
                Err(Error::Domain { cell: 0, point: 0, j: f64::NAN, msg: format!("on rank {rank}: {msg}") })
            }
            (Err(e), _) => Err(e),
        }
    }

    /// Scatters U and U̇ to the local (owned + ghost) work vectors.
    fn load_state(&mut self, u: &Vector, udot: &Vector) -> Result<()> {
        self.scatter.forward(u, &mut self.u_loc)?;
        self.scatter.forward(udot, &mut self.udot_loc)
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
        self.load_state(u, &backward_euler_rate(u, prev, dt)?)?;
        let outcome = {
            let (ul, udl) = (self.u_loc.read()?, self.udot_loc.read()?);
            self.disc.advanced_qp_state(&ul, &udl, dt).map(|next| self.disc.qp_state = next)
        };
        self.timers.qp_commit_s += t0.elapsed().as_secs_f64();
        self.collective(outcome)
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

    /// The pressure stabilisation the assembly uses.
    pub fn stabilisation(&self) -> Stabilisation {
        self.disc.stab
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

/// The backward-Euler rate (u − prev) / dt of a step.
pub fn backward_euler_rate(u: &Vector, prev: &Vector, dt: f64) -> Result<Vector> {
    let mut r = u.copy()?;
    r.axpy(-1.0, prev)?;
    r.scale(1.0 / dt)?;
    Ok(r)
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

    fn pre_stage(&mut self, ts: TsRef, t: f64) -> Result<()> {
        self.stage_plates(ts, t)
    }

    fn initial_guess(&mut self, ts: TsRef, x: &mut Vector) -> Result<()> {
        self.predict(ts, x)
    }
}
