//! What `poroplast run` was asked ([`RunArgs`]) and how much a run prints ([`Log`]).

use std::path::PathBuf;

/// What `poroplast run` was asked to do.
#[derive(Debug, Clone)]
pub struct RunArgs {
    pub scene: String,
    /// `--set KEY=VALUE` overrides of scene values.
    pub set: Vec<String>,
    pub out: Option<PathBuf>,
    pub force: bool,
    pub petsc: Vec<String>,
    /// What the run prints on rank 0.
    pub log: Log,
}

/// What a run prints on standard output (rank 0). Warnings (standard error) print at every level.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Log {
    /// The scene's notes, the set-up, a progress line per step, the summary.
    Steps,
    /// `-q`: all of it but the per-step progress lines.
    Quiet,
    /// Nothing but warnings: a sweep's case (the sweep tells the scene's notes once, and a
    /// line per case).
    Silent,
}
