//! `DMShell` whose only job is to hand PCFIELDSPLIT the u/p index sets through a callback.
//!
//! Why a DM: in PETSc 3.18 the index sets given with `PCFieldSplitSetIS` are freed when SNESVI
//! (vinewtonrsls) resets the KSP after the active set changes, and fieldsplit then fails. A DM
//! field decomposition is asked again after every reset, so the callback can return the sets
//! restricted to the current inactive set (checked against PETSc 3.18's `src/snes/impls/vi/rs/virs.c`).

use super::{check, ffi, petsc_malloc, IndexSet, Int, Snes, Vector};
use crate::error::Result;
use std::ffi::{c_char, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Supplies named fields (index sets into the vector of the system being solved). `snes` is the
/// solver asking, so a VI solver's inactive set can be queried.
pub(crate) trait FieldDecomposition {
    fn fields(&mut self, snes: Option<Snes>) -> Result<Vec<(String, IndexSet)>>;
}

struct Ctx {
    fields: Box<dyn FieldDecomposition>,
    snes: Option<Snes>,
}

/// An owned DMShell carrying a field decomposition.
pub struct DmShell {
    pub(crate) raw: ffi::DM,
    ctx: Box<Ctx>,
}

destroy_on_drop!(DmShell, DMDestroy);

unsafe extern "C" fn decomposition_tramp(
    dm: ffi::DM,
    n: *mut Int,
    names: *mut *mut *mut c_char,
    is: *mut *mut ffi::IS,
    dms: *mut *mut ffi::DM,
) -> ffi::PetscErrorCode {
    let mut ctx: *mut c_void = std::ptr::null_mut();
    if ffi::DMShellGetContext(dm, &mut ctx as *mut *mut c_void as *mut c_void) != 0 || ctx.is_null() {
        return super::raise("DMShell without context");
    }
    let ctx = &mut *(ctx as *mut Ctx);
    let r = catch_unwind(AssertUnwindSafe(|| -> Result<()> {
        let fields = ctx.fields.fields(ctx.snes)?;
        let k = fields.len();
        if !n.is_null() {
            *n = k as Int;
        }
        if !dms.is_null() {
            *dms = std::ptr::null_mut();
        }
        let name_arr: *mut *mut c_char = petsc_malloc(k)?;
        let is_arr: *mut ffi::IS = petsc_malloc(k)?;
        for (i, (name, set)) in fields.into_iter().enumerate() {
            let c = super::cstr(&name);
            let mut dst: *mut c_char = std::ptr::null_mut();
            check(ffi::PetscStrallocpy(c.as_ptr(), &mut dst))?;
            *name_arr.add(i) = dst;
            *is_arr.add(i) = set.into_raw();
        }
        // PETSc frees whatever the caller did not ask for.
        if names.is_null() {
            for i in 0..k {
                super::petsc_free(*name_arr.add(i))?;
            }
            super::petsc_free(name_arr)?;
        } else {
            *names = name_arr;
        }
        if is.is_null() {
            for i in 0..k {
                ffi::ISDestroy(is_arr.add(i));
            }
            super::petsc_free(is_arr)?;
        } else {
            *is = is_arr;
        }
        Ok(())
    }));
    match r {
        Ok(Ok(())) => 0,
        Ok(Err(e)) => super::raise(&e.to_string()),
        Err(_) => super::raise("panic in field decomposition"),
    }
}

impl DmShell {
    /// A shell DM whose global vectors look like `global`, with the given field decomposition.
    pub(crate) fn new(comm: ffi::MPI_Comm, global: &Vector, fields: Box<dyn FieldDecomposition>) -> Result<DmShell> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::DMShellCreate(comm, &mut raw) })?;
        let mut dm = DmShell { raw, ctx: Box::new(Ctx { fields, snes: None }) };
        unsafe {
            check(ffi::DMShellSetGlobalVector(raw, global.raw))?;
            check(ffi::DMShellSetContext(raw, &mut *dm.ctx as *mut Ctx as *mut c_void))?;
            check(ffi::DMShellSetCreateFieldDecomposition(raw, Some(decomposition_tramp)))?;
        }
        Ok(dm)
    }

    /// Tells the callback which SNES is asking (set once the TS/SNES exists).
    pub(crate) fn set_snes(&mut self, snes: Snes) {
        self.ctx.snes = Some(snes);
    }
}
