//! `poroplast sweep STUDY.toml [--ranks-per-case k] [--out DIR] [--cases-dir DIR]`: the cases of
//! a study (a base scene and a grid or list of `--set` overrides, or a list of cases with their
//! own scenes, see `study`) run under one `mpirun -n N`.
//!
//! - The world splits into N/k groups of k consecutive ranks; each group runs one case at a
//!   time on its own communicator, through the driver's public entry points
//!   ([`driver::run`](crate::driver::run), [`driver::resume`](crate::driver::resume)), which
//!   initialise PETSc on that communicator with the case's options and finalise it after: no
//!   PETSc option, object or log stage passes from a case to the next.
//! - Cases are handed out as groups become free (`schedule`): a group's leader claims the
//!   next case of a fixed order (longest first when `estimate_from` gives costs) by creating
//!   its claim file exclusively, and tells its group. Nothing waits on another group: the
//!   world meets only at the start and at the end. (A coordinating rank answering requests
//!   would have to be one that runs no case, or a thread, since world rank 0 runs cases too;
//!   rsmpi 0.8 has no one-sided atomics. The file system the run directories need anyway is
//!   the coordinator.)
//! - The cases live in a case store (`store`): each in a run directory named after what it
//!   runs (scene, overrides, PETSc options), with `case.toml`, its outcome, once it has ended.
//!   The store is the sweep directory's `cases/`, or one that several sweeps share
//!   (`--cases-dir`): a case any of them has completed is not run again.
//! - The sweep directory (`--out`, default `runs/sweep-<study>-<UTC time>`) holds `study.toml`
//!   (the study file) and `sweep.toml` (the command line's `-- PETSC OPTIONS`), both written at
//!   the first session, which a later session must match; `summary.csv` (`summary`: a row per
//!   case, with the observables of `io::observable`), `claims/` (this
//!   session's) and, by default, the store `cases/`.
//! - Every case's overrides are read into its scene before anything is written: an unknown key
//!   (or a value of the wrong type) is the sweep's error, naming the case. A case that fails
//!   later (a value out of range, its set-up, a solve that does not converge) is recorded with
//!   its error
//!   line; the group goes on to the next case.
//! - Resuming: the same command with `--out DIR`. Complete cases are skipped; a case with a run
//!   directory and no outcome (killed, or stopped by a signal) continues from its last
//!   checkpoint ([`driver::resume`](crate::driver::resume)); a failed case runs again. A sweep
//!   directory of an earlier version (`cases/NNN_<overrides>/`) has its cases moved into the
//!   store first (`store::adopt_legacy`).
//! - A stop signal (SIGTERM, SIGINT, SIGUSR1) makes running cases checkpoint and stop (the
//!   driver's own handling), and every group stop before its next case; exit code 75 then.
//!   A signal that arrives while a case is being set up, before its time loop, is the
//!   process's (src/driver/signals.rs): the case stops at the end of its first step.
//! - summary.csv is rewritten by a group's leader after each case and by world rank 0 at the
//!   end, in case order, so a killed sweep leaves a usable partial one.
//!
//! Where things are: [`sweep()`] (in `run`) is the course of a sweep, from the study file to the
//! world's outcome; `group` a group of ranks claiming and running cases; `plan` the cases as the
//! store knows them, and summary.csv written from their states; `directory` the sweep directory,
//! its lock and its record of the session's options; `args` the command line ([`SweepArgs`]).

mod args;
pub(crate) mod counters;
mod directory;
pub mod find;
mod group;
mod plan;
mod run;
pub(crate) mod schedule;
pub(crate) mod store;
pub(crate) mod study;
pub(crate) mod summary;

pub use args::SweepArgs;
pub use run::sweep;
