//! The rate of the last accepted step: the velocity the next step's predictor extrapolates
//! with (`PoroProblem::set_extrapolation`; the plates' contact correction of the guess is
//! physics, `Plates::predict`) and the local error estimate the schedule's step controller
//! (`Schedule::next_nominal`, `Schedule::reject`) acts on.

use crate::error::Result;
use crate::parallel::{max_slice, sum_slice};
use crate::petsc::Vector;
use crate::physics::problem::{backward_euler_rate, ErrorScales};
use mpi::topology::SimpleCommunicator;

/// The velocity of an accepted step and its size.
pub(crate) struct StepRate {
    pub(crate) velocity: Vector,
    pub(crate) dt: f64,
}

impl StepRate {
    /// The backward-Euler rate of the step from `prev` to `u` in dt.
    pub(crate) fn of(prev: &Vector, u: &Vector, dt: f64) -> Result<StepRate> {
        Ok(StepRate { velocity: backward_euler_rate(u, prev, dt)?, dt })
    }

    /// Local error estimate of the backward-Euler step from `prev` to `u` in dt that followed
    /// this one, relative to `tol`: ≤ 1 is within tolerance (collective).
    ///
    /// The estimate is the distance to the linear extrapolation of the previous step,
    /// e = dt/(dt + dt_prev) (u − u_prev − dt v_prev), Milne's device: for BE, whose local
    /// error is −dt²/2 ü, u − (u_prev + dt v_prev) = dt (dt + dt_prev)/2 ü + O(dt³). Measured in
    /// the RMS norm per field (a few nodes entering contact in a step jump; the
    /// bulk does not), relative to the field's magnitude with a floor (`scales`: h for u, 10% of
    /// the drained bulk modulus for p), so a field decaying to zero does not force ever smaller
    /// steps.
    pub(crate) fn error(
        &self,
        world: &SimpleCommunicator,
        (prev, u): (&Vector, &Vector),
        dt: f64,
        tol: f64,
        scales: ErrorScales,
    ) -> Result<f64> {
        let nu = scales.n_u_owned;
        let w = dt / (dt + self.dt);
        // Per field (u, p): Σ e², number of dofs, and max |x| over this rank's dofs.
        let (mut sums, mut maxs) = ([0.0f64; 4], [0.0f64; 2]);
        {
            let (uv, pv, vv) = (u.read()?, prev.read()?, self.velocity.read()?);
            for i in 0..uv.len() {
                let e = w * (uv[i] - pv[i] - dt * vv[i]);
                let f = usize::from(i >= nu);
                sums[2 * f] += e * e;
                sums[2 * f + 1] += 1.0;
                maxs[f] = maxs[f].max(uv[i].abs());
            }
        }
        let (gs, gm) = (sum_slice(world, &sums), max_slice(world, &maxs));
        let rms = |f: usize| (gs[2 * f] / gs[2 * f + 1].max(1.0)).sqrt();
        let u_ref = gm[0].max(scales.u_floor);
        let p_ref = gm[1].max(scales.p_floor);
        Ok((rms(0) / u_ref).max(rms(1) / p_ref) / tol)
    }
}
