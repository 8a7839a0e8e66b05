//! The PETSc init token: initialises PETSc (again, after an earlier finalisation) and finalises
//! it when dropped.

use super::error::{record_error, LAST_ERROR};
use super::{alive, check, ffi, options, reinit};
use crate::error::{Error, Result};
use mpi::topology::SimpleCommunicator;
use mpi::traits::AsRaw;
use std::ffi::{c_char, c_int, CString};

/// The PETSc init token. Create it after MPI (rsmpi) is initialised; drop it before MPI.
pub struct Petsc {
    _private: (),
}

impl Petsc {
    /// Initialises PETSc on `comm` (its `PETSC_COMM_WORLD`: the ranks that take part in
    /// PETSc's collective start and end) with the given command-line style options (e.g.
    /// `["-log_view", "-ksp_monitor"]`), so init-time options such as `-log_view` work.
    ///
    /// PETSc may be initialised again after it was finalised (while MPI lives): each
    /// initialisation starts from an empty options database, so a sweep's cases, each run
    /// between its own `init` and drop, see only their own options. Our own records of the
    /// options (the defaults we set) and of the last error start empty too.
    pub fn init(comm: &SimpleCommunicator, options: &[String]) -> Result<Petsc> {
        if alive() {
            return Err(Error::Internal("PETSc is already initialised in this process".into()));
        }
        options::DEFAULTS.lock().unwrap_or_else(|e| e.into_inner()).clear();
        LAST_ERROR.lock().unwrap_or_else(|e| e.into_inner()).clear();
        let again = INITIALISED_BEFORE.swap(true, std::sync::atomic::Ordering::Relaxed);
        if again {
            reinit::before();
        }
        let mut args: Vec<CString> = std::iter::once("poroplast".to_string())
            .chain(options.iter().cloned())
            .map(|s| CString::new(s).map_err(|_| Error::Options("PETSc option contains a NUL byte".into())))
            .collect::<Result<_>>()?;
        // PETSc keeps pointers into argv for the whole run: leak the strings deliberately.
        let mut ptrs: Vec<*mut c_char> = args.iter_mut().map(|s| s.as_ptr() as *mut c_char).collect();
        ptrs.push(std::ptr::null_mut());
        let mut argc = (ptrs.len() - 1) as c_int;
        let mut argv = ptrs.as_mut_ptr();
        std::mem::forget(args);
        std::mem::forget(ptrs);
        unsafe {
            ffi::PETSC_COMM_WORLD = comm.as_raw();
            check(ffi::PetscInitialize(&mut argc, &mut argv, std::ptr::null(), std::ptr::null()))?;
            check(ffi::PetscPushErrorHandler(Some(record_error), std::ptr::null_mut()))?;
        }
        let petsc = Petsc { _private: () };
        if again {
            reinit::after()?;
        }
        Ok(petsc)
    }

    /// The communicator all objects live on.
    pub fn comm(&self) -> ffi::MPI_Comm {
        unsafe { ffi::PETSC_COMM_WORLD }
    }
}

/// PETSc has been initialised in this process before (and finalised since).
static INITIALISED_BEFORE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

impl Drop for Petsc {
    fn drop(&mut self) {
        if alive() {
            unsafe {
                ffi::PetscPopErrorHandler();
                ffi::PetscFinalize();
            }
        }
    }
}
