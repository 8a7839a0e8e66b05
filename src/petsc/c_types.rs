//! PETSc's integer type, and the conversions of Rust strings and booleans to and from C.

use super::ffi;
use std::ffi::{c_char, CStr, CString};

/// PETSc's integer type (32-bit in the Debian build).
pub type Int = ffi::PetscInt;

/// A PETSc type name (a C string that may be NULL before a type is set) as a String.
pub(crate) fn type_name_of(t: *const c_char) -> String {
    if t.is_null() {
        String::new()
    } else {
        unsafe { CStr::from_ptr(t) }.to_string_lossy().into_owned()
    }
}

pub(crate) fn cstr(s: &str) -> CString {
    CString::new(s).unwrap_or_default()
}

pub(crate) fn pbool(b: bool) -> ffi::PetscBool {
    if b {
        ffi::PetscBool::PETSC_TRUE
    } else {
        ffi::PetscBool::PETSC_FALSE
    }
}
