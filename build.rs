//! Generates the PETSc FFI with bindgen from the headers under `$PETSC_DIR[/$PETSC_ARCH]`
//! (default: Debian's `/usr/lib/petsc`) and links the PETSc library found there.
//! MPI types are not generated here: they come from `mpi-sys` so `MPI_Comm` has one Rust type.
use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-env-changed=PETSC_DIR");
    println!("cargo:rerun-if-env-changed=PETSC_ARCH");
    println!("cargo:rerun-if-changed=src/petsc/wrapper.h");
    let dir = PathBuf::from(env::var("PETSC_DIR").unwrap_or_else(|_| "/usr/lib/petsc".into()));
    let arch = env::var("PETSC_ARCH").unwrap_or_default();
    let arch_dir = if arch.is_empty() { dir.clone() } else { dir.join(&arch) };

    let mut includes = vec![dir.join("include"), arch_dir.join("include")];
    includes.extend(mpi_include_dirs());
    let libdir = arch_dir.join("lib");
    let lib = ["petsc_real", "petsc"].into_iter().find(|l| has_lib(&libdir, l)).unwrap_or_else(|| {
        panic!("no libpetsc in {} — set PETSC_DIR (and PETSC_ARCH) to a PETSc 3.18 installation", libdir.display())
    });
    println!("cargo:rustc-link-search=native={}", libdir.display());
    println!("cargo:rustc-link-lib=dylib={lib}");
    // Let the binary find a non-system PETSc at run time without LD_LIBRARY_PATH.
    println!("cargo:rustc-link-arg=-Wl,-rpath,{}", libdir.display());

    let mut b = bindgen::Builder::default()
        .header("src/petsc/wrapper.h")
        .allowlist_function("(Petsc|Vec|Mat|IS|KSP|PC|SNES|TS|DM).*")
        .allowlist_type("(_p_)?(Petsc|Vec|Mat|IS|KSP|PC|SNES|TS|DM|Insert|Scatter|Norm).*")
        .allowlist_var("(PETSC|MAT|VEC|KSP|PC|SNES|TS|DM|IS)_.*|Petsc.*")
        .blocklist_type("MPI_.*|ompi_.*|MPIX_.*")
        .blocklist_function("MPI_.*|PMPI_.*")
        .raw_line("#[allow(unused_imports)] pub use mpi::ffi::*;")
        .default_enum_style(bindgen::EnumVariation::NewType { is_bitfield: false, is_global: false })
        .prepend_enum_name(false)
        .layout_tests(false)
        .generate_comments(false)
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()));
    for inc in &includes {
        b = b.clang_arg(format!("-I{}", inc.display()));
    }
    let out = PathBuf::from(env::var("OUT_DIR").unwrap()).join("petsc_bindings.rs");
    b.generate().expect("bindgen failed on the PETSc headers (is libclang-dev installed?)").write_to_file(out).unwrap();
}

fn has_lib(dir: &Path, name: &str) -> bool {
    ["so", "a", "dylib"].iter().any(|e| dir.join(format!("lib{name}.{e}")).exists())
}

/// MPI include directories from the MPI compiler wrapper (Open MPI or MPICH spellings).
fn mpi_include_dirs() -> Vec<PathBuf> {
    let cc = env::var("MPICC").unwrap_or_else(|_| "mpicc".into());
    for args in [&["--showme:incdirs"][..], &["-show"][..]] {
        if let Ok(o) = Command::new(&cc).args(args).output() {
            if o.status.success() {
                let s = String::from_utf8_lossy(&o.stdout);
                return s
                    .split_whitespace()
                    .filter_map(|t| {
                        if args[0] == "-show" {
                            t.strip_prefix("-I").map(PathBuf::from)
                        } else {
                            Some(PathBuf::from(t))
                        }
                    })
                    .collect();
            }
        }
    }
    Vec::new()
}
