//! `KSP` and `PC` handles (borrowed from the SNES that owns them).

use super::{check, cstr, ffi, Int, Mat};
use crate::error::{Error, Result};
use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Work done before every solve of a KSP (before its own setup).
pub(crate) type PreSolve = fn(Ksp) -> Result<()>;

unsafe extern "C" fn pre_solve_tramp(
    ksp: ffi::KSP,
    _b: ffi::Vec,
    _x: ffi::Vec,
    ctx: *mut c_void,
) -> ffi::PetscErrorCode {
    // SAFETY: ctx is the PreSolve fn pointer set by Ksp::set_pre_solve.
    let f: PreSolve = std::mem::transmute::<*mut c_void, PreSolve>(ctx);
    match catch_unwind(AssertUnwindSafe(|| f(Ksp { raw: ksp }))) {
        Ok(Ok(())) => 0,
        Ok(Err(e)) => super::raise(&e.to_string()),
        Err(_) => super::raise("panic before a Krylov solve"),
    }
}

/// A Krylov solver owned by a SNES.
#[derive(Clone, Copy)]
pub struct Ksp {
    pub(crate) raw: ffi::KSP,
}

impl Ksp {
    pub fn pc(&self) -> Result<Pc> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::KSPGetPC(self.raw, &mut raw) })?;
        Ok(Pc { raw })
    }
    pub fn set_type(&self, t: &str) -> Result<()> {
        let c = cstr(t);
        check(unsafe { ffi::KSPSetType(self.raw, c.as_ptr()) })
    }
    /// Type name as PETSc reports it ("fgmres", "preonly", ...).
    pub(crate) fn type_name(&self) -> Result<String> {
        let mut t: ffi::KSPType = std::ptr::null();
        check(unsafe { ffi::KSPGetType(self.raw, &mut t) })?;
        Ok(super::type_name_of(t))
    }
    /// (rtol, atol, dtol, max_it) as set (by options too), unclamped.
    pub(crate) fn tolerances(&self) -> Result<(f64, f64, f64, i64)> {
        let (mut rtol, mut atol, mut dtol, mut maxit) = (0.0, 0.0, 0.0, 0 as Int);
        check(unsafe { ffi::KSPGetTolerances(self.raw, &mut rtol, &mut atol, &mut dtol, &mut maxit) })?;
        Ok((rtol, atol, dtol, maxit as i64))
    }
    /// The iteration limit in effect.
    pub(crate) fn max_it(&self) -> Result<usize> {
        let (mut rtol, mut atol, mut dtol, mut maxit) = (0.0, 0.0, 0.0, 0 as Int);
        check(unsafe { ffi::KSPGetTolerances(self.raw, &mut rtol, &mut atol, &mut dtol, &mut maxit) })?;
        Ok(maxit.max(0) as usize)
    }
    /// Sets only the iteration limit (PETSC_DEFAULT leaves the others as they are).
    pub(crate) fn set_max_it(&self, max_it: usize) -> Result<()> {
        let keep = ffi::PETSC_DEFAULT as f64;
        check(unsafe { ffi::KSPSetTolerances(self.raw, keep, keep, keep, max_it as Int) })
    }
    /// Iterations of the last solve.
    pub(crate) fn iterations(&self) -> Result<usize> {
        let mut n: Int = 0;
        check(unsafe { ffi::KSPGetIterationNumber(self.raw, &mut n) })?;
        Ok(n as usize)
    }
    pub(crate) fn set_operators(&self, a: &Mat, p: &Mat) -> Result<()> {
        check(unsafe { ffi::KSPSetOperators(self.raw, a.raw, p.raw) })
    }
    /// Solves A x = b with the current operators (divergence is not an error here: see
    /// [`Ksp::converged_reason`]).
    pub(crate) fn solve(&self, b: &super::Vector, x: &mut super::Vector) -> Result<()> {
        check(unsafe { ffi::KSPSolve(self.raw, b.raw, x.raw) })
    }
    /// Converged reason code (> 0 converged, < 0 diverged).
    pub(crate) fn converged_reason(&self) -> Result<i32> {
        let mut r = ffi::KSPConvergedReason(0);
        check(unsafe { ffi::KSPGetConvergedReason(self.raw, &mut r) })?;
        Ok(r.0)
    }
    /// Keep the preconditioner of the last setup although the operator changed (until reset).
    pub(crate) fn set_reuse_preconditioner(&self, reuse: bool) -> Result<()> {
        check(unsafe { ffi::KSPSetReusePreconditioner(self.raw, super::pbool(reuse)) })
    }
    pub(crate) fn set_up(&self) -> Result<()> {
        check(unsafe { ffi::KSPSetUp(self.raw) })
    }
    pub(crate) fn set_from_options(&self) -> Result<()> {
        check(unsafe { ffi::KSPSetFromOptions(self.raw) })
    }
    /// Calls `f` at the start of every solve, before the KSP sets itself up.
    pub(crate) fn set_pre_solve(&self, f: PreSolve) -> Result<()> {
        check(unsafe { ffi::KSPSetPreSolve(self.raw, Some(pre_solve_tramp), f as *mut c_void) })
    }
}

/// A preconditioner owned by a KSP.
#[derive(Clone, Copy)]
pub struct Pc {
    pub(crate) raw: ffi::PC,
}

impl Pc {
    pub(crate) fn raw_handle(&self) -> ffi::PC {
        self.raw
    }
    pub fn set_type(&self, t: &str) -> Result<()> {
        let c = cstr(t);
        check(unsafe { ffi::PCSetType(self.raw, c.as_ptr()) })
    }
    /// Type name as PETSc reports it ("fieldsplit", "lu", ...).
    pub(crate) fn type_name(&self) -> Result<String> {
        let mut t: ffi::PCType = std::ptr::null();
        check(unsafe { ffi::PCGetType(self.raw, &mut t) })?;
        Ok(super::type_name_of(t))
    }
    /// SOR by forward sweeps over each rank's own rows (PCSOR's default is the symmetric sweep).
    pub(crate) fn set_sor_local_forward(&self) -> Result<()> {
        check(unsafe { ffi::PCSORSetSymmetric(self.raw, ffi::MatSORType::SOR_LOCAL_FORWARD_SWEEP) })
    }
    /// x = M⁻¹ b with the preconditioner as set up (for a direct one, an exact solve).
    pub fn apply(&self, b: &super::Vector, x: &mut super::Vector) -> Result<()> {
        check(unsafe { ffi::PCApply(self.raw, b.raw, x.raw) })
    }
    /// Solves with a factorisation preconditioner (LU, Cholesky) for several right-hand sides
    /// at once: `out[j]` = M⁻¹ `rhs[j]`, by one `MatMatSolve` on dense blocks (MUMPS then
    /// passes over the factors once, with BLAS-3, instead of once per column). The vectors
    /// share one layout. Another preconditioner type: one `apply` per column.
    pub(crate) fn apply_columns(&self, rhs: &[super::Vector], out: &mut [super::Vector]) -> Result<()> {
        if rhs.len() != out.len() {
            return Err(Error::Internal(format!(
                "apply_columns: {} right-hand sides, {} outputs",
                rhs.len(),
                out.len()
            )));
        }
        let Some(first) = rhs.first() else { return Ok(()) };
        if !matches!(self.type_name()?.as_str(), "lu" | "cholesky") {
            return rhs.iter().zip(out.iter_mut()).try_for_each(|(b, x)| self.apply(b, x));
        }
        let mut factor: ffi::Mat = std::ptr::null_mut();
        check(unsafe { ffi::PCFactorGetMatrix(self.raw, &mut factor) })?;
        let (n, cols) = (first.local_size(), rhs.len());
        let (b, x) = (Mat::dense(first.comm()?, n, cols)?, Mat::dense(first.comm()?, n, cols)?);
        // Column-major local blocks with leading dimension n.
        unsafe {
            let mut a: *mut f64 = std::ptr::null_mut();
            check(ffi::MatDenseGetArrayWrite(b.raw, &mut a))?;
            let block = std::slice::from_raw_parts_mut(a, n * cols);
            for (j, v) in rhs.iter().enumerate() {
                block[j * n..(j + 1) * n].copy_from_slice(&v.read()?[..]);
            }
            check(ffi::MatDenseRestoreArrayWrite(b.raw, &mut a))?;
            check(ffi::MatMatSolve(factor, b.raw, x.raw))?;
            let mut a: *const f64 = std::ptr::null();
            check(ffi::MatDenseGetArrayRead(x.raw, &mut a))?;
            let block = std::slice::from_raw_parts(a, n * cols);
            let copied = out.iter_mut().enumerate().try_for_each(|(j, v)| -> Result<()> {
                v.write()?.copy_from_slice(&block[j * n..(j + 1) * n]);
                Ok(())
            });
            check(ffi::MatDenseRestoreArrayRead(x.raw, &mut a))?;
            copied
        }
    }
    /// The KSPs of a fieldsplit's blocks (set up before), in split order.
    pub(crate) fn split_ksps(&self) -> Result<Vec<Ksp>> {
        let mut n: Int = 0;
        let mut subs: *mut ffi::KSP = std::ptr::null_mut();
        check(unsafe { ffi::PCFieldSplitGetSubKSP(self.raw, &mut n, &mut subs) })?;
        let out = (0..n as usize).map(|i| Ksp { raw: unsafe { *subs.add(i) } }).collect();
        unsafe { super::petsc_free(subs) }?;
        Ok(out)
    }
    /// A multigrid preconditioner's number of levels (set up before).
    pub(crate) fn mg_levels(&self) -> Result<usize> {
        let mut n: Int = 0;
        check(unsafe { ffi::PCMGGetLevels(self.raw, &mut n) })?;
        Ok(n.max(0) as usize)
    }
    /// A multigrid preconditioner's smoother on `level` (0: the coarsest).
    pub(crate) fn mg_smoother(&self, level: usize) -> Result<Ksp> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::PCMGGetSmoother(self.raw, level as Int, &mut raw) })?;
        Ok(Ksp { raw })
    }
    /// Makes the preconditioners of a fieldsplit's blocks (set up before) forget what they kept
    /// from earlier setups — GAMG its interpolation — so that the next setup builds them as a new
    /// solver would. Nothing for another type.
    pub(crate) fn renew_split_preconditioners(&self) -> Result<()> {
        if self.type_name()? != "fieldsplit" {
            return Ok(());
        }
        // PCReset would not do: GAMG's keeps its levels. A new object of the same type, set
        // from the same options, is what a new solver has.
        self.split_ksps()?.into_iter().try_for_each(|k| {
            let pc = k.pc()?;
            let t = pc.type_name()?;
            pc.set_type("none")?;
            pc.set_type(&t)?;
            check(unsafe { ffi::PCSetFromOptions(pc.raw) })
        })
    }
    /// A Schur fieldsplit's Schur-complement preconditioner: built from `schur` (user's).
    pub(crate) fn set_schur_pre_user(&self, schur: &Mat) -> Result<()> {
        check(unsafe {
            ffi::PCFieldSplitSetSchurPre(
                self.raw_handle(),
                ffi::PCFieldSplitSchurPreType::PC_FIELDSPLIT_SCHUR_PRE_USER,
                schur.as_raw(),
            )
        })
    }
}

/// A stand-alone LU factorisation of a matrix (an owned PC, outside any SNES).
pub struct LuFactor {
    raw: ffi::PC,
}

destroy_on_drop!(LuFactor, PCDestroy);

impl LuFactor {
    /// Factorises `a` (collective on `comm`).
    pub fn new(comm: ffi::MPI_Comm, a: &Mat) -> Result<LuFactor> {
        let mut raw = std::ptr::null_mut();
        check(unsafe { ffi::PCCreate(comm, &mut raw) })?;
        let f = LuFactor { raw };
        check(unsafe { ffi::PCSetOperators(raw, a.raw, a.raw) })?;
        f.pc().set_type("lu")?;
        check(unsafe { ffi::PCSetUp(raw) })?;
        Ok(f)
    }

    /// The factorisation as a preconditioner handle (its `apply` solves).
    pub fn pc(&self) -> Pc {
        Pc { raw: self.raw }
    }
}
