//! PETSc 3.18 registers some types once per process, behind flags that `PetscFinalize` does
//! not reset, into lists that it destroys: after a second `PetscInitialize` they would be
//! missing ("Unknown Mat type given: schurcomplement" at the first fieldsplit-Schur set-up of
//! the second run; likewise the KSP initial-guess and TS trajectory types). Registered here
//! again (the still current upstream `kspmatregi.c` has the same flag).

use super::{check, ffi};
use crate::error::Result;

extern "C" {
    fn MatCreate_SchurComplement(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn MatCreate_LMVMDFP(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn MatCreate_LMVMBFGS(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn MatCreate_LMVMSR1(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn MatCreate_LMVMBrdn(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn MatCreate_LMVMBadBrdn(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn MatCreate_LMVMSymBrdn(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn MatCreate_LMVMSymBadBrdn(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn MatCreate_LMVMDiagBrdn(m: ffi::Mat) -> ffi::PetscErrorCode;
    fn KSPGuessCreate_Fischer(g: ffi::KSPGuess) -> ffi::PetscErrorCode;
    fn KSPGuessCreate_POD(g: ffi::KSPGuess) -> ffi::PetscErrorCode;
    static mut TSTrajectoryRegisterAllCalled: ffi::PetscBool;
}

/// Before `PetscInitialize`: the flag PETSc exports is reset, so TS registers its
/// trajectory types again.
pub(super) fn before() {
    unsafe { TSTrajectoryRegisterAllCalled = ffi::PetscBool::PETSC_FALSE };
}

/// After `PetscInitialize`: the types behind static flags, as KSPMatRegisterAll and
/// KSPGuessRegisterAll register them.
pub(super) fn after() -> Result<()> {
    type MatCreate = unsafe extern "C" fn(ffi::Mat) -> ffi::PetscErrorCode;
    let mats: [(&std::ffi::CStr, MatCreate); 9] = [
        (c"schurcomplement", MatCreate_SchurComplement),
        (c"lmvmdfp", MatCreate_LMVMDFP),
        (c"lmvmbfgs", MatCreate_LMVMBFGS),
        (c"lmvmsr1", MatCreate_LMVMSR1),
        (c"lmvmbroyden", MatCreate_LMVMBrdn),
        (c"lmvmbadbroyden", MatCreate_LMVMBadBrdn),
        (c"lmvmsymbroyden", MatCreate_LMVMSymBrdn),
        (c"lmvmsymbadbroyden", MatCreate_LMVMSymBadBrdn),
        (c"lmvmdiagbroyden", MatCreate_LMVMDiagBrdn),
    ];
    for (name, f) in mats {
        check(unsafe { ffi::MatRegister(name.as_ptr(), Some(f)) })?;
    }
    check(unsafe { ffi::KSPGuessRegister(c"fischer".as_ptr(), Some(KSPGuessCreate_Fischer)) })?;
    check(unsafe { ffi::KSPGuessRegister(c"pod".as_ptr(), Some(KSPGuessCreate_POD)) })
}
