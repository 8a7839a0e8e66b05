//! Thin safe layer over PETSc 3.18: the init token, error capture, options database and log
//! stages, with RAII wrappers for the objects in the submodules.
//!
//! Lifetimes: every wrapper destroys its PETSc object in `Drop`, but only while PETSc is
//! initialised; the [`Petsc`] token finalises PETSc when dropped, so it must outlive (be declared
//! before) every object — `main` and the driver keep that order. A wrapper dropped after
//! finalisation leaks instead of crashing.

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

#[allow(non_camel_case_types, non_snake_case, non_upper_case_globals, dead_code, improper_ctypes, clippy::all)]
pub mod ffi {
    include!(concat!(env!("OUT_DIR"), "/petsc_bindings.rs"));
}

pub mod blas;
mod dm;
mod is;
mod ksp;
mod mat;
mod snes;
mod ts;
mod vec;

pub use dm::{DmShell, FieldDecomposition};
pub use is::IndexSet;
pub use ksp::{Ksp, LuFactor, Pc};
pub use mat::{CsrBlock, LocalCsr, Mat, NullSpace};
pub use snes::{ShellSolve, Snes, SolverState};
pub use ts::{Ts, TsProblem, TsRef};
pub use vec::{Scatter, Vector};

use crate::error::{Error, Result};
use mpi::topology::SimpleCommunicator;
use mpi::traits::AsRaw;
use std::ffi::{c_char, c_int, CStr, CString};
use std::sync::Mutex;

/// A PETSc type name (a C string that may be NULL before a type is set) as a String.
pub(crate) fn type_name_of(t: *const c_char) -> String {
    if t.is_null() {
        String::new()
    } else {
        unsafe { CStr::from_ptr(t) }.to_string_lossy().into_owned()
    }
}

/// PETSc's integer type (32-bit in the Debian build).
pub type Int = ffi::PetscInt;

/// A live PETSc object owned by one of the wrappers (for compose).
pub trait Object {
    fn object(&self) -> ffi::PetscObject;
}

impl Object for Vector {
    fn object(&self) -> ffi::PetscObject {
        self.raw as ffi::PetscObject
    }
}

/// Message of the most recent PETSc error, recorded by our error handler at the point where it
/// was raised, with the call chain appended as the error propagates.
static LAST_ERROR: Mutex<String> = Mutex::new(String::new());

unsafe extern "C" fn record_error(
    _comm: ffi::MPI_Comm,
    line: c_int,
    func: *const c_char,
    file: *const c_char,
    code: ffi::PetscErrorCode,
    kind: ffi::PetscErrorType,
    mess: *const c_char,
    _ctx: *mut std::ffi::c_void,
) -> ffi::PetscErrorCode {
    let s = |p: *const c_char| {
        if p.is_null() {
            String::new()
        } else {
            CStr::from_ptr(p).to_string_lossy().into_owned()
        }
    };
    if let Ok(mut buf) = LAST_ERROR.lock() {
        if kind == ffi::PetscErrorType::PETSC_ERROR_INITIAL {
            let mut generic: *const c_char = std::ptr::null();
            ffi::PetscErrorMessage(code, &mut generic, std::ptr::null_mut());
            let m = s(mess);
            let g = s(generic);
            *buf = if m.is_empty() {
                g
            } else if g.is_empty() {
                m
            } else {
                format!("{m} [{g}]")
            };
            buf.push_str(&format!(" (in {} at {}:{})", s(func), s(file), line));
        } else {
            buf.push_str(&format!(" <- {}", s(func)));
        }
    }
    code
}

/// Turns a PETSc return code into a `Result`, with PETSc's message for non-zero codes.
pub fn check(code: ffi::PetscErrorCode) -> Result<()> {
    if code == 0 {
        return Ok(());
    }
    let msg = LAST_ERROR.lock().map(|mut b| std::mem::take(&mut *b)).unwrap_or_default();
    Err(Error::Petsc { code, msg: if msg.is_empty() { format!("error code {code}") } else { msg } })
}

/// Raises a PETSc error from Rust (inside a callback), so PETSc unwinds its own stack and the
/// message reaches the caller of the outermost PETSc function.
pub(crate) fn raise(msg: &str) -> ffi::PetscErrorCode {
    let c = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    unsafe {
        ffi::PetscError(
            mpi::ffi::RSMPI_COMM_SELF,
            0,
            c"poroplast callback".as_ptr(),
            c"rust".as_ptr(),
            ffi::PETSC_ERR_USER as ffi::PetscErrorCode,
            ffi::PetscErrorType::PETSC_ERROR_INITIAL,
            c"%s".as_ptr(),
            c.as_ptr(),
        )
    }
}

/// True between PetscInitialize and PetscFinalize: wrappers only destroy objects then.
pub(crate) fn alive() -> bool {
    unsafe {
        ffi::PetscInitializeCalled == ffi::PetscBool::PETSC_TRUE
            && ffi::PetscFinalizeCalled != ffi::PetscBool::PETSC_TRUE
    }
}

/// The PETSc init token. Create it after MPI (rsmpi) is initialised; drop it before MPI.
pub struct Petsc {
    _private: (),
}

impl Petsc {
    /// Initialises PETSc on `comm` (its `PETSC_COMM_WORLD`: the ranks that take part in
    /// PETSc's collective start and end) with the given command-line style options (e.g.
    /// `["-log_view", "-ksp_monitor"]`), so init-time options such as `-log_view` work.
    ///
    /// PETSc may be initialised again after it was finalised (while MPI lives): each
    /// initialisation starts from an empty options database, so a sweep's cases, each run
    /// between its own `init` and drop, see only their own options. Our own records of the
    /// options (the defaults we set) and of the last error start empty too.
    pub fn init(comm: &SimpleCommunicator, options: &[String]) -> Result<Petsc> {
        if alive() {
            return Err(Error::Internal("PETSc is already initialised in this process".into()));
        }
        options::DEFAULTS.lock().unwrap_or_else(|e| e.into_inner()).clear();
        LAST_ERROR.lock().unwrap_or_else(|e| e.into_inner()).clear();
        let again = INITIALISED_BEFORE.swap(true, std::sync::atomic::Ordering::Relaxed);
        if again {
            reinit::before();
        }
        let mut args: Vec<CString> = std::iter::once("poroplast".to_string())
            .chain(options.iter().cloned())
            .map(|s| CString::new(s).map_err(|_| Error::Options("PETSc option contains a NUL byte".into())))
            .collect::<Result<_>>()?;
        // PETSc keeps pointers into argv for the whole run: leak the strings deliberately.
        let mut ptrs: Vec<*mut c_char> = args.iter_mut().map(|s| s.as_ptr() as *mut c_char).collect();
        ptrs.push(std::ptr::null_mut());
        let mut argc = (ptrs.len() - 1) as c_int;
        let mut argv = ptrs.as_mut_ptr();
        std::mem::forget(args);
        std::mem::forget(ptrs);
        unsafe {
            ffi::PETSC_COMM_WORLD = comm.as_raw();
            check(ffi::PetscInitialize(&mut argc, &mut argv, std::ptr::null(), std::ptr::null()))?;
            check(ffi::PetscPushErrorHandler(Some(record_error), std::ptr::null_mut()))?;
        }
        let petsc = Petsc { _private: () };
        if again {
            reinit::after()?;
        }
        Ok(petsc)
    }

    /// The communicator all objects live on.
    pub fn comm(&self) -> ffi::MPI_Comm {
        unsafe { ffi::PETSC_COMM_WORLD }
    }
}

/// PETSc has been initialised in this process before (and finalised since).
static INITIALISED_BEFORE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// PETSc 3.18 registers some types once per process, behind flags that `PetscFinalize` does
/// not reset, into lists that it destroys: after a second `PetscInitialize` they would be
/// missing ("Unknown Mat type given: schurcomplement" at the first fieldsplit-Schur set-up of
/// the second run; likewise the KSP initial-guess and TS trajectory types). Registered here
/// again (the still current upstream `kspmatregi.c` has the same flag).
mod reinit {
    use super::{check, ffi, Result};

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
}

impl Drop for Petsc {
    fn drop(&mut self) {
        if alive() {
            unsafe {
                ffi::PetscPopErrorHandler();
                ffi::PetscFinalize();
            }
        }
    }
}

/// The global options database.
pub mod options {
    use super::*;

    /// Sets `-name value` (value `None` for a flag), overriding any earlier value.
    pub fn set(name: &str, value: Option<&str>) -> Result<()> {
        let n = CString::new(format!("-{}", name.trim_start_matches('-'))).unwrap_or_default();
        let v = value.map(|v| CString::new(v).unwrap_or_default());
        check(unsafe {
            ffi::PetscOptionsSetValue(
                std::ptr::null_mut(),
                n.as_ptr(),
                v.as_ref().map_or(std::ptr::null(), |v| v.as_ptr()),
            )
        })
    }

    /// Sets `-name value` only if the user has not set `-name` already (our defaults).
    pub fn set_default(name: &str, value: Option<&str>) -> Result<()> {
        if !has(name)? {
            set(name, value)?;
            DEFAULTS.lock().unwrap_or_else(|e| e.into_inner()).insert(format!("-{}", name.trim_start_matches('-')));
        }
        Ok(())
    }

    /// Options set by [`set_default`]: a default a user's choice made irrelevant (e.g. the
    /// fieldsplit settings under `-pc_type lu`) is not an error, so [`unused`] skips them.
    pub(super) static DEFAULTS: std::sync::Mutex<std::collections::BTreeSet<String>> =
        std::sync::Mutex::new(std::collections::BTreeSet::new());

    /// Whether `-name` is in the database (PETSc then counts it as used).
    pub fn has(name: &str) -> Result<bool> {
        let n = CString::new(format!("-{}", name.trim_start_matches('-'))).unwrap_or_default();
        let mut set = ffi::PetscBool::PETSC_FALSE;
        check(unsafe { ffi::PetscOptionsHasName(std::ptr::null_mut(), std::ptr::null(), n.as_ptr(), &mut set) })?;
        Ok(set == ffi::PetscBool::PETSC_TRUE)
    }

    /// Reads a string option, if set.
    pub fn get_string(name: &str) -> Result<Option<String>> {
        let n = CString::new(format!("-{}", name.trim_start_matches('-'))).unwrap_or_default();
        let mut buf = vec![0 as c_char; 1024];
        let mut set = ffi::PetscBool::PETSC_FALSE;
        check(unsafe {
            ffi::PetscOptionsGetString(
                std::ptr::null_mut(),
                std::ptr::null(),
                n.as_ptr(),
                buf.as_mut_ptr(),
                buf.len(),
                &mut set,
            )
        })?;
        Ok((set == ffi::PetscBool::PETSC_TRUE)
            .then(|| unsafe { CStr::from_ptr(buf.as_ptr()) }.to_string_lossy().into_owned()))
    }

    /// Options PETSc reads outside object set-up (at init/finalize) that `options_left` may list.
    const IGNORED_OPTIONS: &[&str] = &[
        "-log_view",
        "-options_left",
        "-malloc_dump",
        "-malloc_debug",
        "-info",
        "-log_trace",
        "-on_error_abort",
        "-no_signal_handler",
    ];

    /// Every PETSc option must have been read once a step has run; reports the others.
    pub fn ensure_all_used() -> Result<()> {
        let unused: Vec<String> = unused()?.into_iter().filter(|o| !IGNORED_OPTIONS.contains(&o.as_str())).collect();
        if unused.is_empty() {
            return Ok(());
        }
        Err(Error::Options(format!(
            "unknown or unused PETSc option(s): {} (check the spelling, or the solver they belong to)",
            unused.join(" ")
        )))
    }

    /// Options set but never queried by any PETSc object so far, as `-name` strings.
    pub fn unused() -> Result<Vec<String>> {
        let mut n: Int = 0;
        let mut names: *mut *mut c_char = std::ptr::null_mut();
        let mut values: *mut *mut c_char = std::ptr::null_mut();
        unsafe {
            check(ffi::PetscOptionsLeftGet(std::ptr::null_mut(), &mut n, &mut names, &mut values))?;
            let defaults = DEFAULTS.lock().unwrap_or_else(|e| e.into_inner());
            let out = (0..n as usize)
                .map(|i| format!("-{}", CStr::from_ptr(*names.add(i)).to_string_lossy()))
                .filter(|o| !defaults.contains(o))
                .collect();
            check(ffi::PetscOptionsLeftRestore(std::ptr::null_mut(), &mut n, &mut names, &mut values))?;
            Ok(out)
        }
    }

    /// A PETSc error about an option's value (not a number, an unknown type), which PETSc
    /// reports by the value alone, with the option(s) holding that value named:
    /// `-ksp_rtol abc: Input string abc has no numeric value [...]`. Other errors unchanged.
    pub fn name_option(e: Error) -> Error {
        // Also inside another error (a solve that failed when a preconditioner read its options).
        let text = e.to_string();
        let Ok(all) = dump() else {
            return e;
        };
        if let Some(at) = ["Input string ", "Unable to find requested "].iter().find_map(|p| text.find(p)) {
            let short = text[at..].split(" (in ").next().unwrap_or_default();
            let named: Vec<&str> = all
                .lines()
                .filter(|l| l.split_once(' ').is_some_and(|(_, v)| short.contains(&format!(" {v} "))))
                .collect();
            if !named.is_empty() {
                return Error::Options(format!("PETSc option {}: {short}", named.join(", ")));
            }
        }
        // Any other error raised while PETSc read its options (e.g. "Restart must be positive"):
        // the options the user gave, since one of them is the cause.
        if text.contains("SetFromOptions") {
            let defaults = DEFAULTS.lock().unwrap_or_else(|e| e.into_inner());
            let given: Vec<&str> = all
                .lines()
                .filter(|l| {
                    let name = l.split(' ').next().unwrap_or_default();
                    !defaults.contains(name) && name != "-no_signal_handler"
                })
                .collect();
            if !given.is_empty() {
                return Error::Options(format!("{e} — while reading the PETSc options given: {}", given.join(" ")));
            }
        }
        e
    }

    /// All options in the database, one `-name value` per line (for the run directory).
    pub fn dump() -> Result<String> {
        let mut s: *mut c_char = std::ptr::null_mut();
        unsafe {
            check(ffi::PetscOptionsGetAll(std::ptr::null_mut(), &mut s))?;
            let out = CStr::from_ptr(s).to_string_lossy().replace(" -", "\n-");
            petsc_free(s)?;
            Ok(out.trim().to_string())
        }
    }
}

/// A `-log_view` stage, entered for the lifetime of the guard from [`Stage::push`].
#[derive(Clone, Copy)]
pub struct Stage(ffi::PetscLogStage);

impl Stage {
    /// Registers a named stage.
    pub fn register(name: &str) -> Result<Stage> {
        let n = CString::new(name).unwrap_or_default();
        let mut s: ffi::PetscLogStage = 0;
        check(unsafe { ffi::PetscLogStageRegister(n.as_ptr(), &mut s) })?;
        Ok(Stage(s))
    }
    /// Enters the stage until the guard drops.
    pub fn push(self) -> StageGuard {
        unsafe { ffi::PetscLogStagePush(self.0) };
        StageGuard
    }
}

/// Leaves the log stage on drop.
pub struct StageGuard;
impl Drop for StageGuard {
    fn drop(&mut self) {
        unsafe { ffi::PetscLogStagePop() };
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
