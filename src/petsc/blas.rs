//! The BLAS under PETSc's direct solvers. Debian 12's OpenBLAS (0.3.21) does not recognise
//! recent Intel cores and falls back to its Prescott (SSE3) kernels; MUMPS's dense updates then
//! run several times slower than with the AVX2/AVX-512 kernels the CPU supports. OpenBLAS picks
//! its kernels when it is loaded, before `main`, so the fix is an environment variable
//! (`OPENBLAS_CORETYPE`) set before the process starts: see `main`.

use std::ffi::{c_char, c_void, CStr};

extern "C" {
    fn dlsym(handle: *mut c_void, symbol: *const c_char) -> *mut c_void;
}

/// The kernel family OpenBLAS chose ("Prescott", "SkylakeX", ...), if OpenBLAS is loaded.
pub(crate) fn kernel() -> Option<String> {
    // RTLD_DEFAULT (a null handle in glibc): search every loaded library.
    let f = unsafe { dlsym(std::ptr::null_mut(), c"openblas_get_corename".as_ptr()) };
    if f.is_null() {
        return None;
    }
    let corename: extern "C" fn() -> *const c_char = unsafe { std::mem::transmute(f) };
    let name = corename();
    (!name.is_null()).then(|| unsafe { CStr::from_ptr(name) }.to_string_lossy().into_owned())
}

/// The kernels to ask for when OpenBLAS chose pre-AVX2 ones on a CPU with AVX2 (or
/// AVX-512), unless the user chose (`OPENBLAS_CORETYPE` set).
pub fn better_kernel() -> Option<&'static str> {
    if std::env::var_os("OPENBLAS_CORETYPE").is_some() {
        return None;
    }
    let old = ["prescott", "core2", "penryn", "dunnington", "nehalem", "atom", "katmai", "northwood"];
    let chosen = kernel()?.to_lowercase();
    if !old.iter().any(|o| chosen.contains(o)) {
        return None;
    }
    x86_kernel()
}

#[cfg(target_arch = "x86_64")]
fn x86_kernel() -> Option<&'static str> {
    if std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx512dq") {
        Some("SkylakeX")
    } else if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        Some("Haswell")
    } else {
        None
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn x86_kernel() -> Option<&'static str> {
    None
}
