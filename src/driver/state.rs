//! The run state: the state between steps ([`StepState`]: U, the last step's rate — the
//! predictor's velocity and the error estimate's — and the committed qp state B_p, which the
//! problem holds), captured into the [`RunState`] of a checkpoint with everything else a
//! restart needs (where the time loop stands, the experiment's cumulative outflow, the output
//! counters), and applied from one. The files themselves are `io::checkpoint`'s.

use super::rate::StepRate;
use crate::error::Result;
use crate::fem::dofmap::DofMap;
use crate::io::checkpoint::{mesh_fingerprint, Counters, FileLayout, RunState, Snapshot};
use crate::mesh::dist::LocalMesh;
use crate::parallel::reduce_to_root;
use crate::petsc::Vector;
use crate::physics::problem::PoroProblem;
use crate::physics::tools::protocol::Progress;
use mpi::topology::SimpleCommunicator;

/// The state between steps, with one owner (the run). Its third part, the committed qp state,
/// is held by the problem, whose assembly reads it: [`StepState::commit`] commits it with the
/// step, [`RunState`] captures and applies it with the rest.
pub(crate) struct StepState {
    /// U, the solution vector of the time stepper.
    pub(crate) u: Vector,
    /// U at the start of the last step.
    pub(crate) prev: Vector,
    /// The last accepted step's rate (None after a kink of the loading, where the velocity
    /// jumps, and when neither the predictor nor the error estimate uses it).
    pub(crate) rate: Option<StepRate>,
}

impl StepState {
    /// The state at the start, U; no step taken yet.
    pub(crate) fn new(u: Vector) -> Result<StepState> {
        Ok(StepState { prev: u.duplicate()?, u, rate: None })
    }

    /// Commits the accepted step of size dt from `prev` to `u`: the problem's qp state and, with
    /// `keep_rate`, the step's rate for the predictor and the error estimate of the next.
    pub(crate) fn commit(&mut self, problem: &mut PoroProblem, dt: f64, keep_rate: bool) -> Result<()> {
        problem.commit(&self.prev, &self.u, dt, keep_rate)?;
        self.rate = if keep_rate && dt > 0.0 { Some(StepRate::of(&self.prev, &self.u, dt)?) } else { None };
        problem.set_extrapolation(self.rate.as_ref().map(|r| &r.velocity))
    }
}

/// An owned state vector by original node (this rank's owned nodes filled, zeros elsewhere).
fn by_original_node(mesh: &LocalMesh, dofs: &DofMap, local: &[f64], n_nodes: usize) -> Vec<f64> {
    let mut out = vec![0.0; 4 * n_nodes];
    for n in 0..mesh.n_owned_nodes {
        let o = mesh.node_original[n] as usize;
        for c in 0..3 {
            out[4 * o + c] = local[dofs.u_local(n, c)];
        }
        let v = mesh.vertex_of_node[n];
        out[4 * o + 3] = if v >= 0 { local[dofs.p_local(v as usize)] } else { 0.0 };
    }
    out
}

/// The owned entries of a state vector from its by-original-node values.
fn to_owned(mesh: &LocalMesh, dofs: &DofMap, state: &[f64], x: &mut Vector) -> Result<()> {
    let mut w = x.write()?;
    for n in 0..mesh.n_nodes() {
        let o = mesh.node_original[n] as usize;
        for c in 0..3 {
            if let Some(i) = dofs.local_to_owned(dofs.u_local(n, c)) {
                w[i] = state[4 * o + c];
            }
        }
        let v = mesh.vertex_of_node[n];
        if v >= 0 {
            if let Some(i) = dofs.local_to_owned(dofs.p_local(v as usize)) {
                w[i] = state[4 * o + 3];
            }
        }
    }
    Ok(())
}

/// The step state in and out of a checkpoint's run state.
impl StepState {
    /// Captures the run state on rank 0 (collective): the counters, and this step state with
    /// the problem's qp state by the file's numbering `layout`.
    pub(crate) fn capture(
        &self,
        world: &SimpleCommunicator,
        problem: &mut PoroProblem,
        layout: FileLayout,
        counters: Counters,
    ) -> Result<RunState> {
        let u_local = problem.localize(&self.u)?;
        let v_local = match &self.rate {
            Some(r) => Some((problem.localize(&r.velocity)?, r.dt)),
            None => None,
        };
        let (mesh, dofs) = (problem.mesh(), problem.dofs());
        let mut u = by_original_node(mesh, dofs, &u_local, layout.n_nodes);
        reduce_to_root(world, &mut u);
        let velocity = v_local.map(|(v, dt)| {
            let mut vv = by_original_node(mesh, dofs, &v, layout.n_nodes);
            reduce_to_root(world, &mut vv);
            (vv, dt)
        });
        let per_elem = problem.qp_state_per_elem();
        let mut qp_state = vec![0.0; layout.n_elems * per_elem];
        if per_elem > 0 {
            for (o, values) in problem.qp_state_by_original() {
                qp_state[o as usize * per_elem..(o as usize + 1) * per_elem].copy_from_slice(values);
            }
            reduce_to_root(world, &mut qp_state);
        }
        // The upper plate's, then each tool's (d, rate, segment, held).
        let plate = problem.upper_plate().map(|p| p.progress);
        let tools = plate.into_iter().chain(problem.tool_progress()).flat_map(|p| p.values()).collect();
        let snapshot = Snapshot { u, velocity, qp_state, tools };
        Ok(RunState { counters, snapshot, mesh: mesh_fingerprint(world, mesh) })
    }

    /// Sets this step state from a run state (U, the rate, the problem's qp state); returns
    /// its counters.
    pub(crate) fn apply(&mut self, problem: &mut PoroProblem, state: RunState) -> Result<Counters> {
        let Snapshot { u, velocity, qp_state, tools } = state.snapshot;
        let mut saved: Vec<Progress> = tools.chunks_exact(4).filter_map(Progress::from_values).collect();
        if let Some(mut p) = problem.upper_plate() {
            if !saved.is_empty() {
                p.progress = saved.remove(0);
                problem.set_upper_plate(p);
            }
        }
        // A checkpoint written before the tools had a state has none: their protocols give it.
        problem.set_tool_progress(&saved, state.counters.t);
        let (mesh, dofs) = (problem.mesh(), problem.dofs());
        to_owned(mesh, dofs, &u, &mut self.u)?;
        self.rate = match velocity {
            Some((v, dt)) => {
                let mut x = self.u.duplicate()?;
                to_owned(mesh, dofs, &v, &mut x)?;
                Some(StepRate { velocity: x, dt })
            }
            None => None,
        };
        problem.set_qp_state_by_original(&qp_state)?;
        problem.set_extrapolation(self.rate.as_ref().map(|r| &r.velocity))?;
        Ok(state.counters)
    }
}
