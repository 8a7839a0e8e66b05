//! `IS` (index set) wrapper: the u and p field index sets for PCFIELDSPLIT.

use super::{check, ffi, Int};
use crate::error::Result;

/// An owned index set.
pub(crate) struct IndexSet {
    pub(crate) raw: ffi::IS,
}

destroy_on_drop!(IndexSet, ISDestroy);

impl IndexSet {
    /// An index set holding a copy of `idx`.
    pub(crate) fn general(comm: ffi::MPI_Comm, idx: &[Int]) -> Result<IndexSet> {
        let mut raw = std::ptr::null_mut();
        check(unsafe {
            ffi::ISCreateGeneral(comm, idx.len() as Int, idx.as_ptr(), ffi::PetscCopyMode::PETSC_COPY_VALUES, &mut raw)
        })?;
        Ok(IndexSet { raw })
    }

    /// first, first+step, ... (n entries on this rank).
    pub(crate) fn stride(comm: ffi::MPI_Comm, n: usize, first: usize, step: usize) -> Result<IndexSet> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::ISCreateStride(comm, n as Int, first as Int, step as Int, &mut raw) })?;
        Ok(IndexSet { raw })
    }

    /// A fresh copy of `other` (same indices and layout).
    pub(crate) fn stride_like(other: &IndexSet) -> Result<IndexSet> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::ISDuplicate(other.raw, &mut raw) })?;
        Ok(IndexSet { raw })
    }

    /// Wraps an IS PETSc returns with a new reference we own.
    ///
    /// # Safety
    /// `raw` must be a valid IS whose reference count we are allowed to increment.
    pub(crate) unsafe fn from_raw_ref(raw: ffi::IS) -> Result<IndexSet> {
        check(ffi::PetscObjectReference(raw as ffi::PetscObject))?;
        Ok(IndexSet { raw })
    }

    /// Hands our reference to PETSc (e.g. as the output of a DM callback).
    pub(crate) fn into_raw(self) -> ffi::IS {
        let r = self.raw;
        std::mem::forget(self);
        r
    }

    pub(crate) fn set_block_size(&mut self, bs: usize) -> Result<()> {
        check(unsafe { ffi::ISSetBlockSize(self.raw, bs as Int) })
    }

    pub(crate) fn local_size(&self) -> usize {
        let mut n: Int = 0;
        unsafe { ffi::ISGetLocalSize(self.raw, &mut n) };
        n as usize
    }

    /// The local indices, copied.
    pub(crate) fn indices(&self) -> Result<Vec<Int>> {
        let mut p: *const Int = std::ptr::null();
        unsafe {
            check(ffi::ISGetIndices(self.raw, &mut p))?;
            let v = std::slice::from_raw_parts(p, self.local_size()).to_vec();
            check(ffi::ISRestoreIndices(self.raw, &mut p))?;
            Ok(v)
        }
    }

    /// Attaches `obj` under `key` (fieldsplit looks up "nearnullspace" and "pmat" on its ISes).
    pub(crate) fn compose(&mut self, key: &str, obj: &impl super::Object) -> Result<()> {
        let k = super::cstr(key);
        check(unsafe { ffi::PetscObjectCompose(self.raw as ffi::PetscObject, k.as_ptr(), obj.object()) })
    }
}
