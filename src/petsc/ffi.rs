//! The PETSc C API, as bindgen generates it from PETSc's headers (`build.rs`).

include!(concat!(env!("OUT_DIR"), "/petsc_bindings.rs"));
