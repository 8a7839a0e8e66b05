//! `Mat` (parallel AIJ with exact preallocation) and `MatNullSpace` (rigid-body modes) wrappers.

use super::{check, ffi, pbool, Int, Vector};
use crate::error::{Error, Result};

/// An owned PETSc matrix.
pub struct Mat {
    pub(crate) raw: ffi::Mat,
}

destroy_on_drop!(Mat, MatDestroy);

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

    /// A dense matrix with `n_local` rows on this rank and `cols` columns, in PETSc's own
    /// column-major storage (leading dimension `n_local`).
    pub(crate) fn dense(comm: ffi::MPI_Comm, n_local: usize, cols: usize) -> Result<Mat> {
        let mut raw = std::ptr::null_mut();
        check(unsafe {
            ffi::MatCreateDense(
                comm,
                n_local as Int,
                ffi::PETSC_DECIDE,
                ffi::PETSC_DETERMINE,
                cols as Int,
                std::ptr::null_mut(),
                &mut raw,
            )
        })?;
        Ok(Mat { raw })
    }

    /// Borrows a matrix PETSc hands to a callback.
    ///
    /// # Safety
    /// `raw` must be valid for the lifetime of the returned value.
    pub(crate) unsafe fn borrowed(raw: ffi::Mat) -> std::mem::ManuallyDrop<Mat> {
        std::mem::ManuallyDrop::new(Mat { raw })
    }

    pub(crate) fn as_raw(&self) -> ffi::Mat {
        self.raw
    }

    /// Adds a dense block `vals` (row-major, rows.len() × cols.len()) at global indices.
    /// Negative indices are skipped by PETSc.
    pub fn add_values(&mut self, rows: &[Int], cols: &[Int], vals: &[f64]) -> Result<()> {
        debug_assert_eq!(vals.len(), rows.len() * cols.len());
        check(unsafe {
            ffi::MatSetValues(
                self.raw,
                rows.len() as Int,
                rows.as_ptr(),
                cols.len() as Int,
                cols.as_ptr(),
                vals.as_ptr(),
                ffi::InsertMode::ADD_VALUES,
            )
        })
    }

    /// Replaces the rows and columns `rows` (global indices) by `diag` times the identity,
    /// keeping the nonzero pattern. With `x` and `b` given, b is made consistent: b_i −= A_ij x_j
    /// for the kept rows i, and b_j = diag x_j on the zeroed rows.
    pub fn zero_rows_columns(&mut self, rows: &[Int], diag: f64, xb: Option<(&Vector, &mut Vector)>) -> Result<()> {
        let (x, b) = xb.map_or((std::ptr::null_mut(), std::ptr::null_mut()), |(x, b)| (x.raw, b.raw));
        check(unsafe { ffi::MatZeroRowsColumns(self.raw, rows.len() as Int, rows.as_ptr(), diag, x, b) })
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

    /// y = Aᵀ x
    pub(crate) fn mult_transpose(&self, x: &Vector, y: &mut Vector) -> Result<()> {
        check(unsafe { ffi::MatMultTranspose(self.raw, x.raw, y.raw) })
    }

    /// A new matrix with the same layout, pattern and values.
    pub fn duplicate_with_values(&self) -> Result<Mat> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::MatDuplicate(self.raw, ffi::MatDuplicateOption::MAT_COPY_VALUES, &mut raw) })?;
        Ok(Mat { raw })
    }

    /// Copies the values of `src`, which has the same nonzero pattern.
    pub(crate) fn copy_values_from(&mut self, src: &Mat) -> Result<()> {
        check(unsafe { ffi::MatCopy(src.raw, self.raw, ffi::MatStructure::SAME_NONZERO_PATTERN) })
    }

    /// The operator's null space: Krylov methods remove it from their iterates.
    pub(crate) fn set_null_space(&mut self, ns: &NullSpace) -> Result<()> {
        check(unsafe { ffi::MatSetNullSpace(self.raw, ns.raw) })
    }

    /// Vectors compatible with the matrix layout (right, left).
    pub(crate) fn create_vecs(&self) -> Result<(Vector, Vector)> {
        let (mut r, mut l) = (std::ptr::null_mut(), std::ptr::null_mut());
        check(unsafe { ffi::MatCreateVecs(self.raw, &mut r, &mut l) })?;
        Ok((Vector { raw: r }, Vector { raw: l }))
    }

    /// Names the matrix.
    pub(crate) fn set_name(&mut self, name: &str) -> Result<()> {
        let c = super::cstr(name);
        check(unsafe { ffi::PetscObjectSetName(self.raw as ffi::PetscObject, c.as_ptr()) })
    }
}

/// A (near) null space: here the six rigid-body modes of 3-D elasticity.
pub(crate) struct NullSpace {
    pub(crate) raw: ffi::MatNullSpace,
}

destroy_on_drop!(NullSpace, MatNullSpaceDestroy);

impl NullSpace {
    /// A near-null space spanned by `vecs` (orthonormal, see `MatNullSpaceCreate`).
    pub(crate) fn from_vectors(comm: ffi::MPI_Comm, vecs: &[Vector]) -> Result<NullSpace> {
        let raws: Vec<ffi::Vec> = vecs.iter().map(|v| v.raw).collect();
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::MatNullSpaceCreate(comm, pbool(false), raws.len() as Int, raws.as_ptr(), &mut raw) })?;
        Ok(NullSpace { raw })
    }

    /// Rigid-body modes from nodal coordinates (`coords` has block size 3, one block per node).
    pub(crate) fn rigid_body(coords: &Vector) -> Result<NullSpace> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::MatNullSpaceCreateRigidBody(coords.raw, &mut raw) })?;
        Ok(NullSpace { raw })
    }
}

impl super::Object for NullSpace {
    fn object(&self) -> ffi::PetscObject {
        self.raw as ffi::PetscObject
    }
}

impl super::Object for Mat {
    fn object(&self) -> ffi::PetscObject {
        self.raw as ffi::PetscObject
    }
}

/// A sequential CSR block of this rank's rows (row pointers, column indices, values).
pub(crate) struct CsrBlock<'a> {
    pub(crate) ia: &'a [Int],
    pub(crate) ja: &'a [Int],
    pub(crate) vals: &'a mut [f64],
}

/// Direct access to the locally owned rows of an assembled AIJ matrix: the diagonal block
/// (columns local to [col_start, col_end)) and, in parallel, the off-diagonal block whose
/// compressed column j is global column `garray[j]`.
pub(crate) struct LocalCsr<'a> {
    pub(crate) row_start: usize,
    pub(crate) col_start: usize,
    pub(crate) col_end: usize,
    pub(crate) diag: CsrBlock<'a>,
    pub(crate) off: Option<CsrBlock<'a>>,
    pub(crate) garray: &'a [Int],
}

struct RawBlock {
    m: ffi::Mat,
    n: Int,
    ia: *const Int,
    ja: *const Int,
    vals: *mut f64,
}

impl RawBlock {
    unsafe fn get(m: ffi::Mat) -> Result<RawBlock> {
        let mut b = RawBlock { m, n: 0, ia: std::ptr::null(), ja: std::ptr::null(), vals: std::ptr::null_mut() };
        let mut done = ffi::PetscBool::PETSC_FALSE;
        check(ffi::MatGetRowIJ(m, 0, pbool(false), pbool(false), &mut b.n, &mut b.ia, &mut b.ja, &mut done))?;
        if done != ffi::PetscBool::PETSC_TRUE {
            return Err(crate::error::Error::Options(
                "MatGetRowIJ is not supported by this matrix type (-mat_type: use aij)".into(),
            ));
        }
        check(ffi::MatSeqAIJGetArray(m, &mut b.vals))?;
        Ok(b)
    }
    unsafe fn block<'a>(&self) -> CsrBlock<'a> {
        let ia = std::slice::from_raw_parts(self.ia, self.n as usize + 1);
        let nnz = ia[self.n as usize] as usize;
        CsrBlock {
            ia,
            ja: std::slice::from_raw_parts(self.ja, nnz),
            vals: std::slice::from_raw_parts_mut(self.vals, nnz),
        }
    }
    unsafe fn restore(mut self) -> Result<()> {
        let mut done = ffi::PetscBool::PETSC_FALSE;
        check(ffi::MatSeqAIJRestoreArray(self.m, &mut self.vals))?;
        check(ffi::MatRestoreRowIJ(
            self.m,
            0,
            pbool(false),
            pbool(false),
            &mut self.n,
            &mut self.ia,
            &mut self.ja,
            &mut done,
        ))
    }
}

impl Mat {
    /// The values of the locally owned rows (diagonal block, then off-diagonal block), in
    /// storage order: with [`set_local_values`](Self::set_local_values) on a matrix of the
    /// same pattern, a copy.
    pub(crate) fn local_values(&mut self) -> Result<Vec<f64>> {
        self.with_local_csr(|c| {
            let mut v = c.diag.vals.to_vec();
            if let Some(o) = &c.off {
                v.extend_from_slice(o.vals);
            }
            Ok(v)
        })
    }

    /// Sets the values of the locally owned rows from [`local_values`](Self::local_values) of a
    /// matrix with the same pattern, and assembles.
    pub(crate) fn set_local_values(&mut self, values: &[f64]) -> Result<()> {
        self.with_local_csr(|c| {
            let nd = c.diag.vals.len();
            let no = c.off.as_ref().map_or(0, |o| o.vals.len());
            if values.len() != nd + no {
                return Err(Error::Checkpoint(format!(
                    "saved matrix values: {} on this rank, the matrix has {}",
                    values.len(),
                    nd + no
                )));
            }
            c.diag.vals.copy_from_slice(&values[..nd]);
            if let Some(o) = c.off.as_mut() {
                o.vals.copy_from_slice(&values[nd..]);
            }
            Ok(())
        })?;
        self.assemble()
    }

    /// Runs `f` with direct access to the local CSR blocks of an assembled AIJ matrix. Values
    /// written there bypass `MatSetValues` (and its per-entry search); call [`Mat::assemble`]
    /// afterwards as usual.
    pub(crate) fn with_local_csr<R>(&mut self, f: impl FnOnce(&mut LocalCsr) -> Result<R>) -> Result<R> {
        unsafe {
            let mut t: ffi::MatType = std::ptr::null();
            check(ffi::MatGetType(self.raw, &mut t))?;
            let is_mpi = !t.is_null() && std::ffi::CStr::from_ptr(t).to_bytes() == b"mpiaij";
            let (mut r0, mut r1, mut c0, mut c1): (Int, Int, Int, Int) = (0, 0, 0, 0);
            check(ffi::MatGetOwnershipRange(self.raw, &mut r0, &mut r1))?;
            check(ffi::MatGetOwnershipRangeColumn(self.raw, &mut c0, &mut c1))?;
            let (ad, ao, garray): (ffi::Mat, ffi::Mat, &[Int]) = if is_mpi {
                let (mut ad, mut ao, mut g): (ffi::Mat, ffi::Mat, *const Int) =
                    (std::ptr::null_mut(), std::ptr::null_mut(), std::ptr::null());
                check(ffi::MatMPIAIJGetSeqAIJ(self.raw, &mut ad, &mut ao, &mut g))?;
                let (mut m, mut n): (Int, Int) = (0, 0);
                check(ffi::MatGetSize(ao, &mut m, &mut n))?;
                (ad, ao, if g.is_null() || n == 0 { &[] } else { std::slice::from_raw_parts(g, n as usize) })
            } else {
                (self.raw, std::ptr::null_mut(), &[])
            };
            let d = RawBlock::get(ad)?;
            let o = if ao.is_null() { None } else { Some(RawBlock::get(ao)?) };
            let mut csr = LocalCsr {
                row_start: r0 as usize,
                col_start: c0 as usize,
                col_end: c1 as usize,
                diag: d.block(),
                off: o.as_ref().map(|o| o.block()),
                garray,
            };
            let r = f(&mut csr);
            d.restore()?;
            if let Some(o) = o {
                o.restore()?;
            }
            r
        }
    }
}
