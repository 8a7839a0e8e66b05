//! Whether PETSc is alive, and the `Drop` of every wrapper, which destroys its PETSc object only
//! then (see the module docs of `petsc`).

use super::ffi;

/// True between PetscInitialize and PetscFinalize: wrappers only destroy objects then.
pub(crate) fn alive() -> bool {
    unsafe {
        ffi::PetscInitializeCalled == ffi::PetscBool::PETSC_TRUE
            && ffi::PetscFinalizeCalled != ffi::PetscBool::PETSC_TRUE
    }
}

/// Destroys the wrapped PETSc object on drop, while PETSc is alive (see the module docs).
macro_rules! destroy_on_drop {
    ($ty:ty, $destroy:ident) => {
        impl Drop for $ty {
            fn drop(&mut self) {
                if super::alive() && !self.raw.is_null() {
                    unsafe { super::ffi::$destroy(&mut self.raw) };
                }
            }
        }
    };
}
