//! What `poroplast sweep` was asked to do: the command line of a sweep.

use std::path::PathBuf;

/// What `poroplast sweep` was asked to do.
#[derive(Debug, Clone)]
pub struct SweepArgs {
    /// The study file.
    pub study: PathBuf,
    /// Ranks of each case (k); must divide the world's size.
    pub ranks_per_case: usize,
    pub out: Option<PathBuf>,
    /// The case store (default: the sweep directory's `cases/`).
    pub cases_dir: Option<PathBuf>,
    /// PETSc options of every case (after the study's own).
    pub petsc: Vec<String>,
    /// A progress line per case ended.
    pub progress: bool,
}
