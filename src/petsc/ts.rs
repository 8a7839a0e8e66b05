//! `TS` wrapper: backward Euler with IFunction/IJacobian/pre-stage callbacks into a typed Rust
//! problem. Trampolines never unwind into C: panics and errors become PETSc errors, and the
//! original Rust error is kept and returned by [`Ts::step`]. A domain error (J ≤ Φs ...) is not
//! an error: it marks the SNES solve as failed so TS cuts the step and retries.

use super::snes::ShellBox;
use super::{check, ffi, pbool, raise, DmShell, Int, Mat, ShellSolve, Snes, Vector};
use crate::error::{Error, Result};
use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Handle to the running TS, given to callbacks.
#[derive(Clone, Copy)]
pub struct TsRef {
    raw: ffi::TS,
}

impl TsRef {
    pub(crate) fn snes(&self) -> Result<Snes> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::TSGetSNES(self.raw, &mut raw) })?;
        Ok(Snes { raw })
    }
    /// Size of the step being attempted.
    pub fn time_step(&self) -> Result<f64> {
        let mut dt = 0.0;
        check(unsafe { ffi::TSGetTimeStep(self.raw, &mut dt) })?;
        Ok(dt)
    }
    /// The solution at the start of the step being attempted (TS replaces it only when the
    /// step is accepted).
    pub(crate) fn solution(&self) -> Result<std::mem::ManuallyDrop<Vector>> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::TSGetSolution(self.raw, &mut raw) })?;
        Ok(unsafe { Vector::borrowed(raw) })
    }
    /// Start time of the step being attempted.
    pub(crate) fn time(&self) -> Result<f64> {
        let mut t = 0.0;
        check(unsafe { ffi::TSGetTime(self.raw, &mut t) })?;
        Ok(t)
    }
}

/// The physics a TS integrates: F(t, U, U̇) = 0.
pub trait TsProblem {
    /// Residual F(t, U, U̇).
    fn residual(&mut self, ts: TsRef, t: f64, u: &Vector, udot: &Vector, f: &mut Vector) -> Result<()>;
    /// dF/dU + shift dF/dU̇ into `jac` (and the preconditioning matrix `pre`, same object or not).
    #[allow(clippy::too_many_arguments)]
    fn jacobian(
        &mut self,
        ts: TsRef,
        t: f64,
        u: &Vector,
        udot: &Vector,
        shift: f64,
        jac: &mut Mat,
        pre: &mut Mat,
    ) -> Result<()>;
    /// Called before each stage solve, also on a retried step, with the stage time.
    fn pre_stage(&mut self, _ts: TsRef, _t: f64) -> Result<()> {
        Ok(())
    }
    /// Improves the initial guess `x` of each nonlinear solve (the previous solution by default).
    fn initial_guess(&mut self, _ts: TsRef, _x: &mut Vector) -> Result<()> {
        Ok(())
    }
    /// Called after each accepted step by `TSSolve` (a driver calling [`Ts::step`] itself does
    /// its own post-step work).
    fn post_step(&mut self, _ts: TsRef) -> Result<()> {
        Ok(())
    }
    /// TS monitor: called by `TSSolve` with the step number, time and solution.
    fn monitor(&mut self, _ts: TsRef, _step: usize, _t: f64, _u: &Vector) -> Result<()> {
        Ok(())
    }
}

struct Ctx<P> {
    problem: P,
    /// The TS itself (for callbacks that only get the SNES).
    ts: ffi::TS,
    /// First hard error raised inside a callback during the current step.
    error: Option<Error>,
    /// Domain errors (step cuts) seen so far, and the last message.
    domain_errors: usize,
    last_domain: Option<String>,
}

/// An owned TS with its problem. Drops the TS before the problem and DM it points to.
pub struct Ts<P: TsProblem> {
    raw: ffi::TS,
    ctx: Box<Ctx<P>>,
    _dm: Option<DmShell>,
    _keep: (Vector, Mat, Option<Mat>),
    /// A Rust nonlinear solver run as the SNESSHELL, if one is installed (double box: the
    /// SNES keeps a thin pointer to the inner one).
    shell: Option<Box<ShellBox>>,
}

impl<P: TsProblem> Drop for Ts<P> {
    fn drop(&mut self) {
        if super::alive() && !self.raw.is_null() {
            unsafe { ffi::TSDestroy(&mut self.raw) };
        }
    }
}

/// Runs a callback body, converting panics and errors into PETSc error codes.
fn guard<P>(ctx: *mut c_void, ts: ffi::TS, f: impl FnOnce(&mut Ctx<P>) -> Result<()>) -> ffi::PetscErrorCode {
    let ctx = unsafe { &mut *(ctx as *mut Ctx<P>) };
    match catch_unwind(AssertUnwindSafe(|| f(&mut *ctx))) {
        Ok(Ok(())) => 0,
        Ok(Err(Error::Domain { cell, point, j, msg })) => {
            // Soft failure: SNES reports a domain error and TS cuts the step.
            ctx.domain_errors += 1;
            ctx.last_domain = Some(format!("element {cell}, point {point}: {msg} (J = {j:.6})"));
            match (TsRef { raw: ts }).snes().and_then(|s| s.set_function_domain_error()) {
                Ok(()) => 0,
                Err(e) => {
                    let m = e.to_string();
                    ctx.error.get_or_insert(e);
                    raise(&m)
                }
            }
        }
        Ok(Err(e)) => {
            let m = e.to_string();
            ctx.error.get_or_insert(e);
            raise(&m)
        }
        Err(p) => {
            let m = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            let m = format!("panic in a PETSc callback: {m}");
            ctx.error.get_or_insert(Error::Internal(m.clone()));
            raise(&m)
        }
    }
}

unsafe extern "C" fn ifunction_tramp<P: TsProblem>(
    ts: ffi::TS,
    t: f64,
    u: ffi::Vec,
    udot: ffi::Vec,
    f: ffi::Vec,
    ctx: *mut c_void,
) -> ffi::PetscErrorCode {
    guard::<P>(ctx, ts, |c| {
        let (u, udot, mut f) = (Vector::borrowed(u), Vector::borrowed(udot), Vector::borrowed(f));
        c.problem.residual(TsRef { raw: ts }, t, &u, &udot, &mut f)
    })
}

#[allow(clippy::too_many_arguments)]
unsafe extern "C" fn ijacobian_tramp<P: TsProblem>(
    ts: ffi::TS,
    t: f64,
    u: ffi::Vec,
    udot: ffi::Vec,
    shift: f64,
    a: ffi::Mat,
    p: ffi::Mat,
    ctx: *mut c_void,
) -> ffi::PetscErrorCode {
    guard::<P>(ctx, ts, |c| {
        let (u, udot) = (Vector::borrowed(u), Vector::borrowed(udot));
        let (mut a, mut p) = (Mat::borrowed(a), Mat::borrowed(p));
        c.problem.jacobian(TsRef { raw: ts }, t, &u, &udot, shift, &mut a, &mut p)
    })
}

/// The problem context stored as the TS application context (for callbacks without a ctx).
unsafe fn app_ctx(ts: ffi::TS) -> Option<*mut c_void> {
    let mut ctx: *mut c_void = std::ptr::null_mut();
    (ffi::TSGetApplicationContext(ts, &mut ctx as *mut *mut c_void as *mut c_void) == 0 && !ctx.is_null())
        .then_some(ctx)
}

unsafe extern "C" fn prestage_tramp<P: TsProblem>(ts: ffi::TS, t: f64) -> ffi::PetscErrorCode {
    match app_ctx(ts) {
        Some(ctx) => guard::<P>(ctx, ts, |c| c.problem.pre_stage(TsRef { raw: ts }, t)),
        None => raise("TS has no application context"),
    }
}

unsafe extern "C" fn poststep_tramp<P: TsProblem>(ts: ffi::TS) -> ffi::PetscErrorCode {
    match app_ctx(ts) {
        Some(ctx) => guard::<P>(ctx, ts, |c| c.problem.post_step(TsRef { raw: ts })),
        None => raise("TS has no application context"),
    }
}

unsafe extern "C" fn guess_tramp<P: TsProblem>(_snes: ffi::SNES, x: ffi::Vec, ctx: *mut c_void) -> ffi::PetscErrorCode {
    let ts = (*(ctx as *mut Ctx<P>)).ts;
    guard::<P>(ctx, ts, |c| {
        let mut x = Vector::borrowed(x);
        c.problem.initial_guess(TsRef { raw: ts }, &mut x)
    })
}

unsafe extern "C" fn monitor_tramp<P: TsProblem>(
    ts: ffi::TS,
    step: Int,
    t: f64,
    u: ffi::Vec,
    ctx: *mut c_void,
) -> ffi::PetscErrorCode {
    guard::<P>(ctx, ts, |c| {
        let u = Vector::borrowed(u);
        c.problem.monitor(TsRef { raw: ts }, step.max(0) as usize, t, &u)
    })
}

impl<P: TsProblem> Ts<P> {
    /// A backward-Euler TS on `comm` integrating `problem`, with residual vector `f`, Jacobian
    /// `jac` and an optional separate preconditioning matrix. If `dm` is given it provides the
    /// field decomposition for PCFIELDSPLIT (and must hold the solution layout).
    pub fn new(
        comm: ffi::MPI_Comm,
        problem: P,
        f: Vector,
        jac: Mat,
        pre: Option<Mat>,
        mut dm: Option<DmShell>,
    ) -> Result<Ts<P>> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::TSCreate(comm, &mut raw) })?;
        let mut ts = Ts {
            raw,
            ctx: Box::new(Ctx { problem, ts: raw, error: None, domain_errors: 0, last_domain: None }),
            _dm: None,
            _keep: (f, jac, pre),
            shell: None,
        };
        let ctxp = &mut *ts.ctx as *mut Ctx<P> as *mut c_void;
        unsafe {
            if let Some(dm) = &mut dm {
                check(ffi::TSSetDM(raw, dm.raw))?;
                dm.set_snes(TsRef { raw }.snes()?);
            }
            check(ffi::TSSetType(raw, c"beuler".as_ptr()))?;
            check(ffi::TSSetProblemType(raw, ffi::TSProblemType::TS_NONLINEAR))?;
            check(ffi::TSSetApplicationContext(raw, ctxp))?;
            check(ffi::TSSetIFunction(raw, ts._keep.0.raw, Some(ifunction_tramp::<P>), ctxp))?;
            let pmat = ts._keep.2.as_ref().map_or(ts._keep.1.raw, |m| m.raw);
            check(ffi::TSSetIJacobian(raw, ts._keep.1.raw, pmat, Some(ijacobian_tramp::<P>), ctxp))?;
            check(ffi::TSSetPreStage(raw, Some(prestage_tramp::<P>)))?;
            check(ffi::TSSetPostStep(raw, Some(poststep_tramp::<P>)))?;
            check(ffi::TSMonitorSet(raw, Some(monitor_tramp::<P>), ctxp, None))?;
            let mut snes = std::ptr::null_mut();
            check(ffi::TSGetSNES(raw, &mut snes))?;
            check(ffi::SNESSetComputeInitialGuess(snes, Some(guess_tramp::<P>), ctxp))?;
            check(ffi::TSSetExactFinalTime(raw, ffi::TSExactFinalTimeOption::TS_EXACTFINALTIME_MATCHSTEP))?;
            check(ffi::TSSetMaxSNESFailures(raw, -1))?;
            check(ffi::TSSetErrorIfStepFails(raw, pbool(false)))?;
        }
        ts._dm = dm;
        Ok(ts)
    }

    pub(crate) fn as_ref(&self) -> TsRef {
        TsRef { raw: self.raw }
    }
    pub fn problem(&self) -> &P {
        &self.ctx.problem
    }
    pub(crate) fn problem_mut(&mut self) -> &mut P {
        &mut self.ctx.problem
    }
    /// The problem together with the Jacobian matrix TS assembles into (for diagnostics that
    /// assemble outside a solve).
    pub(crate) fn problem_and_jacobian(&mut self) -> (&mut P, &mut Mat) {
        (&mut self.ctx.problem, &mut self._keep.1)
    }
    pub fn snes(&self) -> Result<Snes> {
        self.as_ref().snes()
    }
    /// Replaces the SNES by `solver` (a SNESSHELL); the TS keeps it alive.
    pub(crate) fn set_nonlinear_solver(&mut self, solver: Box<dyn ShellSolve>) -> Result<()> {
        let snes = self.snes()?;
        let shell = self.shell.insert(Box::new(solver));
        snes.set_shell(shell)
    }
    /// Makes the next nonlinear solve start afresh (see [`ShellSolve::restart`]). PETSc's own
    /// objects keep what they keep (e.g. GAMG's reused interpolation): a run resumed with
    /// them repeats the uninterrupted one only to solver tolerance.
    pub(crate) fn restart_nonlinear_solver(&mut self) {
        if let Some(s) = self.shell.as_mut() {
            s.restart();
        }
    }
    /// The shell nonlinear solver's state between solves (see [`ShellSolve::saved_state`]).
    pub(crate) fn nonlinear_solver_state(&mut self) -> Result<Option<super::SolverState>> {
        match self.shell.as_mut() {
            Some(s) => s.saved_state(),
            None => Ok(None),
        }
    }
    /// Hands the shell nonlinear solver a saved state for its next solve.
    pub(crate) fn restore_nonlinear_solver_state(&mut self, state: super::SolverState) {
        if let Some(s) = self.shell.as_mut() {
            s.restore_state(state);
        }
    }
    /// Newton and Krylov iterations summed over every nonlinear solve so far (failed attempts of
    /// cut steps included).
    pub(crate) fn solver_totals(&self) -> Result<(usize, usize)> {
        if let Some(s) = &self.shell {
            return Ok(s.totals());
        }
        let (mut n, mut k): (Int, Int) = (0, 0);
        check(unsafe { ffi::TSGetSNESIterations(self.raw, &mut n) })?;
        check(unsafe { ffi::TSGetKSPIterations(self.raw, &mut k) })?;
        Ok((n as usize, k as usize))
    }
    /// The vector TS advances in place.
    pub fn set_solution(&mut self, u: &Vector) -> Result<()> {
        check(unsafe { ffi::TSSetSolution(self.raw, u.raw) })
    }
    pub fn set_time(&mut self, t: f64) -> Result<()> {
        check(unsafe { ffi::TSSetTime(self.raw, t) })
    }
    pub fn time(&self) -> Result<f64> {
        self.as_ref().time()
    }
    pub fn set_time_step(&mut self, dt: f64) -> Result<()> {
        check(unsafe { ffi::TSSetTimeStep(self.raw, dt) })
    }
    pub fn set_max_time(&mut self, t: f64) -> Result<()> {
        check(unsafe { ffi::TSSetMaxTime(self.raw, t) })
    }
    /// How many times a failed step may be cut (by TSAdapt's factor, `-ts_adapt_scale_solve_failed`) and retried.
    pub fn set_max_rejections(&mut self, n: usize) -> Result<()> {
        check(unsafe { ffi::TSSetMaxStepRejections(self.raw, n as Int) })
    }
    /// Total rejected (cut) steps so far.
    pub fn rejections(&self) -> Result<usize> {
        let mut n: Int = 0;
        check(unsafe { ffi::TSGetStepRejections(self.raw, &mut n) })?;
        Ok(n as usize)
    }
    pub fn domain_errors(&self) -> (usize, Option<&str>) {
        (self.ctx.domain_errors, self.ctx.last_domain.as_deref())
    }
    pub fn set_from_options(&mut self) -> Result<()> {
        check(unsafe { ffi::TSSetFromOptions(self.raw) })
    }
    /// Type name as PETSc reports it ("beuler", "bdf", ...).
    pub(crate) fn type_name(&self) -> Result<String> {
        let mut t: ffi::TSType = std::ptr::null();
        check(unsafe { ffi::TSGetType(self.raw, &mut t) })?;
        Ok(super::type_name_of(t))
    }
    /// Integrates to the max time with `TSSolve` (calls the post-step and monitor hooks).
    pub fn solve(&mut self, u: &mut Vector) -> Result<()> {
        self.ctx.error = None;
        let code = unsafe { ffi::TSSolve(self.raw, u.raw) };
        if let Some(e) = self.ctx.error.take() {
            let _ = check(code);
            return Err(e);
        }
        check(code)
    }
    /// Number of steps taken.
    pub fn step_number(&self) -> Result<usize> {
        let mut n: Int = 0;
        check(unsafe { ffi::TSGetStepNumber(self.raw, &mut n) })?;
        Ok(n as usize)
    }
    /// Takes one step (with internal cut-and-retry). Errors from callbacks come back unchanged;
    /// a step that still fails after all retries is `Error::Diverged`.
    pub fn step(&mut self) -> Result<()> {
        self.ctx.error = None;
        let code = unsafe { ffi::TSStep(self.raw) };
        if let Some(e) = self.ctx.error.take() {
            let _ = check(code); // clear the recorded PETSc message
            return Err(e);
        }
        check(code)?;
        let mut reason = ffi::TSConvergedReason(0);
        check(unsafe { ffi::TSGetConvergedReason(self.raw, &mut reason) })?;
        if reason.0 < 0 {
            let snes_reason = self.snes().and_then(|s| s.converged_reason()).unwrap_or(0);
            let dom =
                self.ctx.last_domain.as_deref().map(|d| format!("; last inadmissible state: {d}")).unwrap_or_default();
            return Err(Error::Diverged(format!(
                "time step from t = {} failed after all retries (TS reason {}, last SNES reason {}{})",
                self.time()?,
                ts_reason_name(reason.0),
                snes_reason,
                dom
            )));
        }
        Ok(())
    }
    /// Undoes the last accepted step (state and time), e.g. when an error estimate rejects it.
    pub(crate) fn roll_back(&mut self) -> Result<()> {
        check(unsafe { ffi::TSRollBack(self.raw) })
    }
    /// Tells multistep methods (BDF) that the solution's history is not smooth across the
    /// current time (a kink of the loading): the next step starts afresh.
    pub(crate) fn restart_step(&mut self) -> Result<()> {
        check(unsafe { ffi::TSRestartStep(self.raw) })
    }
}

impl<P: TsProblem> super::Object for Ts<P> {
    fn object(&self) -> ffi::PetscObject {
        self.raw as ffi::PetscObject
    }
}

fn ts_reason_name(r: i32) -> &'static str {
    match r {
        -1 => "DIVERGED_NONLINEAR_SOLVE",
        -2 => "DIVERGED_STEP_REJECTED",
        -3 => "FORWARD_DIVERGED_LINEAR_SOLVE",
        -4 => "ADJOINT_DIVERGED_LINEAR_SOLVE",
        _ => "unknown",
    }
}
