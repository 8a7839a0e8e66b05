//! Thin safe layer over PETSc 3.18: the init token, error capture, options database and log
//! stages, with RAII wrappers for the objects in the submodules.
//!
//! Lifetimes: every wrapper destroys its PETSc object in `Drop`, but only while PETSc is
//! initialised; the [`Petsc`] token finalises PETSc when dropped, so it must outlive (be declared
//! before) every object — `main` and the driver keep that order. A wrapper dropped after
//! finalisation leaks instead of crashing.

// First: its `destroy_on_drop!` serves the wrappers declared after it.
#[macro_use]
mod lifetime;

#[allow(non_camel_case_types, non_snake_case, non_upper_case_globals, dead_code, improper_ctypes, clippy::all)]
pub mod ffi;

pub mod blas;
mod c_types;
mod dm;
mod error;
mod init;
mod is;
mod ksp;
mod mat;
mod memory;
mod object;
pub mod options;
mod reinit;
mod snes;
mod stage;
mod ts;
mod vec;

pub use c_types::Int;
pub(crate) use dm::{DmShell, FieldDecomposition};
pub use init::Petsc;
pub(crate) use is::IndexSet;
pub use ksp::LuFactor;
pub(crate) use ksp::{Ksp, Pc};
pub use mat::Mat;
pub(crate) use mat::{CsrBlock, LocalCsr, NullSpace};
pub(crate) use object::Object;
pub(crate) use snes::{ShellSolve, Snes, SolverState};
pub use ts::{Ts, TsProblem, TsRef};
pub(crate) use vec::Scatter;
pub use vec::Vector;

pub(crate) use c_types::{cstr, pbool, type_name_of};
pub(crate) use error::{check, raise};
pub(crate) use lifetime::alive;
pub(crate) use memory::{petsc_free, petsc_malloc};
pub(crate) use stage::Stage;
