//! The global options database.

use super::{check, ffi, petsc_free, Int};
use crate::error::{Error, Result};
use std::ffi::{c_char, CStr, CString};

/// Sets `-name value` (value `None` for a flag), overriding any earlier value.
pub fn set(name: &str, value: Option<&str>) -> Result<()> {
    let n = CString::new(format!("-{}", name.trim_start_matches('-'))).unwrap_or_default();
    let v = value.map(|v| CString::new(v).unwrap_or_default());
    check(unsafe {
        ffi::PetscOptionsSetValue(std::ptr::null_mut(), n.as_ptr(), v.as_ref().map_or(std::ptr::null(), |v| v.as_ptr()))
    })
}

/// Sets `-name value` only if the user has not set `-name` already (our defaults).
pub(crate) fn set_default(name: &str, value: Option<&str>) -> Result<()> {
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
pub(crate) fn get_string(name: &str) -> Result<Option<String>> {
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
pub(crate) fn ensure_all_used() -> Result<()> {
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
pub(crate) fn name_option(e: Error) -> Error {
    // Also inside another error (a solve that failed when a preconditioner read its options).
    let text = e.to_string();
    let Ok(all) = dump() else {
        return e;
    };
    if let Some(at) = ["Input string ", "Unable to find requested "].iter().find_map(|p| text.find(p)) {
        let short = text[at..].split(" (in ").next().unwrap_or_default();
        let named: Vec<&str> =
            all.lines().filter(|l| l.split_once(' ').is_some_and(|(_, v)| short.contains(&format!(" {v} ")))).collect();
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
pub(crate) fn dump() -> Result<String> {
    let mut s: *mut c_char = std::ptr::null_mut();
    unsafe {
        check(ffi::PetscOptionsGetAll(std::ptr::null_mut(), &mut s))?;
        let out = CStr::from_ptr(s).to_string_lossy().replace(" -", "\n-");
        petsc_free(s)?;
        Ok(out.trim().to_string())
    }
}
