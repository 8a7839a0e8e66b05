//! The rigid plates in the steps ([`ContactStage`]): the plates, their SNESVI contact bounds
//! moved to each stage time, the predictor of a step (the previous state extrapolated with the
//! last step's velocity, the contact nodes moved with the plate, or the isochoric guess where
//! that compacts a point to its solid fraction), whose gaps may set the step's drainage
//! (`drainage_stage`).

use crate::error::{Error, Result};
use crate::fem::assembly::Discretization;
use crate::fem::dofmap::DofMap;
use crate::petsc::Vector;
use crate::physics::contact::{DrainageGap, Plates};
use crate::physics::surface_tension::PlatePlanes;
use crate::physics::tools::protocol::Progress;
use crate::solver::active_set::{Moves, PositionUnknown};
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
    crate::physics::tools::protocol::untouched("the upper plate", t, gap)
}

/// The upper plate between steps (`Progress`: its committed displacement, rate, segment, held
/// position), and the model's share of a full-body force (1 / the symmetry factor).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Upper {
    pub(crate) progress: Progress,
    pub(crate) share: f64,
}

impl ContactStage {
    /// The upper plate as a position of the solver's border (None without force rows): its
    /// bounds move with it (−1 on every contact node's upper bound but the anchor's), its
    /// reaction is −F_z summed over the contact nodes of the upper half.
    pub(crate) fn border(&self, template: &Vector, dofs: &DofMap) -> Result<Option<PositionUnknown>> {
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
        Ok(Some(PositionUnknown {
            shared: p.positions.clone(),
            index: 0,
            name: "the upper plate".into(),
            moves: Moves::Bounds { lower, upper, reaction },
        }))
    }

    /// The plates with their contact bounds at t = 0 on the surface u_z dofs (vectors like
    /// `template`, ±∞ elsewhere).
    pub(crate) fn new(plates: Plates, template: &Vector, dofs: &DofMap, share: f64) -> Result<ContactStage> {
        let progress = Progress::start(&plates.upper);
        plates.positions.borrow_mut().d[0] = progress.d;
        let upper = Upper { progress, share };
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
        let (d, force) = u.progress.stage(&self.plates.upper, start, t, self.extrapolation.is_some());
        let mut p = self.plates.positions.borrow_mut();
        (p.d[0], p.target[0]) = (d, force.map(|f| f * u.share));
    }

    /// Commits the upper plate's position of the accepted step of size dt (its rate kept
    /// with `keep_rate`).
    pub(crate) fn commit(&mut self, dt: f64, keep_rate: bool) {
        let d = self.plates.positions.borrow().d[0];
        self.upper.progress.commit(d, dt, keep_rate);
    }

    /// The upper plate between steps (for a checkpoint).
    pub(crate) fn upper(&self) -> Upper {
        self.upper
    }

    /// Restores the upper plate of a checkpoint (at its time: the next stage moves the bounds).
    pub(crate) fn set_upper(&mut self, upper: Upper) {
        self.upper = upper;
        self.plates.positions.borrow_mut().d[0] = upper.progress.d;
    }

    /// At the first stage under force control after a switch at time t: the upper plate must
    /// touch the body at the step's start (owned entries `x0`: within the seal gap), else the
    /// error says what to do (collective).
    pub(crate) fn check_switch(&self, world: &SimpleCommunicator, x0: &[f64], dofs: &DofMap, t: f64) -> Result<()> {
        let force = self.plates.positions.borrow().target[0].is_some();
        if !(force && self.upper.progress.switched) {
            return Ok(());
        }
        let gap = -crate::parallel::max(world, -self.plates.upper_gap(self.upper.progress.d, dofs, x0));
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
        self.plates.predict_upper(self.upper.progress.d, dofs, &x0, &mut x.write()?);
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
}
