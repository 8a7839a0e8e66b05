//! The discrete u–p problem F(t, U, U̇) = 0 that TS integrates ([`PoroProblem`]): the element
//! loop over the local cells (`fem::assembly`, either family), the surface tension, the plates'
//! drainage, the external loads and the constraint rows, assembled into PETSc vectors and
//! matrices; the qp state it commits; post-processing of a converged state. Its parts are
//! pieces, a file each: the local work vectors (`local`), the constraint rows (`constraints`),
//! the plates in the steps (`contact_stage`), the Schur approximation (`schur`) and the
//! Jacobian's insertion (`insertion`); the surface tension is `physics::surface_tension`.
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

use super::constraints::ConstraintRows;
use super::contact_stage::ContactStage;
use super::drainage_stage::{DrainageStage, Seals};
use super::insertion::JacobianInsertion;
use super::local::LocalVectors;
use super::parts::ProblemParts;
use super::post::{backward_euler_rate, Post};
use super::schur::SchurApprox;
use super::timers::Timers;
use super::tool_stage::ToolStage;
use crate::error::{Error, Result};
use crate::fem::assembly::{Discretization, QpStateUse};
use crate::fem::dofmap::DofMap;
use crate::fem::equal_order;
use crate::fem::kernel::Stabilisation;
use crate::fem::point::PointModel;
use crate::fem::qp_store::QpStore;
use crate::mesh::dist::LocalMesh;
use crate::petsc::{Int, Mat, TsProblem, TsRef, Vector};
use crate::physics::contact::Plates;
use crate::physics::medium::Medium;
use crate::physics::surface_tension::{PlatePlanes, SurfaceTension};
use crate::physics::tools::ToolSet;
use crate::solver::active_set::CurvedContact;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::cell::RefCell;
use std::rc::Rc;
use std::time::Instant;

mod access;

pub(crate) struct PoroProblem {
    world: SimpleCommunicator,
    disc: Discretization,
    rows: ConstraintRows,
    /// External loads (traction, prescribed flux) in the local layout, already integrated.
    external: Vec<f64>,
    local: LocalVectors,
    schur: SchurApprox,
    insertion: JacobianInsertion,
    /// Rigid plates, if the scene has them.
    contact: Option<ContactStage>,
    tools: Option<ToolStage>,
    /// The surface's drainage off the plates and the sealing tools, if it drains.
    drainage: Option<DrainageStage>,
    /// The solver's part of force control, until the solver takes it (`take_border`).
    border: Option<crate::solver::active_set::Border>,
    /// Surface tension of the boundary, if the scene has it.
    surface: Option<SurfaceTension>,
    /// The medium's pressure on the boundary and in the drained pores, if the scene has it.
    medium: Option<Medium>,
    timers: Timers,
}

/// The scales of the local error estimate of a step (`PoroProblem::error_scales`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ErrorScales {
    /// Owned dofs before the first p dof (the owned layout is u, then p).
    pub(crate) n_u_owned: usize,
    /// Floors of the u and p magnitudes the error is measured against.
    pub(crate) u_floor: f64,
    pub(crate) p_floor: f64,
}

impl PoroProblem {
    /// The problem of `parts` on `world`, for distributed vectors like `template` (collective).
    pub(crate) fn new(world: SimpleCommunicator, parts: ProblemParts, template: &Vector) -> Result<PoroProblem> {
        let ProblemParts {
            mesh,
            dofs,
            model,
            tab,
            xi,
            stab,
            equal_order,
            constraints,
            loads: mut external,
            surface,
            medium,
            plates,
            tools,
            drainage,
            schur,
        } = parts;
        let local = LocalVectors::new(world.as_raw(), &dofs, template)?;
        let h = mesh.mean_size(&world);
        let (rows, constrained) = ConstraintRows::new(&constraints, &local, template, &dofs, h)?;
        let qp_state = QpStore::new(mesh.cells.len(), xi.len(), model.qp_state_len(), |v| model.initial_qp_state(v));
        if equal_order {
            equal_order::tie_loads(&mut external, &mesh);
        }
        let tools = tools.map(|t| ToolStage::new(t, plates.is_some(), template)).transpose()?;
        let share = match &plates {
            Some(p) => 1.0 / p.symmetry(mesh.volume(&world)),
            None => 1.0,
        };
        let contact = plates.map(|p| ContactStage::new(p, template, &dofs, share)).transpose()?;
        // Force control: the upper plate's and the tools' positions, one bordered solve.
        let mut unknowns: Vec<_> =
            contact.as_ref().map(|c| c.border(template, &dofs)).transpose()?.flatten().into_iter().collect();
        unknowns.extend(tools.iter().flat_map(ToolStage::border_unknowns));
        let border = (!unknowns.is_empty()).then(|| crate::solver::active_set::Border::new(&world, unknowns));
        Ok(PoroProblem {
            world,
            disc: Discretization { stab, qp_state, evolve: true, equal_order, mesh, dofs, model, tab, xi, constrained },
            rows,
            external,
            local,
            schur: SchurApprox::new(schur),
            insertion: JacobianInsertion::default(),
            contact,
            tools,
            drainage: drainage.map(DrainageStage::new),
            border,
            surface,
            medium,
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

    /// The scales of the local error estimate (`driver::rate`): the owned u dofs come first;
    /// the floors of the fields' magnitudes are h for u and 10% of the drained bulk modulus
    /// for p, so that a field decaying to zero does not force ever smaller steps.
    pub(crate) fn error_scales(&self) -> ErrorScales {
        ErrorScales {
            n_u_owned: self.disc.dofs.n_u_owned(),
            u_floor: self.rows.h(),
            p_floor: 0.1 * self.disc.model.drained_bulk_modulus(),
        }
    }

    /// Commits the end-of-step qp state of the accepted step from `prev` to `u` (size dt): the
    /// update every evaluation of that step computed, now stored. Nothing without qp state, or
    /// while it is frozen (settling).
    pub(crate) fn commit(&mut self, prev: &Vector, u: &Vector, dt: f64, keep_rate: bool) -> Result<()> {
        if let Some(c) = &mut self.contact {
            c.commit(dt, keep_rate);
        }
        if let Some(ts) = &self.tools {
            ts.commit(dt, keep_rate);
        }
        if self.disc.qp_state.is_empty() || !self.disc.evolve {
            return Ok(());
        }
        let t0 = Instant::now();
        self.local.load(u, &backward_euler_rate(u, prev, dt)?)?;
        let disc = &mut self.disc;
        let outcome =
            self.local.with_state(|ul, udl| disc.advanced_qp_state(ul, udl, dt))?.map(|next| disc.qp_state = next);
        self.timers.qp_commit_s += t0.elapsed().as_secs_f64();
        self.collective(outcome)
    }
}

/// The residual and the Jacobian of a step.
impl PoroProblem {
    /// Residual of the current step at (t, U, U̇) with step size dt: the element loop, the
    /// surface tension, the drainage through the surface off the plates, the external loads,
    /// and the constraint rows s (U_i − g_i).
    pub(crate) fn assemble_residual(
        &mut self,
        t: f64,
        dt: f64,
        u: &Vector,
        udot: &Vector,
        f: &mut Vector,
    ) -> Result<()> {
        let t0 = Instant::now();
        self.local.load(u, udot)?;
        let r = self.residual_with(t, dt, f);
        self.timers.residual_s += t0.elapsed().as_secs_f64();
        self.timers.residual_n += 1;
        r
    }

    fn residual_with(&mut self, t: f64, dt: f64, f: &mut Vector) -> Result<()> {
        self.move_medium(t);
        let planes = self.plate_planes(t);
        let (disc, surface, contact, external) = (&self.disc, &self.surface, &self.contact, &self.external);
        let (tools, medium, drainage) = (&self.tools, self.medium.as_ref(), &self.drainage);
        let outcome = self.local.with_zeroed_f(|ul, udl, fl| {
            // The tools' contact at this iterate, for the solver's split.
            tools.iter().for_each(|ts| ts.update(ul, &disc.dofs));
            let res = disc.add_residual(ul, udl, dt, fl);
            // Surface tension: γ ∂A/∂x of the boundary's nodes (with the adhesion to the plates
            // where they are at time t).
            if let Some(st) = surface {
                st.add_residual(&disc.mesh, &disc.dofs, ul, planes, fl);
            }
            // The medium's pressure on the boundary: Σ_q p_m N_b (n da)_q.
            if let Some(m) = medium {
                m.add_residual(&disc.mesh, &disc.dofs, ul, udl, fl);
            }
            // Drainage through the surface off the plates and tools: outflow c(g) (p − p_m).
            if let Some(d) = drainage {
                let set = tools.as_ref().map(ToolStage::set);
                d.add_residual(disc, ul, t, seals(contact, set.as_deref(), medium), fl);
            }
            for (l, x) in fl.iter_mut().enumerate() {
                if disc.constrained[l] {
                    *x = 0.0;
                } else {
                    *x -= external[l];
                }
            }
            res
        })?;
        self.collective(outcome)?;
        self.local.sum_f_into(f)?;
        let scales = self.rows.scales(self.disc.model.as_ref(), 1.0 / dt);
        let mut fw = f.write()?;
        let (rows, dofs) = (&self.rows, &self.disc.dofs);
        self.local.with_u(|ul| rows.set_residual_rows(dofs, scales, ul, &mut fw))
    }

    /// Jacobian dF/dU + shift dF/dU̇ into `jac`, and the Schur approximation if the
    /// preconditioner uses it: the element loop (see `insertion`), the surface tension's face
    /// blocks, the drainage rows, and the constraint rows on the diagonal.
    pub(crate) fn assemble_jacobian(
        &mut self,
        t: f64,
        dt: f64,
        shift: f64,
        u: &Vector,
        udot: &Vector,
        jac: &mut Mat,
    ) -> Result<()> {
        // A linear model's Jacobian depends only on the shift (unless contact changes the
        // drained set, or the surface tension's geometry moves): leaving the matrix untouched
        // lets PETSc keep the preconditioner too.
        if self.disc.model.is_linear()
            && (self.contact.is_none() && self.tools.is_none())
            && self.surface.is_none()
            && self.medium.is_none()
            && self.insertion.assembled_at(shift)
        {
            return Ok(());
        }
        let t0 = Instant::now();
        self.local.load(u, udot)?;
        let r = self.jacobian_with(t, dt, shift, jac);
        self.timers.jacobian_s += t0.elapsed().as_secs_f64();
        self.timers.jacobian_n += 1;
        r
    }

    fn jacobian_with(&mut self, t: f64, dt: f64, shift: f64, jac: &mut Mat) -> Result<()> {
        self.move_medium(t);
        jac.zero_entries()?;
        self.schur.zero()?;
        let (disc, insertion, schur) = (&self.disc, &mut self.insertion, &mut self.schur);
        let outcome =
            self.local.with_state(|ul, udl| insertion.add_elements(disc, ul, udl, dt, shift, schur.active(), jac))?;
        self.collective(outcome)?;
        self.insertion.flush(jac)?;
        let scales = self.rows.scales(self.disc.model.as_ref(), shift);
        let planes = self.plate_planes(t);
        let ul = self.local.u()?;
        // The surface's face blocks, constrained rows and columns dropped as the element loop
        // drops them.
        let disc = &self.disc;
        let mut add_face_block = |idx: &[usize], block: &[f64]| {
            let keep: Vec<usize> = (0..idx.len()).filter(|&k| !disc.constrained[idx[k]]).collect();
            let rows: Vec<Int> = keep.iter().map(|&k| disc.dofs.l2g[idx[k]]).collect();
            let vals: Vec<f64> =
                keep.iter().flat_map(|&a| keep.iter().map(move |&b| block[a * idx.len() + b])).collect();
            jac.add_values(&rows, &rows, &vals)
        };
        // Surface tension: γ ∂²A/∂x² of each face (with the adhesion to the plates at time t).
        if let Some(st) = &self.surface {
            st.for_each_block(&disc.mesh, &disc.dofs, &ul, planes, &mut add_face_block)?;
        }
        // The medium's load: its exact derivative per face.
        if let Some(m) = &self.medium {
            m.for_each_block(&disc.mesh, &disc.dofs, &ul, shift, &mut add_face_block)?;
        }
        if let Some(d) = &self.drainage {
            let set = self.tools.as_ref().map(ToolStage::set);
            let seals = seals(&self.contact, set.as_deref(), self.medium.as_ref());
            d.add_jacobian(&self.disc, &ul, t, seals, jac, &mut self.schur)?;
        }
        self.rows.add_jacobian_rows(&self.disc.mesh, &self.disc.dofs, scales, jac, &mut self.schur)?;
        jac.assemble()?;
        self.schur.assemble()?;
        self.insertion.finish(&self.disc, shift, jac)
    }
}

/// What the drained surface drains against: the plates (with their predictor's gaps), the tools
/// and the medium.
fn seals<'a>(contact: &'a Option<ContactStage>, tools: Option<&'a ToolSet>, medium: Option<&'a Medium>) -> Seals<'a> {
    let plates = contact.as_ref().map(ContactStage::plates);
    Seals { plates, tools, gaps: contact.as_ref().and_then(ContactStage::drainage_gaps), medium }
}

/// Post-processing of a converged state.
impl PoroProblem {
    /// Reactions (the surface tension's included), their pressure part and cell fields at the
    /// state (U, U̇) at time t after a step of size dt.
    pub(crate) fn post_process(&mut self, t: f64, dt: f64, u: &Vector, udot: &Vector) -> Result<Post> {
        self.local.load(u, udot)?;
        self.move_medium(t);
        let mut post = Post::new(self.local.u()?, self.disc.mesh.cells.len());
        post.upper_d = self.contact.as_ref().map_or(0.0, |c| c.plates().positions.borrow().d[0]);
        post.tool_d = self.tools.as_ref().map_or_else(Vec::new, |t| t.set().positions());
        let planes = self.plate_planes(t);
        let with_qp_state = !self.disc.qp_state.is_empty();
        let mut pres_loc = Vector::seq(self.disc.dofs.n_local())?;
        let (disc, surface, medium, external) = (&self.disc, &self.surface, &self.medium, &self.external);
        let outcome = {
            let mut pl = pres_loc.write()?;
            pl.iter_mut().for_each(|x| *x = 0.0);
            self.local.with_zeroed_f(|ul, udl, fl| {
                let (kernel, n, nu) = (disc.kernel(), disc.ndof(), disc.dofs.nc * disc.family().cell_nodes());
                // The end-of-step qp state is already committed: hold it.
                let r = disc.each_element(ul, udl, dt, QpStateUse::Held, |_, d, input| {
                    let ep = kernel.post(input)?;
                    for k in 0..n {
                        fl[d[k]] += ep.r[k];
                    }
                    for k in 0..nu {
                        pl[d[k]] += ep.r_pressure[k];
                    }
                    post.add_element(&ep, with_qp_state);
                    Ok(())
                });
                // The surface tension's forces on the nodes, on the plates' too (the residual's).
                if let Some(st) = surface {
                    st.add_residual(&disc.mesh, &disc.dofs, ul, planes, fl);
                    post.adhesion_pull = st.plate_pull(&disc.mesh, &disc.dofs, ul, planes);
                }
                // The medium's load on the nodes, on the plates' too: their reactions are the
                // excess over the medium.
                if let Some(m) = medium {
                    m.add_residual(&disc.mesh, &disc.dofs, ul, udl, fl);
                    post.drag = m.drag_force(&disc.mesh, &disc.dofs, udl);
                }
                for (x, ext) in fl.iter_mut().zip(external) {
                    *x -= ext;
                }
                r
            })?
        };
        self.collective(outcome)?;
        let mut g = u.duplicate()?;
        self.local.sum_f_into(&mut g)?;
        post.reaction = g.read()?.to_vec();
        g.zero()?;
        self.local.add_to(&pres_loc, &mut g)?;
        post.reaction_pressure = g.read()?.to_vec();
        Ok(post)
    }
}

/// The plates in the steps: the bounds moved to each stage time and the predictor.
impl PoroProblem {
    /// Predictor: the previous state extrapolated with the last step's velocity (the driver's,
    /// `set_extrapolation`; none if the loading has a kink at the step start), and the nodes on
    /// the lower plate moved with it (see `Plates::predict`). Why: moving only the contact nodes
    /// compacts their (already compacted) elements below J = Φs in the initial guess; the
    /// extrapolated field moves the bulk consistently with the plate.
    ///
    /// Where the extrapolation compacts a point of the mixture to its solid fraction (J ≤ Φs:
    /// near the plates J approaches Φs ever more slowly, and a linear extrapolation over a
    /// grown step overshoots it), the isochoric affine guess (`Plates::predict_isochoric`)
    /// replaces it if that one is admissible. Without this the Newton solve starts from an
    /// inadmissible state and TS has to cut the step by 4 (docs/performance.md).
    fn predict(&mut self, ts: TsRef, x: &mut Vector) -> Result<()> {
        // From the start of the step, whatever the integrator put in x (BDF extrapolates).
        let start = ts.solution()?;
        if let Some(tools) = &self.tools {
            tools.check_touch(&start.read()?, ts.time()?)?;
        }
        let Some(contact) = &self.contact else { return Ok(()) };
        let x0 = contact.extrapolate(&start, &self.disc.dofs, x)?;
        contact.check_switch(&self.world, &x0, &self.disc.dofs, ts.time()?)?;
        let (predicted_gap, extrapolating) = (contact.drains_by_predicted_gap(), contact.extrapolating());
        self.retie(x)?;
        // The drainage gaps are the extrapolation's, whatever guess the Newton solve starts from.
        if predicted_gap {
            self.local.load_u(x)?;
            let ul = self.local.u()?;
            if let Some(c) = &mut self.contact {
                c.keep_predicted(&ul);
            }
        }
        if extrapolating && !self.compaction_admissible(x)? {
            let Some(contact) = &self.contact else { return Ok(()) };
            let mut affine = x.duplicate()?;
            contact.isochoric(&start, &x0, &self.disc, &mut affine)?;
            self.retie(&mut affine)?;
            if self.compaction_admissible(&affine)? {
                x.copy_from(&affine)?;
            }
        }
        Ok(())
    }

    /// Whether J > Φs at every point in the state `x` (true for models without a solid
    /// fraction). Collective.
    fn compaction_admissible(&mut self, x: &Vector) -> Result<bool> {
        let Some(phi_s) = self.disc.model.solid_fraction() else { return Ok(true) };
        self.local.load_u(x)?;
        let disc = &self.disc;
        let ok = self.local.with_u(|ul| disc.min_j(ul).is_ok_and(|j| j > phi_s))?;
        Ok(crate::parallel::all(&self.world, ok))
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
        self.local.load_u(x)?;
        let (disc, mut xw) = (&self.disc, x.write()?);
        self.local.with_u_mut(|ul| {
            equal_order::tie_nodes(ul, &disc.mesh);
            for (l, &v) in ul.iter().enumerate().take(disc.dofs.n_u_local()) {
                if let Some(i) = disc.dofs.local_to_owned(l) {
                    xw[i] = v;
                }
            }
        })
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
        let start = ts.time()?;
        self.tools.iter().for_each(|tools| tools.move_to(start, t));
        match &mut self.contact {
            Some(c) => c.move_to(ts.time()?, t, &self.disc.dofs),
            None => Ok(()),
        }
    }

    fn initial_guess(&mut self, ts: TsRef, x: &mut Vector) -> Result<()> {
        self.predict(ts, x)
    }
}
