//! poroplast: parallel finite-element solver for large-deformation biphasic (poroelastic,
//! visco-plastic) aggregates compressed between rigid plates, on PETSc.

// Element kernels index small fixed-size arrays by their tensor/node indices on purpose.
#![allow(clippy::needless_range_loop)]

pub mod cli;
pub mod driver;
pub mod error;
pub mod fem;
pub(crate) mod files;
pub(crate) mod hash;
pub mod io;
pub mod material;
pub mod mesh;
pub mod observe;
pub mod parallel;
pub mod petsc;
pub mod physics;
pub mod range;
pub mod reference_cell;
pub mod scene;
pub mod solver;
pub mod sweep;
