//! Taking the steps ([`Stepper`]): the time stepper with its problem, the state between steps,
//! the schedule's step control (`Stepper::advance`), gravity settling before t = 0, and the
//! step's Jacobian against central differences (`-poroplast_check_jacobian`).

use super::progress::{Progress, Stages, Step};
use super::schedule::Schedule;
use super::state::StepState;
use super::voice::Voice;
use crate::error::{Error, Result};
use crate::io::checkpoint::{Counters, FileLayout, RunState};
use crate::observe::observers::{Observers, Sample};
use crate::petsc::{SolverState, Stage, Ts};
use crate::physics::problem::PoroProblem;
use crate::scene::medium::weighing_density;
use crate::scene::{Scene, SolidSpec};
use mpi::topology::SimpleCommunicator;
use std::time::Instant;

/// The time stepper and what its steps need.
pub(super) struct Stepper {
    ts: Ts<PoroProblem>,
    /// U, U before the last step, and the last step's rate (the qp state is the problem's).
    state: StepState,
    schedule: Schedule,
    /// Settle under gravity before t = 0.
    settle: bool,
    /// `-poroplast_check_jacobian [eps]`: after each step, compare the assembled Jacobian with
    /// central differences of the residual (`PoroProblem::jacobian_error`, relative step eps,
    /// default 1e-7) and print the errors.
    jacobian_check: Option<f64>,
    /// The solid law loses strong ellipticity under the run's strains (`ellipticity_warning`):
    /// added to a failed solve's error.
    ellipticity: Option<String>,
}

impl Stepper {
    /// Steps `ts` from the state `state` on `schedule`.
    pub(crate) fn new(
        ts: Ts<PoroProblem>,
        state: StepState,
        schedule: Schedule,
        settle: bool,
        jacobian_check: Option<f64>,
        ellipticity: Option<String>,
    ) -> Stepper {
        Stepper { ts, state, schedule, settle, jacobian_check, ellipticity }
    }

    pub(crate) fn problem(&self) -> &PoroProblem {
        self.ts.problem()
    }

    pub(crate) fn schedule(&self) -> &Schedule {
        &self.schedule
    }

    /// The solver's Newton and Krylov iteration totals so far (this process).
    pub(crate) fn solver_totals(&self) -> Result<(usize, usize)> {
        self.ts.solver_totals()
    }

    /// Steps TS cut so far.
    pub(crate) fn rejections(&self) -> Result<usize> {
        self.ts.rejections()
    }

    /// Samples the state at time t after the step of size dt just taken, for `observers`.
    pub(crate) fn sample(&mut self, observers: &Observers, t: f64, dt: f64, fields: bool) -> Result<Sample> {
        observers.sample(self.ts.problem_mut(), &self.state.u, &self.state.prev, t, dt, fields)
    }

    /// Samples the initial state (at t = 0, as if reached from itself), fields included.
    pub(crate) fn sample_initial(&mut self, observers: &Observers) -> Result<Sample> {
        let u = &self.state.u;
        observers.sample(self.ts.problem_mut(), u, u, 0.0, 0.0, true)
    }

    /// The run state after the step just taken with `counters` (collective), the step state
    /// by the file's numbering `layout`.
    pub(crate) fn capture(
        &mut self,
        world: &SimpleCommunicator,
        layout: FileLayout,
        counters: Counters,
    ) -> Result<RunState> {
        self.state.capture(world, self.ts.problem_mut(), layout, counters)
    }

    /// Sets the step state and the time of a checkpoint's run state; returns its counters.
    pub(crate) fn restore(&mut self, state: RunState) -> Result<Counters> {
        let c = self.state.apply(self.ts.problem_mut(), state)?;
        self.ts.set_time(c.t)?;
        Ok(c)
    }

    /// The nonlinear solver's state between steps (the kept factorised Jacobian), if it has one.
    pub(crate) fn solver_state(&mut self) -> Result<Option<SolverState>> {
        self.ts.nonlinear_solver_state()
    }

    /// Continues with a saved nonlinear solver state (a resume on as many ranks).
    pub(crate) fn restore_solver_state(&mut self, state: SolverState) {
        self.ts.restore_nonlinear_solver_state(state)
    }

    /// Makes the next solve start afresh, as a resumed run's does.
    pub(crate) fn restart_solver(&mut self) {
        self.ts.restart_nonlinear_solver()
    }

    /// One time step from the current state, with the step size of the schedule (a step the
    /// error estimate rejects is taken again, shorter).
    pub(crate) fn advance(&mut self, pg: &mut Progress, stages: Stages, world: &SimpleCommunicator) -> Result<Step> {
        self.state.prev.copy_from(&self.state.u)?;
        let ws = Instant::now();
        let (taken, err) = loop {
            let dt = self.schedule.step(pg.c.t, pg.c.nominal);
            self.ts.set_time_step(dt)?;
            {
                let _g = stages.solve.push();
                self.ts.step().map_err(|e| self.explain(e))?;
            }
            let taken = self.ts.time()? - pg.c.t;
            if taken < self.schedule.dt_min && taken < dt {
                let last =
                    self.ts.domain_errors().1.map(|d| format!("; last inadmissible state: {d}")).unwrap_or_default();
                return Err(self.explain(Error::Diverged(format!(
                    "failed solves cut the step from t = {} to {taken:.3e} s, below time.dt_min = {:.3e} s: \
                     the solve does not converge here{last}",
                    pg.c.t, self.schedule.dt_min
                ))));
            }
            let err = match (self.schedule.tol, &self.state.rate) {
                (Some(tol), Some(rate)) => {
                    let scales = self.ts.problem().error_scales();
                    Some(rate.error(world, (&self.state.prev, &self.state.u), taken, tol, scales)?)
                }
                _ => None,
            };
            match self.schedule.reject(taken, err) {
                Some(retry) => {
                    // Too large an error: back to the start of the step, with a shorter one.
                    self.ts.roll_back()?;
                    pg.c.nominal = retry;
                    pg.c.rejected += 1;
                }
                None => break (taken, err),
            }
        };
        let wall = ws.elapsed().as_secs_f64();
        pg.c.solve_s += wall;
        pg.c.t = self.ts.time()?;
        pg.c.step += 1;
        let totals = self.ts.solver_totals()?;
        let its = (totals.0 - pg.totals.0, totals.1 - pg.totals.1);
        pg.totals = totals;
        pg.c.newton += its.0;
        pg.c.ksp += its.1;
        pg.c.nominal = self.schedule.next_nominal(pg.c.nominal, taken, pg.c.t, err);
        let kink = self.schedule.at_kink(pg.c.t);
        // The step's rate serves the contact predictor and the error estimate; not across a kink.
        let keep_rate = !kink && (self.ts.problem().plates().is_some() || self.schedule.tol.is_some());
        self.state.commit(self.ts.problem_mut(), taken, keep_rate)?;
        if kink {
            self.ts.restart_step()?;
        }
        pg.recent.push_back(wall);
        if pg.recent.len() > 5 {
            pg.recent.pop_front();
        }
        Ok(Step { dt: taken, its })
    }

    /// Gravity settling, if the run settles: one drained step from t = −T to 0 with T huge (so
    /// J̇ ≈ 0 and the fluid is at rest): the equilibrium resting on the lower plate, the state
    /// at t = 0.
    ///
    /// From the undeformed sphere the whole weight comes down on one contact point: a full Newton
    /// step can overshoot there (J < Φs) for soft solids (µ = 3 kPa); the active-set Newton halves
    /// such steps. Where that is not enough — pole elements of a micrometre or less, which the
    /// weight alone compacts below Φs before a contact patch forms — the weight is applied in
    /// stages (`SETTLE_RAMP`), each settled state the start of the next.
    pub(crate) fn settle(&mut self, stage: Stage, scene: &Scene, voice: &Voice) -> Result<()> {
        const SETTLE_RAMP: [f64; 4] = [0.01, 0.1, 0.4, 1.0];
        if !self.settle {
            return Ok(());
        }
        let _g = stage.push();
        // B_p(X, 0⁻) = I: no remodelling while settling.
        self.ts.problem_mut().freeze_qp_state(true);
        let start = self.state.u.copy()?;
        if let Err(e) = self.settle_under(1.0, scene) {
            // The cause is in the error if the stages fail too; here, what is being done.
            drop(e);
            voice.warn(&format!(
                "settling under the whole weight at once did not converge; applying it in stages ({})",
                SETTLE_RAMP.map(|f| f.to_string()).join(", ")
            ));
            self.state.u.copy_from(&start)?;
            for factor in SETTLE_RAMP {
                self.settle_under(factor, scene)?;
            }
        }
        self.ts.problem_mut().freeze_qp_state(false);
        self.ts.set_time(0.0)
    }

    /// One settling step under `factor` times the scene's gravity.
    fn settle_under(&mut self, factor: f64, scene: &Scene) -> Result<()> {
        const T: f64 = 1e6;
        self.ts.problem_mut().set_gravity_factor(factor);
        self.ts.set_time(-T)?;
        self.ts.set_time_step(T)?;
        let r = self.ts.step().map_err(|e| {
            self.explain(Error::Diverged(format!(
                "settling under gravity (the static equilibrium on the lower plate, before t = 0; \
                 {factor} of the weight) failed: {e}. {}",
                settle_cause(scene)
            )))
        });
        self.ts.problem_mut().set_gravity_factor(1.0);
        r
    }

    /// A failed solve's error, with the likely cause when the solid law is not elliptic.
    fn explain(&self, e: Error) -> Error {
        match (e, &self.ellipticity) {
            (Error::Diverged(m), Some(w)) => Error::Diverged(format!("{m}. Likely cause: {w}")),
            (e, _) => e,
        }
    }

    /// `-poroplast_check_jacobian`: the assembled Jacobian of the step against central
    /// differences (rank 0 prints the errors).
    pub(crate) fn report_jacobian_error(&mut self, pg: &Progress, step: Step, voice: &Voice) -> Result<()> {
        let Some(eps) = self.jacobian_check else { return Ok(()) };
        let (problem, jac) = self.ts.problem_and_jacobian();
        let (u, prev) = (&self.state.u, &self.state.prev);
        let (eu, ep) = problem.jacobian_error(pg.c.t, step.dt, u, prev, jac, eps)?;
        if voice.rank0() {
            crate::console::line(&format!(
                "jacobian check: step {} t = {:.6e}: rel. error u rows {eu:.3e}, p rows {ep:.3e}",
                pg.c.step, pg.c.t
            ));
        }
        Ok(())
    }
}

/// The likely cause of a failed settling: a solid too soft for its weight, or, when it carries
/// it easily, the mesh at the lower pole (cells the first point contact compacts below Φs).
fn settle_cause(scene: &Scene) -> String {
    let Some(m) = scene.material.mixture() else { return String::new() };
    let (Ok(SolidSpec::MuNu { mu, .. }), Some(r)) = (m.solid(), scene.plates.as_ref().map(|p| p.radius())) else {
        return "Can the solid carry its weight (material.mu, material.gravity)?".into();
    };
    let g_drained = m.phi_s * mu;
    // ρ |g| R in Pa (R in µm), in kPa.
    // The excess over the medium's, if it sits in one.
    let weight = weighing_density(m, scene.medium.as_ref()).abs() * m.gravity_magnitude() * r * 1e-6 / 1e3;
    let ratio = weight / g_drained;
    if ratio > 0.1 {
        return format!(
            "The weight's stress ρ g R = {weight:.3e} kPa is {ratio:.2} of the drained shear modulus Φs µ = \
             {g_drained:.3e} kPa: the solid is too soft to carry its weight (raise the modulus{})",
            if scene.medium.is_none() { "; an aggregate in medium is buoyed: add [medium]" } else { "" }
        );
    }
    let sizes: Vec<String> = ["h_pole", "h_surf", "h"]
        .iter()
        .filter_map(|k| scene.mesh.params.get(*k).map(|v| format!("mesh.params.{k} = {v} µm")))
        .collect();
    format!(
        "The solid carries its weight easily (ρ g R = {weight:.2e} kPa, {ratio:.1e} of Φs µ = {g_drained:.3e} kPa), so \
         the likely cause is the mesh: its smallest cells at the lower pole, which the first point contact compacts \
         ({}). Coarsen the pole (mesh.params.h_pole of R/100 or more)",
        if sizes.is_empty() { "see mesh.params".into() } else { sizes.join(", ") }
    )
}
