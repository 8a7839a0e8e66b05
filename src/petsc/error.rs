//! PETSc errors: our error handler records PETSc's message where it was raised, [`check`] turns
//! a return code into a `Result` carrying it, and [`raise`] raises one from a Rust callback.

use super::ffi;
use crate::error::{Error, Result};
use std::ffi::{c_char, c_int, CStr, CString};
use std::sync::Mutex;

/// Message of the most recent PETSc error, recorded by our error handler at the point where it
/// was raised, with the call chain appended as the error propagates.
pub(super) static LAST_ERROR: Mutex<String> = Mutex::new(String::new());

pub(super) unsafe extern "C" fn record_error(
    _comm: ffi::MPI_Comm,
    line: c_int,
    func: *const c_char,
    file: *const c_char,
    code: ffi::PetscErrorCode,
    kind: ffi::PetscErrorType,
    mess: *const c_char,
    _ctx: *mut std::ffi::c_void,
) -> ffi::PetscErrorCode {
    let s = |p: *const c_char| {
        if p.is_null() {
            String::new()
        } else {
            CStr::from_ptr(p).to_string_lossy().into_owned()
        }
    };
    if let Ok(mut buf) = LAST_ERROR.lock() {
        if kind == ffi::PetscErrorType::PETSC_ERROR_INITIAL {
            let mut generic: *const c_char = std::ptr::null();
            ffi::PetscErrorMessage(code, &mut generic, std::ptr::null_mut());
            let m = s(mess);
            let g = s(generic);
            *buf = if m.is_empty() {
                g
            } else if g.is_empty() {
                m
            } else {
                format!("{m} [{g}]")
            };
            buf.push_str(&format!(" (in {} at {}:{})", s(func), s(file), line));
        } else {
            buf.push_str(&format!(" <- {}", s(func)));
        }
    }
    code
}

/// Turns a PETSc return code into a `Result`, with PETSc's message for non-zero codes.
pub(crate) fn check(code: ffi::PetscErrorCode) -> Result<()> {
    if code == 0 {
        return Ok(());
    }
    let msg = LAST_ERROR.lock().map(|mut b| std::mem::take(&mut *b)).unwrap_or_default();
    Err(Error::Petsc { code, msg: if msg.is_empty() { format!("error code {code}") } else { msg } })
}

/// Raises a PETSc error from Rust (inside a callback), so PETSc unwinds its own stack and the
/// message reaches the caller of the outermost PETSc function.
pub(crate) fn raise(msg: &str) -> ffi::PetscErrorCode {
    let c = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    unsafe {
        ffi::PetscError(
            mpi::ffi::RSMPI_COMM_SELF,
            0,
            c"poroplast callback".as_ptr(),
            c"rust".as_ptr(),
            ffi::PETSC_ERR_USER as ffi::PetscErrorCode,
            ffi::PetscErrorType::PETSC_ERROR_INITIAL,
            c"%s".as_ptr(),
            c.as_ptr(),
        )
    }
}
