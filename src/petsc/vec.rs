//! `Vec` (distributed vectors) and `VecScatter` (ghost exchange) wrappers.

use super::{check, ffi, IndexSet, Int};
use crate::error::Result;
use std::mem::ManuallyDrop;

/// An owned PETSc vector.
pub struct Vector {
    pub(crate) raw: ffi::Vec,
}

destroy_on_drop!(Vector, VecDestroy);

impl Vector {
    /// A distributed vector with `n_local` entries on this rank.
    pub fn mpi(comm: ffi::MPI_Comm, n_local: usize) -> Result<Vector> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::VecCreateMPI(comm, n_local as Int, ffi::PETSC_DETERMINE, &mut raw) })?;
        Ok(Vector { raw })
    }

    /// A sequential (rank-local) vector.
    pub(crate) fn seq(n: usize) -> Result<Vector> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::VecCreateSeq(mpi::ffi::RSMPI_COMM_SELF, n as Int, &mut raw) })?;
        Ok(Vector { raw })
    }

    /// Borrows a vector PETSc hands to a callback, without taking ownership.
    ///
    /// # Safety
    /// `raw` must be a valid Vec for the lifetime of the returned value.
    pub(crate) unsafe fn borrowed(raw: ffi::Vec) -> ManuallyDrop<Vector> {
        ManuallyDrop::new(Vector { raw })
    }

    /// Another owning handle to the same vector (PETSc reference counting): both see the same
    /// values.
    pub(crate) fn clone_ref(&self) -> Result<Vector> {
        check(unsafe { ffi::PetscObjectReference(self.raw as ffi::PetscObject) })?;
        Ok(Vector { raw: self.raw })
    }

    /// A new vector with the same layout (values not copied).
    pub fn duplicate(&self) -> Result<Vector> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::VecDuplicate(self.raw, &mut raw) })?;
        Ok(Vector { raw })
    }

    /// A new vector with the same layout and values.
    pub(crate) fn copy(&self) -> Result<Vector> {
        let mut v = self.duplicate()?;
        v.copy_from(self)?;
        Ok(v)
    }

    /// The communicator the vector lives on.
    pub(crate) fn comm(&self) -> Result<ffi::MPI_Comm> {
        let mut comm: ffi::MPI_Comm = unsafe { std::mem::zeroed() };
        check(unsafe { ffi::PetscObjectGetComm(self.raw as ffi::PetscObject, &mut comm) })?;
        Ok(comm)
    }

    pub(crate) fn local_size(&self) -> usize {
        let mut n: Int = 0;
        unsafe { ffi::VecGetLocalSize(self.raw, &mut n) };
        n as usize
    }

    /// First global index owned by this rank.
    pub(crate) fn ownership_start(&self) -> usize {
        let (mut lo, mut hi): (Int, Int) = (0, 0);
        unsafe { ffi::VecGetOwnershipRange(self.raw, &mut lo, &mut hi) };
        lo as usize
    }

    pub fn set(&mut self, v: f64) -> Result<()> {
        check(unsafe { ffi::VecSet(self.raw, v) })
    }

    pub fn zero(&mut self) -> Result<()> {
        check(unsafe { ffi::VecZeroEntries(self.raw) })
    }

    pub(crate) fn copy_from(&mut self, other: &Vector) -> Result<()> {
        check(unsafe { ffi::VecCopy(other.raw, self.raw) })
    }

    /// self += a * x
    pub fn axpy(&mut self, a: f64, x: &Vector) -> Result<()> {
        check(unsafe { ffi::VecAXPY(self.raw, a, x.raw) })
    }

    /// self *= a
    pub fn scale(&mut self, a: f64) -> Result<()> {
        check(unsafe { ffi::VecScale(self.raw, a) })
    }

    pub fn norm2(&self) -> Result<f64> {
        self.norm(ffi::NormType::NORM_2)
    }

    pub fn norm_inf(&self) -> Result<f64> {
        self.norm(ffi::NormType::NORM_INFINITY)
    }

    fn norm(&self, t: ffi::NormType) -> Result<f64> {
        let mut r = 0.0;
        check(unsafe { ffi::VecNorm(self.raw, t, &mut r) })?;
        Ok(r)
    }

    /// Global dot product.
    pub(crate) fn dot(&self, other: &Vector) -> Result<f64> {
        let mut r = 0.0;
        check(unsafe { ffi::VecDot(self.raw, other.raw, &mut r) })?;
        Ok(r)
    }

    /// Read-only view of the locally owned entries.
    pub fn read(&self) -> Result<VecRead<'_>> {
        let mut p: *const f64 = std::ptr::null();
        check(unsafe { ffi::VecGetArrayRead(self.raw, &mut p) })?;
        let n = self.local_size();
        Ok(VecRead { v: self, slice: unsafe { std::slice::from_raw_parts(p, n) } })
    }

    /// Writable view of the locally owned entries.
    pub fn write(&mut self) -> Result<VecWrite<'_>> {
        let mut p: *mut f64 = std::ptr::null_mut();
        check(unsafe { ffi::VecGetArray(self.raw, &mut p) })?;
        let n = self.local_size();
        Ok(VecWrite {
            raw: self.raw,
            slice: unsafe { std::slice::from_raw_parts_mut(p, n) },
            _v: std::marker::PhantomData,
        })
    }

    /// Sets the block size (before the layout is used).
    pub fn set_block_size(&mut self, bs: usize) -> Result<()> {
        check(unsafe { ffi::VecSetBlockSize(self.raw, bs as Int) })
    }

    /// Names the vector (shown by viewers and monitors).
    pub(crate) fn set_name(&mut self, name: &str) -> Result<()> {
        let c = super::cstr(name);
        check(unsafe { ffi::PetscObjectSetName(self.raw as ffi::PetscObject, c.as_ptr()) })
    }
}

impl super::Object for Vector {
    fn object(&self) -> ffi::PetscObject {
        self.raw as ffi::PetscObject
    }
}

/// Restores the array on drop.
pub struct VecRead<'a> {
    v: &'a Vector,
    slice: &'a [f64],
}
impl std::ops::Deref for VecRead<'_> {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        self.slice
    }
}
impl Drop for VecRead<'_> {
    fn drop(&mut self) {
        let mut p = self.slice.as_ptr();
        unsafe { ffi::VecRestoreArrayRead(self.v.raw, &mut p) };
    }
}

/// Restores the array on drop.
pub struct VecWrite<'a> {
    raw: ffi::Vec,
    slice: &'a mut [f64],
    _v: std::marker::PhantomData<&'a mut Vector>,
}
impl std::ops::Deref for VecWrite<'_> {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        self.slice
    }
}
impl std::ops::DerefMut for VecWrite<'_> {
    fn deref_mut(&mut self) -> &mut [f64] {
        self.slice
    }
}
impl Drop for VecWrite<'_> {
    fn drop(&mut self) {
        let mut p = self.slice.as_mut_ptr();
        unsafe { ffi::VecRestoreArray(self.raw, &mut p) };
    }
}

/// Scatter between a distributed vector and a rank-local one (owned + ghost entries).
pub(crate) struct Scatter {
    raw: ffi::VecScatter,
}

destroy_on_drop!(Scatter, VecScatterDestroy);

impl Scatter {
    /// Gathers `global[from[i]]` into `local[i]`.
    pub(crate) fn new(global: &Vector, from: &IndexSet, local: &Vector) -> Result<Scatter> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::VecScatterCreate(global.raw, from.raw, local.raw, std::ptr::null_mut(), &mut raw) })?;
        Ok(Scatter { raw })
    }

    /// local <- global (gather owned and ghost values).
    pub(crate) fn forward(&self, global: &Vector, local: &mut Vector) -> Result<()> {
        unsafe {
            check(ffi::VecScatterBegin(
                self.raw,
                global.raw,
                local.raw,
                ffi::InsertMode::INSERT_VALUES,
                ffi::ScatterMode::SCATTER_FORWARD,
            ))?;
            check(ffi::VecScatterEnd(
                self.raw,
                global.raw,
                local.raw,
                ffi::InsertMode::INSERT_VALUES,
                ffi::ScatterMode::SCATTER_FORWARD,
            ))
        }
    }

    /// global += local (accumulate element contributions, ghosts included).
    pub(crate) fn reverse_add(&self, local: &Vector, global: &mut Vector) -> Result<()> {
        unsafe {
            check(ffi::VecScatterBegin(
                self.raw,
                local.raw,
                global.raw,
                ffi::InsertMode::ADD_VALUES,
                ffi::ScatterMode::SCATTER_REVERSE,
            ))?;
            check(ffi::VecScatterEnd(
                self.raw,
                local.raw,
                global.raw,
                ffi::InsertMode::ADD_VALUES,
                ffi::ScatterMode::SCATTER_REVERSE,
            ))
        }
    }
}
