//! `PetscViewer` wrapper (ASCII to stdout or a file), for `-ksp_view`-like dumps from code.

use super::{alive, check, cstr, ffi};
use crate::error::Result;

/// An owned viewer.
pub struct Viewer {
    raw: ffi::PetscViewer,
    owned: bool,
}

impl Drop for Viewer {
    fn drop(&mut self) {
        if self.owned && alive() && !self.raw.is_null() {
            unsafe { ffi::PetscViewerDestroy(&mut self.raw) };
        }
    }
}

impl Viewer {
    /// An ASCII viewer writing to `path` (collective).
    pub fn ascii_file(comm: ffi::MPI_Comm, path: &str) -> Result<Viewer> {
        let mut raw = std::ptr::null_mut();
        let c = cstr(path);
        check(unsafe { ffi::PetscViewerASCIIOpen(comm, c.as_ptr(), &mut raw) })?;
        Ok(Viewer { raw, owned: true })
    }
    /// Standard output of the communicator (rank 0 prints).
    pub fn stdout(comm: ffi::MPI_Comm) -> Result<Viewer> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::PetscViewerASCIIGetStdout(comm, &mut raw) })?;
        Ok(Viewer { raw, owned: false })
    }
    /// Views any PETSc object (KSP, SNES, TS, Mat, Vec ...).
    pub fn view(&self, obj: &impl super::Object) -> Result<()> {
        check(unsafe { ffi::PetscObjectView(obj.object(), self.raw) })
    }
}
