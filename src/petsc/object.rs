//! The PETSc object under each wrapper, for `PetscObjectCompose`.

use super::ffi;

/// A live PETSc object owned by one of the wrappers (for compose).
pub(crate) trait Object {
    fn object(&self) -> ffi::PetscObject;
}
