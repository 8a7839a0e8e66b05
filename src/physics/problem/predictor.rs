//! The rigid plates in the steps: their contact bounds, moved to each stage time, and the
//! predictor of a step (the previous state extrapolated with the last step's velocity, the
//! contact nodes moved with the plate, the isochoric guess where that compacts a point to its
//! solid fraction), whose gaps may set the step's drainage.

use super::{PoroProblem, INFINITY};
use crate::error::Result;
use crate::petsc::{TsRef, Vector};
use crate::physics::contact::{DrainageGap, Plates};

impl PoroProblem {
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

    /// The state whose gaps set the last step's drainage (local layout), if not its solution:
    /// the predictor's, with `DrainageGap::Predicted`.
    pub fn drainage_gaps(&self) -> Option<&[f64]> {
        self.predicted.as_deref()
    }

    /// Whether J > Φs at every point in the state `x` (true for models without a solid
    /// fraction). Collective.
    fn compaction_admissible(&mut self, x: &Vector) -> Result<bool> {
        let Some(phi_s) = self.disc.model.solid_fraction() else { return Ok(true) };
        self.scatter.forward(x, &mut self.u_loc)?;
        let ok = self.disc.min_j(&self.u_loc.read()?).is_ok_and(|j| j > phi_s);
        Ok(crate::parallel::all(&self.world, ok))
    }

    /// Moves the lower plate's bound to the stage time (also on a retried step).
    pub(super) fn stage_plates(&mut self, ts: TsRef, t: f64) -> Result<()> {
        if let (Some(pl), Some((lo, hi))) = (&self.plates, &mut self.bounds) {
            let (mut l, mut h) = (lo.write()?, hi.write()?);
            pl.fill_bounds(t, &self.disc.dofs, &mut l, &mut h);
            self.stage = (ts.time()?, t);
        }
        Ok(())
    }

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
    pub(super) fn predict(&mut self, ts: TsRef, x: &mut Vector) -> Result<()> {
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
