//! The library's one error type. Every failure names what went wrong and where
//! (file, group, element, quadrature point, PETSc function), so `main` can print one line and exit non-zero.

/// Errors raised by poroplast.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A PETSc call returned a non-zero code; `msg` carries PETSc's own message.
    #[error("PETSc error {code}: {msg}")]
    Petsc { code: i32, msg: String },
    /// MPI failure outside PETSc.
    #[error("MPI: {0}")]
    Mpi(String),
    /// Missing, unreadable or malformed mesh, or a missing physical group.
    #[error("mesh {path}: {msg}")]
    Mesh { path: String, msg: String },
    /// Invalid scene: unknown key, non-physical parameter, inconsistent settings.
    #[error("scene {path}: {msg}")]
    Scene { path: String, msg: String },
    /// Invalid material parameters.
    #[error("material: {0}")]
    Material(String),
    /// A state outside the material's domain (J <= 0, J <= Φs, NaN) at a quadrature point.
    #[error("inadmissible state in element {cell}, point {point}: {msg} (J = {j})")]
    Domain { cell: usize, point: usize, j: f64, msg: String },
    /// File-system or HDF5 failure on a named path.
    #[error("{path}: {msg}")]
    Io { path: String, msg: String },
    /// A PETSc or `-poroplast_*` option that is unknown, unused or has an invalid value.
    #[error("options: {0}")]
    Options(String),
    /// A solve that did not converge: a time step after all retries, or the settling.
    #[error("no convergence: {0}")]
    Diverged(String),
    /// A checkpoint that does not fit the run being resumed (element or value counts).
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// An operating-system facility the run needs (signal handlers).
    #[error("system: {0}")]
    System(String),
    /// A broken internal invariant (a bug: please report it with the command line).
    #[error("internal error: {0}")]
    Internal(String),
    /// The run stopped on request (a signal) after writing a checkpoint.
    #[error("{0}")]
    Stopped(String),
    /// A run stopped on request (a signal) during its set-up, before it wrote anything.
    #[error("{0}")]
    StoppedInSetup(String),
    /// A sweep that cannot start (bad study, rank count), or whose cases failed.
    #[error("sweep: {0}")]
    Sweep(String),
    /// A failure on another rank, reported here so every rank stops together.
    #[error("{msg} (reported by rank {rank})")]
    Elsewhere { rank: i32, msg: String },
}

/// Result with the library error.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// A mesh error for `path`.
    pub(crate) fn mesh(path: impl AsRef<std::path::Path>, msg: impl Into<String>) -> Self {
        Error::Mesh { path: path.as_ref().display().to_string(), msg: msg.into() }
    }
    /// An I/O error for `path`.
    pub(crate) fn io(path: impl AsRef<std::path::Path>, msg: impl std::fmt::Display) -> Self {
        Error::Io { path: path.as_ref().display().to_string(), msg: msg.to_string() }
    }
}
