//! poroplast: parallel finite-element solver for large-deformation biphasic (poroelastic,
//! visco-plastic) aggregates compressed between rigid plates, on PETSc.

// Element kernels index small fixed-size arrays by their tensor/node indices on purpose.
#![allow(clippy::needless_range_loop)]

pub mod cli;
pub mod console;
pub mod driver;
pub mod error;
pub(crate) mod fem;
pub(crate) mod files;
pub(crate) mod hash;
pub mod io;
pub mod launch;
pub(crate) mod material;
pub(crate) mod mesh;
pub(crate) mod observe;
pub(crate) mod parallel;
pub mod petsc;
pub(crate) mod physics;
pub mod plot;
pub(crate) mod range;
pub mod reference_cell;
pub mod scene;
pub mod solver;
pub(crate) mod spelling;
pub mod sweep;

pub use observe::columns::reference_table as history_column_table;
pub use observe::observers::history_column_names;
