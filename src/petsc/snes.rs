//! `SNES` handle (the TS's nonlinear solver): iteration counts, VI bounds, domain errors, and
//! a Rust nonlinear solver run as a SNESSHELL ([`ShellSolve`]).

use super::{check, ffi, raise, Int, Ksp, Mat, Vector};
use crate::error::Result;
use std::ffi::c_void;
use std::mem::ManuallyDrop;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// A nonlinear solver written in Rust, run by a SNESSHELL inside TS: it evaluates the residual
/// and Jacobian through the SNES ([`Snes::compute_function`], [`Snes::compute_jacobian`]) and
/// reports through [`Snes::set_converged_reason`] and [`Snes::set_iteration_number`].
pub(crate) trait ShellSolve {
    /// Solves F(x) = 0 from the initial guess in `x`.
    fn solve(&mut self, snes: Snes, x: &mut Vector) -> Result<()>;
    /// Newton and Krylov iterations summed over every solve so far (failed ones included).
    fn totals(&self) -> (usize, usize);
    /// Forgets what one solve hands the next (a reused operator or preconditioner), so that
    /// the next solve starts as after a restart from a checkpoint.
    fn restart(&mut self) {}
    /// What one solve hands the next, for a checkpoint on this rank (None: nothing, or nothing
    /// that can be saved; then [`restart`](Self::restart) makes runs with and without a restart
    /// agree).
    fn saved_state(&mut self) -> Result<Option<SolverState>> {
        Ok(None)
    }
    /// Hands the next solve a state of [`saved_state`](Self::saved_state) (same rank count).
    fn restore_state(&mut self, _state: SolverState) {}
}

/// A nonlinear solver's state between solves on one rank: the local values of a kept operator,
/// a set of global indices (e.g. an active set), and counters.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SolverState {
    pub(crate) values: Vec<f64>,
    pub(crate) indices: Vec<Int>,
    pub(crate) counters: Vec<u64>,
}

impl SolverState {
    /// Little-endian bytes: three length-prefixed arrays.
    pub(crate) fn to_bytes(&self) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend((self.values.len() as u64).to_le_bytes());
        self.values.iter().for_each(|v| b.extend(v.to_le_bytes()));
        b.extend((self.indices.len() as u64).to_le_bytes());
        self.indices.iter().for_each(|v| b.extend((*v as i64).to_le_bytes()));
        b.extend((self.counters.len() as u64).to_le_bytes());
        self.counters.iter().for_each(|v| b.extend(v.to_le_bytes()));
        b
    }

    /// The inverse of [`to_bytes`](Self::to_bytes); None for anything else.
    pub(crate) fn from_bytes(b: &[u8]) -> Option<SolverState> {
        let mut at = 0;
        // Every array length is checked against the file's (a damaged file cannot make a huge
        // allocation).
        let fits = |n: u64| (n as usize).checked_mul(8).is_some_and(|bytes| bytes <= b.len());
        let mut word = || -> Option<[u8; 8]> {
            let w = b.get(at..at + 8)?.try_into().ok()?;
            at += 8;
            Some(w)
        };
        let n = u64::from_le_bytes(word()?);
        if !fits(n) {
            return None;
        }
        let mut values = vec![0.0; n as usize];
        for v in values.iter_mut() {
            *v = f64::from_le_bytes(word()?);
        }
        let n = u64::from_le_bytes(word()?);
        if !fits(n) {
            return None;
        }
        let mut indices = vec![0 as Int; n as usize];
        for v in indices.iter_mut() {
            *v = i64::from_le_bytes(word()?) as Int;
        }
        let n = u64::from_le_bytes(word()?);
        if !fits(n) {
            return None;
        }
        let mut counters = vec![0u64; n as usize];
        for v in counters.iter_mut() {
            *v = u64::from_le_bytes(word()?);
        }
        (at == b.len()).then_some(SolverState { values, indices, counters })
    }
}

/// The solver behind a SNESSHELL's context (a thin pointer to the boxed trait object).
pub(crate) type ShellBox = Box<dyn ShellSolve>;

pub(crate) unsafe extern "C" fn shell_solve_tramp(snes: ffi::SNES, x: ffi::Vec) -> ffi::PetscErrorCode {
    let mut ctx: *mut c_void = std::ptr::null_mut();
    if ffi::SNESShellGetContext(snes, &mut ctx as *mut *mut c_void as *mut c_void) != 0 || ctx.is_null() {
        return raise("SNESSHELL without a solver context");
    }
    let solver = &mut *(ctx as *mut ShellBox);
    let mut x = Vector::borrowed(x);
    match catch_unwind(AssertUnwindSafe(|| solver.solve(Snes { raw: snes }, &mut x))) {
        Ok(Ok(())) => 0,
        Ok(Err(e)) => raise(&e.to_string()),
        Err(_) => raise("internal error (panic) in the nonlinear solver"),
    }
}

/// A nonlinear solver owned by a TS.
#[derive(Clone, Copy)]
pub struct Snes {
    pub(crate) raw: ffi::SNES,
}

impl Snes {
    pub fn ksp(&self) -> Result<Ksp> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::SNESGetKSP(self.raw, &mut raw) })?;
        Ok(Ksp { raw })
    }
    /// Gives `ksp` this SNES's DM for PC information only (field decomposition), not for its
    /// operators.
    pub(crate) fn lend_dm_to(&self, ksp: &Ksp) -> Result<()> {
        let mut dm: ffi::DM = std::ptr::null_mut();
        check(unsafe { ffi::SNESGetDM(self.raw, &mut dm) })?;
        check(unsafe { ffi::KSPSetDM(ksp.raw, dm) })?;
        check(unsafe { ffi::KSPSetDMActive(ksp.raw, super::pbool(false)) })
    }
    pub(crate) fn set_type(&self, t: &str) -> Result<()> {
        let c = super::cstr(t);
        check(unsafe { ffi::SNESSetType(self.raw, c.as_ptr()) })
    }
    /// Whether the solver is a variational-inequality (bounded) Newton method.
    pub(crate) fn is_vi(&self) -> Result<bool> {
        let mut t: ffi::SNESType = std::ptr::null();
        check(unsafe { ffi::SNESGetType(self.raw, &mut t) })?;
        Ok(!t.is_null() && unsafe { std::ffi::CStr::from_ptr(t) }.to_bytes().starts_with(b"vi"))
    }
    /// Converged reason code (> 0 converged, < 0 diverged).
    pub(crate) fn converged_reason(&self) -> Result<i32> {
        let mut r = ffi::SNESConvergedReason(0);
        check(unsafe { ffi::SNESGetConvergedReason(self.raw, &mut r) })?;
        Ok(r.0)
    }
    /// Lower and upper bounds for a VI solve. SNES keeps references: update the vectors in place.
    pub(crate) fn set_vi_bounds(&self, lower: &Vector, upper: &Vector) -> Result<()> {
        check(unsafe { ffi::SNESVISetVariableBounds(self.raw, lower.raw, upper.raw) })
    }
    /// The inactive (free) set of the current VI iterate, if the VI solver has one yet.
    pub(crate) fn vi_inactive_set(&self) -> Result<Option<super::IndexSet>> {
        let mut is: ffi::IS = std::ptr::null_mut();
        check(unsafe { ffi::SNESVIGetInactiveSet(self.raw, &mut is) })?;
        if is.is_null() {
            return Ok(None);
        }
        // SAFETY: a valid IS owned by SNESVI; we take our own reference.
        Ok(Some(unsafe { super::IndexSet::from_raw_ref(is)? }))
    }
    /// Tells SNES the last function evaluation left the admissible domain (J <= Φs ...):
    /// the solve fails softly and TS retries with a smaller step.
    pub(crate) fn set_function_domain_error(&self) -> Result<()> {
        check(unsafe { ffi::SNESSetFunctionDomainError(self.raw) })
    }
    /// F(x) into `f` through the SNES (for TS: the IFunction at the stage). A domain error in
    /// the residual makes `f` infinite on every rank.
    pub(crate) fn compute_function(&self, x: &Vector, f: &mut Vector) -> Result<()> {
        check(unsafe { ffi::SNESComputeFunction(self.raw, x.raw, f.raw) })
    }
    /// Assembles the Jacobian at x into the SNES's matrices and returns them (operator,
    /// preconditioning matrix; possibly the same object).
    pub(crate) fn compute_jacobian(&self, x: &Vector) -> Result<(ManuallyDrop<Mat>, ManuallyDrop<Mat>)> {
        let (mut a, mut p) = (std::ptr::null_mut(), std::ptr::null_mut());
        check(unsafe { ffi::SNESGetJacobian(self.raw, &mut a, &mut p, std::ptr::null_mut(), std::ptr::null_mut()) })?;
        check(unsafe { ffi::SNESComputeJacobian(self.raw, x.raw, a, p) })?;
        Ok(unsafe { (Mat::borrowed(a), Mat::borrowed(p)) })
    }
    /// (atol, rtol, stol, max_it) as set by options.
    pub(crate) fn tolerances(&self) -> Result<(f64, f64, f64, usize)> {
        let (mut atol, mut rtol, mut stol, mut maxit, mut maxf) = (0.0, 0.0, 0.0, 0 as Int, 0 as Int);
        check(unsafe { ffi::SNESGetTolerances(self.raw, &mut atol, &mut rtol, &mut stol, &mut maxit, &mut maxf) })?;
        Ok((atol, rtol, stol, maxit.max(0) as usize))
    }
    pub(crate) fn set_converged_reason(&self, reason: ffi::SNESConvergedReason) -> Result<()> {
        check(unsafe { ffi::SNESSetConvergedReason(self.raw, reason) })
    }
    /// Runs the monitors set by options (`-snes_monitor` ...) for iteration `it`.
    pub(crate) fn monitor(&self, it: usize, fnorm: f64) -> Result<()> {
        check(unsafe { ffi::SNESMonitor(self.raw, it as Int, fnorm) })
    }
    pub(crate) fn set_iteration_number(&self, n: usize) -> Result<()> {
        check(unsafe { ffi::SNESSetIterationNumber(self.raw, n as Int) })
    }
    /// Makes this a SNESSHELL running `solver` (kept alive by the caller at a stable address).
    pub(crate) fn set_shell(&self, solver: &mut ShellBox) -> Result<()> {
        self.set_type("shell")?;
        check(unsafe { ffi::SNESShellSetContext(self.raw, solver as *mut ShellBox as *mut c_void) })?;
        check(unsafe { ffi::SNESShellSetSolve(self.raw, Some(shell_solve_tramp)) })
    }
    fn line_search(&self) -> Result<ffi::SNESLineSearch> {
        let mut ls: ffi::SNESLineSearch = std::ptr::null_mut();
        check(unsafe { ffi::SNESGetLineSearch(self.raw, &mut ls) })?;
        Ok(ls)
    }
    /// The line search type of the Newton iteration ("basic", "bt", ...).
    pub(crate) fn line_search_type(&self) -> Result<String> {
        let mut t: ffi::SNESLineSearchType = std::ptr::null();
        check(unsafe { ffi::SNESLineSearchGetType(self.line_search()?, &mut t) })?;
        Ok(super::type_name_of(t))
    }
}

#[cfg(test)]
mod tests {
    use super::SolverState;

    #[test]
    fn solver_state_round_trips_and_rejects_damaged_bytes() {
        let s = SolverState { values: vec![1.5, -2.0, 3.25], indices: vec![7, 11], counters: vec![4, 9] };
        let b = s.to_bytes();
        assert_eq!(SolverState::from_bytes(&b), Some(s));
        assert_eq!(SolverState::from_bytes(&b[..b.len() - 1]), None, "truncated");
        let mut huge = b.clone();
        huge[..8].copy_from_slice(&u64::MAX.to_le_bytes());
        assert_eq!(SolverState::from_bytes(&huge), None, "a length beyond the file");
        assert_eq!(SolverState::from_bytes(&[b, vec![0]].concat()), None, "trailing bytes");
    }
}
