//! `SNES` handle (the TS's nonlinear solver): iteration counts, VI bounds, domain errors.

use super::{check, ffi, Int, Ksp, Vector};
use crate::error::Result;

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
    pub fn set_type(&self, t: &str) -> Result<()> {
        let c = super::cstr(t);
        check(unsafe { ffi::SNESSetType(self.raw, c.as_ptr()) })
    }
    /// Whether the solver is a variational-inequality (bounded) Newton method.
    pub fn is_vi(&self) -> Result<bool> {
        let mut t: ffi::SNESType = std::ptr::null();
        check(unsafe { ffi::SNESGetType(self.raw, &mut t) })?;
        Ok(!t.is_null() && unsafe { std::ffi::CStr::from_ptr(t) }.to_bytes().starts_with(b"vi"))
    }
    /// Newton iterations of the last solve.
    pub fn iterations(&self) -> Result<usize> {
        let mut n: Int = 0;
        check(unsafe { ffi::SNESGetIterationNumber(self.raw, &mut n) })?;
        Ok(n as usize)
    }
    /// Krylov iterations summed over the last solve.
    pub fn linear_iterations(&self) -> Result<usize> {
        let mut n: Int = 0;
        check(unsafe { ffi::SNESGetLinearSolveIterations(self.raw, &mut n) })?;
        Ok(n as usize)
    }
    /// Converged reason code (> 0 converged, < 0 diverged).
    pub fn converged_reason(&self) -> Result<i32> {
        let mut r = ffi::SNESConvergedReason(0);
        check(unsafe { ffi::SNESGetConvergedReason(self.raw, &mut r) })?;
        Ok(r.0)
    }
    /// Lower and upper bounds for a VI solve. SNES keeps references: update the vectors in place.
    pub fn set_vi_bounds(&self, lower: &Vector, upper: &Vector) -> Result<()> {
        check(unsafe { ffi::SNESVISetVariableBounds(self.raw, lower.raw, upper.raw) })
    }
    /// The inactive (free) set of the current VI iterate, if the VI solver has one yet.
    pub fn vi_inactive_set(&self) -> Result<Option<ffi::IS>> {
        let mut is: ffi::IS = std::ptr::null_mut();
        check(unsafe { ffi::SNESVIGetInactiveSet(self.raw, &mut is) })?;
        Ok((!is.is_null()).then_some(is))
    }
    /// Tells SNES the last function evaluation left the admissible domain (J <= Φs ...):
    /// the solve fails softly and TS retries with a smaller step.
    pub fn set_function_domain_error(&self) -> Result<()> {
        check(unsafe { ffi::SNESSetFunctionDomainError(self.raw) })
    }
    pub fn set_jacobian_domain_error(&self) -> Result<()> {
        check(unsafe { ffi::SNESSetJacobianDomainError(self.raw) })
    }
    pub fn set_tolerances(&self, atol: f64, rtol: f64, stol: f64, max_it: usize) -> Result<()> {
        check(unsafe { ffi::SNESSetTolerances(self.raw, atol, rtol, stol, max_it as Int, ffi::PETSC_DEFAULT) })
    }
    fn line_search(&self) -> Result<ffi::SNESLineSearch> {
        let mut ls: ffi::SNESLineSearch = std::ptr::null_mut();
        check(unsafe { ffi::SNESGetLineSearch(self.raw, &mut ls) })?;
        Ok(ls)
    }
    /// The line search type of the Newton iteration ("basic", "bt", ...).
    pub fn line_search_type(&self) -> Result<String> {
        let mut t: ffi::SNESLineSearchType = std::ptr::null();
        check(unsafe { ffi::SNESLineSearchGetType(self.line_search()?, &mut t) })?;
        Ok(if t.is_null() {
            String::new()
        } else {
            unsafe { std::ffi::CStr::from_ptr(t) }.to_string_lossy().into_owned()
        })
    }
    pub fn set_line_search_type(&self, t: &str) -> Result<()> {
        let c = super::cstr(t);
        check(unsafe { ffi::SNESLineSearchSetType(self.line_search()?, c.as_ptr()) })
    }
    pub fn set_from_options(&self) -> Result<()> {
        check(unsafe { ffi::SNESSetFromOptions(self.raw) })
    }
}
