//! `Mat` (parallel AIJ with exact preallocation) and `MatNullSpace` (rigid-body modes) wrappers.

use super::{alive, check, ffi, pbool, Int, Vector};
use crate::error::Result;

/// An owned PETSc matrix.
pub struct Mat {
    pub(crate) raw: ffi::Mat,
}

impl Drop for Mat {
    fn drop(&mut self) {
        if alive() && !self.raw.is_null() {
            unsafe { ffi::MatDestroy(&mut self.raw) };
        }
    }
}

impl Mat {
    /// A square AIJ matrix with `n_local` rows/columns on this rank and exact preallocation:
    /// `d_nnz[i]`/`o_nnz[i]` nonzeros of local row i in the diagonal/off-diagonal block.
    /// Inserting outside the preallocated pattern is an error (it would mean a wrong pattern).
    pub fn aij(comm: ffi::MPI_Comm, n_local: usize, d_nnz: &[Int], o_nnz: &[Int]) -> Result<Mat> {
        let mut raw = std::ptr::null_mut();
        unsafe {
            check(ffi::MatCreate(comm, &mut raw))?;
            let m = Mat { raw };
            check(ffi::MatSetSizes(raw, n_local as Int, n_local as Int, ffi::PETSC_DETERMINE, ffi::PETSC_DETERMINE))?;
            check(ffi::MatSetType(raw, c"aij".as_ptr()))?;
            check(ffi::MatSeqAIJSetPreallocation(raw, 0, d_nnz.as_ptr()))?;
            check(ffi::MatMPIAIJSetPreallocation(raw, 0, d_nnz.as_ptr(), 0, o_nnz.as_ptr()))?;
            check(ffi::MatSetOption(raw, ffi::MatOption::MAT_NEW_NONZERO_ALLOCATION_ERR, pbool(true)))?;
            Ok(m)
        }
    }

    /// Borrows a matrix PETSc hands to a callback.
    ///
    /// # Safety
    /// `raw` must be valid for the lifetime of the returned value.
    pub unsafe fn borrowed(raw: ffi::Mat) -> std::mem::ManuallyDrop<Mat> {
        std::mem::ManuallyDrop::new(Mat { raw })
    }

    pub fn as_raw(&self) -> ffi::Mat {
        self.raw
    }

    /// Another owning handle to the same matrix (PETSc reference counting).
    pub fn clone_ref(&self) -> Result<Mat> {
        check(unsafe { ffi::PetscObjectReference(self.raw as ffi::PetscObject) })?;
        Ok(Mat { raw: self.raw })
    }

    /// Adds a dense block `vals` (row-major, rows.len() × cols.len()) at global indices.
    /// Negative indices are skipped by PETSc.
    pub fn add_values(&mut self, rows: &[Int], cols: &[Int], vals: &[f64]) -> Result<()> {
        debug_assert_eq!(vals.len(), rows.len() * cols.len());
        check(unsafe {
            ffi::MatSetValues(self.raw, rows.len() as Int, rows.as_ptr(), cols.len() as Int, cols.as_ptr(), vals.as_ptr(), ffi::InsertMode::ADD_VALUES)
        })
    }

    pub fn zero_entries(&mut self) -> Result<()> {
        check(unsafe { ffi::MatZeroEntries(self.raw) })
    }

    /// Final assembly (communicates off-rank contributions).
    pub fn assemble(&mut self) -> Result<()> {
        unsafe {
            check(ffi::MatAssemblyBegin(self.raw, ffi::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
            check(ffi::MatAssemblyEnd(self.raw, ffi::MatAssemblyType::MAT_FINAL_ASSEMBLY))
        }
    }

    /// y = A x
    pub fn mult(&self, x: &Vector, y: &mut Vector) -> Result<()> {
        check(unsafe { ffi::MatMult(self.raw, x.raw, y.raw) })
    }

    pub fn set_near_null_space(&mut self, ns: &NullSpace) -> Result<()> {
        check(unsafe { ffi::MatSetNearNullSpace(self.raw, ns.raw) })
    }

    /// Vectors compatible with the matrix layout (right, left).
    pub fn create_vecs(&self) -> Result<(Vector, Vector)> {
        let (mut r, mut l) = (std::ptr::null_mut(), std::ptr::null_mut());
        check(unsafe { ffi::MatCreateVecs(self.raw, &mut r, &mut l) })?;
        Ok((Vector { raw: r }, Vector { raw: l }))
    }

    /// Global number of stored nonzeros (for logs and memory estimates).
    pub fn nonzeros(&self) -> Result<f64> {
        let mut info = std::mem::MaybeUninit::<ffi::MatInfo>::zeroed();
        check(unsafe { ffi::MatGetInfo(self.raw, ffi::MatInfoType::MAT_GLOBAL_SUM, info.as_mut_ptr()) })?;
        Ok(unsafe { info.assume_init() }.nz_used)
    }

    /// Names the matrix.
    pub fn set_name(&mut self, name: &str) -> Result<()> {
        let c = super::cstr(name);
        check(unsafe { ffi::PetscObjectSetName(self.raw as ffi::PetscObject, c.as_ptr()) })
    }
}

/// A (near) null space: here the six rigid-body modes of 3-D elasticity.
pub struct NullSpace {
    pub(crate) raw: ffi::MatNullSpace,
}

impl Drop for NullSpace {
    fn drop(&mut self) {
        if alive() && !self.raw.is_null() {
            unsafe { ffi::MatNullSpaceDestroy(&mut self.raw) };
        }
    }
}

impl NullSpace {
    /// Rigid-body modes from nodal coordinates (`coords` has block size 3, one block per node).
    pub fn rigid_body(coords: &Vector) -> Result<NullSpace> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::MatNullSpaceCreateRigidBody(coords.raw, &mut raw) })?;
        Ok(NullSpace { raw })
    }

    pub fn as_object(&self) -> ffi::PetscObject {
        self.raw as ffi::PetscObject
    }
}
