//! PETSc's allocator: arrays handed to PETSc, which frees them, and the freeing of arrays PETSc
//! allocated.

use super::{check, ffi};
use crate::error::Result;
use std::ffi::c_int;

/// `PetscMalloc` for arrays PETSc will free itself (outputs of DM callbacks).
pub(crate) unsafe fn petsc_malloc<T>(n: usize) -> Result<*mut T> {
    let mut p: *mut T = std::ptr::null_mut();
    check(ffi::PetscMallocA(
        1,
        ffi::PetscBool::PETSC_FALSE,
        line!() as c_int,
        c"petsc_malloc".as_ptr(),
        c"rust".as_ptr(),
        n.max(1) * std::mem::size_of::<T>(),
        &mut p as *mut *mut T as *mut std::ffi::c_void,
    ))?;
    Ok(p)
}

/// `PetscFree`.
pub(crate) unsafe fn petsc_free<T>(mut p: *mut T) -> Result<()> {
    // Like PetscMallocA, PetscFreeA takes the address of the pointer (and nulls it).
    check(ffi::PetscFreeA(
        1,
        line!() as c_int,
        c"petsc_free".as_ptr(),
        c"rust".as_ptr(),
        &mut p as *mut *mut T as *mut std::ffi::c_void,
    ))
}
