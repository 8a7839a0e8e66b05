//! The rigid plates in the steps ([`ContactStage`]): the plates, their SNESVI contact bounds
//! moved to each stage time, the predictor of a step (the previous state extrapolated with the
//! last step's velocity, the contact nodes moved with the plate, or the isochoric guess where
//! that compacts a point to its solid fraction), whose gaps may set the step's drainage, and
//! the drainage out of contact in the residual and the Jacobian.

use super::schur::SchurApprox;
use crate::error::{Error, Result};
use crate::fem::assembly::Discretization;
use crate::fem::dofmap::DofMap;
use crate::petsc::{Int, Mat, Vector};
use crate::physics::contact::{DrainageGap, Plates};
use crate::physics::medium::Medium;
use crate::physics::surface_tension::PlatePlanes;
use crate::physics::tools::protocol::Mode;
use crate::solver::active_set::{Border, PositionUnknown};
use mpi::topology::SimpleCommunicator;

/// "No bound" for SNESVI (PETSc's PETSC_INFINITY).
pub(super) const INFINITY: f64 = f64::MAX / 4.0;

/// The plates and what the steps keep of them.
pub(super) struct ContactStage {
    plates: Plates,
    /// SNESVI lower/upper bounds (SNES keeps references; refreshed at every stage time).
    bounds: (Vector, Vector),
    /// (start, stage) time of the step being solved, for the predictor.
    stage: (f64, f64),
    /// The velocity the predictor of the step being solved extrapolates with (the driver's
    /// last step rate, `driver::rate`; None: no extrapolation, as after a loading kink).
    extrapolation: Option<Vector>,
    /// The predictor of the step being solved (local layout), whose gaps set the drainage when
    /// the plates drain by the predicted gap (`DrainageGap::Predicted`).
    predicted: Option<Vec<f64>>,
    /// The upper plate between steps (force control).
    upper: Upper,
}

/// Force control of an upper plate that touches nothing (at time t, `gap` µm away): what to do
/// instead.
pub(crate) fn untouched(t: f64, gap: f64) -> String {
    format!(
        "force control from t = {t} s, but the upper plate is {} µm from the body there: it cannot press on \
         nothing. Reach the body under displacement control first (a displacement row before the force row)",
        crate::io::fmt_significant(gap, 4)
    )
}

/// The upper plate's committed displacement and its last step's rate, the protocol segment of
/// the last stage, the position a `"held"` row holds, and the model's share of a full-body
/// force (1 / the symmetry factor).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Upper {
    pub(crate) d: f64,
    pub(crate) rate: f64,
    pub(crate) segment: usize,
    pub(crate) held: f64,
    pub(crate) share: f64,
    /// The stage just switched to force control (its first attempt; the gap is checked).
    pub(crate) switched: bool,
}

impl ContactStage {
    /// The solver's border for the upper plate's force control (None without force rows): its
    /// bounds move with it (−1 on every contact node's upper bound but the anchor's), its
    /// reaction is −F_z summed over the contact nodes of the upper half.
    pub(crate) fn border(
        &self,
        world: &SimpleCommunicator,
        template: &Vector,
        dofs: &DofMap,
    ) -> Result<Option<Border>> {
        let p = &self.plates;
        if !p.upper.has_force() {
            return Ok(None);
        }
        let (mut lower, mut upper, mut reaction) =
            (template.duplicate()?, template.duplicate()?, template.duplicate()?);
        lower.zero()?;
        upper.zero()?;
        reaction.zero()?;
        {
            let (mut s, mut c) = (upper.write()?, reaction.write()?);
            for (n, i) in p.upper_nodes(dofs) {
                s[i] = -1.0;
                if p.upper_half(n) {
                    c[i] = -1.0;
                }
            }
        }
        Ok(Some(Border::new(world, p.positions.clone(), vec![PositionUnknown { lower, upper, reaction }])))
    }

    /// The plates with their contact bounds at t = 0 on the surface u_z dofs (vectors like
    /// `template`, ±∞ elsewhere).
    pub(crate) fn new(plates: Plates, template: &Vector, dofs: &DofMap, share: f64) -> Result<ContactStage> {
        let d0 = match plates.upper.at(0.0, 0.0) {
            Mode::Displacement(d) => d,
            Mode::Force(_) => 0.0,
        };
        plates.positions.borrow_mut().d[0] = d0;
        let upper = Upper { d: d0, rate: 0.0, segment: 0, held: d0, share, switched: false };
        let (mut lo, mut hi) = (template.duplicate()?, template.duplicate()?);
        lo.set(-INFINITY)?;
        hi.set(INFINITY)?;
        {
            let (mut l, mut h) = (lo.write()?, hi.write()?);
            plates.fill_bounds(0.0, dofs, &mut l, &mut h);
        }
        Ok(ContactStage { plates, bounds: (lo, hi), stage: (0.0, 0.0), extrapolation: None, predicted: None, upper })
    }

    pub(crate) fn plates(&self) -> &Plates {
        &self.plates
    }

    /// The bounds for `SNESVISetVariableBounds`.
    pub(crate) fn bounds(&self) -> (&Vector, &Vector) {
        (&self.bounds.0, &self.bounds.1)
    }

    /// The plates' faces at time t, for the surface's adhesion.
    pub(crate) fn planes(&self, t: f64) -> PlatePlanes {
        PlatePlanes { lower: self.plates.z_lower(t), upper: self.plates.z_upper() }
    }

    /// Sets the velocity the predictor of the next steps extrapolates with (copied; None: the
    /// previous state, as after a loading kink).
    pub(crate) fn set_extrapolation(&mut self, velocity: Option<&Vector>) -> Result<()> {
        match velocity {
            Some(v) => match &mut self.extrapolation {
                Some(x) => x.copy_from(v)?,
                None => self.extrapolation = Some(v.copy()?),
            },
            None => self.extrapolation = None,
        }
        Ok(())
    }

    /// Whether the predictor extrapolates (else it starts from the previous state).
    pub(crate) fn extrapolating(&self) -> bool {
        self.extrapolation.is_some()
    }

    /// The state whose gaps set the last step's drainage (local layout), if not its solution:
    /// the predictor's, with `DrainageGap::Predicted`.
    pub(crate) fn drainage_gaps(&self) -> Option<&[f64]> {
        self.predicted.as_deref()
    }

    /// Moves the lower plate's bound to the stage time t of the step from `start` (also on a
    /// retried step).
    pub(crate) fn move_to(&mut self, start: f64, t: f64, dofs: &DofMap) -> Result<()> {
        self.move_upper(start, t);
        let (lo, hi) = &mut self.bounds;
        let (mut l, mut h) = (lo.write()?, hi.write()?);
        self.plates.fill_bounds(t, dofs, &mut l, &mut h);
        self.stage = (start, t);
        Ok(())
    }

    /// The upper plate at the stage time t of the step from `start`: prescribed, or under force
    /// control its target and its predicted position (the committed one extrapolated with its
    /// last rate), from which the solver moves it.
    fn move_upper(&mut self, start: f64, t: f64) {
        let u = &mut self.upper;
        let j = self.plates.upper.segment(t);
        if j != u.segment && self.plates.upper.holds_at(j) {
            u.held = u.d;
        }
        u.switched = j != u.segment || start == 0.0 && t > 0.0;
        u.segment = j;
        let mut p = self.plates.positions.borrow_mut();
        match self.plates.upper.at(t, u.held) {
            Mode::Displacement(d) => (p.d[0], p.target[0]) = (d, None),
            Mode::Force(f) => {
                let ahead = if self.extrapolation.is_some() { (t - start) * u.rate } else { 0.0 };
                (p.d[0], p.target[0]) = (u.d + ahead, Some(f * u.share));
            }
        }
    }

    /// Commits the upper plate's position of the accepted step of size dt (its rate kept
    /// with `keep_rate`).
    pub(crate) fn commit(&mut self, dt: f64, keep_rate: bool) {
        let d = self.plates.positions.borrow().d[0];
        self.upper.rate = if keep_rate && dt > 0.0 { (d - self.upper.d) / dt } else { 0.0 };
        self.upper.d = d;
    }

    /// The upper plate between steps (for a checkpoint).
    pub(crate) fn upper(&self) -> Upper {
        self.upper
    }

    /// Restores the upper plate of a checkpoint (at its time: the next stage moves the bounds).
    pub(crate) fn set_upper(&mut self, upper: Upper) {
        self.upper = upper;
        self.plates.positions.borrow_mut().d[0] = upper.d;
    }

    /// At the first stage under force control after a switch at time t: the upper plate must
    /// touch the body at the step's start (owned entries `x0`: within the seal gap), else the
    /// error says what to do (collective).
    pub(crate) fn check_switch(&self, world: &SimpleCommunicator, x0: &[f64], dofs: &DofMap, t: f64) -> Result<()> {
        let force = self.plates.positions.borrow().target[0].is_some();
        if !(force && self.upper.switched) {
            return Ok(());
        }
        let gap = -crate::parallel::max(world, -self.plates.upper_gap(self.upper.d, dofs, x0));
        if gap > self.plates.drain.seal_gap {
            return Err(Error::Scene { path: "plates.upper".into(), msg: untouched(t, gap) });
        }
        Ok(())
    }

    /// The predictor in `x`: the step's start `start` extrapolated with the last step's
    /// velocity (if any), the nodes on the lower plate moved with it (`Plates::predict`).
    /// Returns the start's owned entries.
    pub(crate) fn extrapolate(&self, start: &Vector, dofs: &DofMap, x: &mut Vector) -> Result<Vec<f64>> {
        let (t0, t1) = self.stage;
        x.copy_from(start)?;
        let x0 = start.read()?.to_vec();
        if let Some(v) = &self.extrapolation {
            x.axpy(t1 - t0, v)?;
        }
        self.plates.predict(t0, t1, dofs, &x0, &mut x.write()?);
        self.plates.predict_upper(self.upper.d, dofs, &x0, &mut x.write()?);
        Ok(x0)
    }

    /// Whether the drainage takes the predictor's gaps ([`ContactStage::keep_predicted`]).
    pub(crate) fn drains_by_predicted_gap(&self) -> bool {
        self.plates.drain.gap == DrainageGap::Predicted
    }

    /// Keeps the predictor of the step (local layout) for the drainage's gaps.
    pub(crate) fn keep_predicted(&mut self, local: &[f64]) {
        let predicted = self.predicted.get_or_insert_with(Vec::new);
        self.plates.drain_d.set(Some(self.plates.positions.borrow().d[0]));
        predicted.clear();
        predicted.extend_from_slice(local);
    }

    /// The isochoric affine guess from the start `start` (owned entries `x0`) in `x`
    /// (`Plates::predict_isochoric`), the contact nodes moved with the plate.
    pub(crate) fn isochoric(&self, start: &Vector, x0: &[f64], disc: &Discretization, x: &mut Vector) -> Result<()> {
        let (t0, t1) = self.stage;
        x.copy_from(start)?;
        let n = disc.dofs.n_owned_nodes;
        self.plates.predict_isochoric(t0, t1, &disc.mesh.coords[..n], disc.family().axes(), x0, &mut x.write()?);
        self.plates.predict(t0, t1, &disc.dofs, x0, &mut x.write()?);
        Ok(())
    }

    /// The drainage through the surface off the plates into the local residual `f`: outflow
    /// c(g) (p − p_m) at the local state `u`, p_m the medium's pressure at the vertex's current
    /// position (0 without a medium: the bath's gauge).
    pub(crate) fn add_drainage(
        &self,
        disc: &Discretization,
        u: &[f64],
        t: f64,
        medium: Option<&Medium>,
        f: &mut [f64],
    ) {
        for d in self.plates.drainage(&disc.mesh, &disc.dofs, self.predicted.as_deref().unwrap_or(u), t) {
            match medium {
                None => f[d.p] += d.conductance * u[d.p],
                Some(m) => f[d.p] += d.conductance * (u[d.p] - m.at_node(&disc.mesh, &disc.dofs, d.vertex, u)),
            }
        }
    }

    /// The drainage's Jacobian: d(c p)/dp = c on the diagonal, d(c p)/du_z = c' p (not with the
    /// predicted gap, fixed during the step); and c in the Schur approximation. With a medium,
    /// c' (p − p_m) instead, and −c ∇p_m on the vertex's u columns (in the pattern: the vertex
    /// couples with its own u).
    pub(crate) fn add_drainage_jacobian(
        &self,
        disc: &Discretization,
        u: &[f64],
        t: f64,
        medium: Option<&Medium>,
        jac: &mut Mat,
        schur: &mut SchurApprox,
    ) -> Result<()> {
        let l2g = &disc.dofs.l2g;
        let gaps = self.predicted.as_deref();
        for d in self.plates.drainage(&disc.mesh, &disc.dofs, gaps.unwrap_or(u), t) {
            if disc.constrained[d.p] {
                continue;
            }
            let p_m = medium.map_or(0.0, |m| m.at_node(&disc.mesh, &disc.dofs, d.vertex, u));
            let dc_du = if gaps.is_some() { 0.0 } else { d.d_conductance * (u[d.p] - p_m) };
            jac.add_values(&[l2g[d.p]], &[l2g[d.p], l2g[d.uz]], &[d.conductance, dc_du])?;
            if let Some(m) = medium {
                for (c, g) in m.gradient_at(&disc.mesh, &disc.dofs, d.vertex, u).iter().take(disc.dofs.nc).enumerate() {
                    let col = disc.dofs.u_local(d.vertex, c);
                    if !disc.constrained[col] {
                        jac.add_values(&[l2g[d.p]], &[l2g[col]], &[-d.conductance * g])?;
                    }
                }
            }
            let gv = disc.mesh.vertex_global[d.p - disc.dofs.n_u_local()] as Int;
            schur.add_diagonal(gv, d.conductance)?;
        }
        Ok(())
    }
}
