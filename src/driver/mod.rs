//! One run: scene → PETSc → mesh → partition → problem → TS loop with output, in a run
//! directory holding the resolved scene, the PETSc options, `history.csv`, `fields.h5/.xdmf`
//! and `timings.txt`. Everything that can fail on bad input is checked before the run directory
//! is touched, so a failed start never damages an earlier run's results.
//!
//! One concept a module: the entry points `run` and `resume` (`entry`) and what they are asked
//! (`args`); the run and its time
//! loop (`run`), built from its pieces by the set-up (`setup`): the steps (`step`: the time
//! stepper, the state between steps and the schedule), the outputs (`output`), the checkpoints
//! (`checkpoint`) and what the run prints (`voice`), the tools at set-up (`tool_setup`); the `check` command (`check`); where the
//! loop stands (`progress`), the step controller (`schedule`) and the step rate it acts on
//! (`rate`), the state between steps and the checkpoint files (`state`), what the scene
//! resolved to and its expected accuracy (`resolved`), the run record `run.toml` (`record`),
//! the run summary `summary.toml` (`summary`), with the protocol's holds (`holds`) and the
//! liquid test on them (`liquid_test`), and stop signals (`signals`).

mod args;
mod check;
mod checkpoint;
mod entry;
mod holds;
mod liquid_test;
mod output;
mod progress;
mod rate;
mod record;
mod resolved;
mod run;
mod schedule;
mod setup;
pub mod signals;
pub(crate) mod state;
mod step;
mod summary;
mod tool_setup;
mod voice;

pub use args::{Log, RunArgs};
pub use check::check;
pub(crate) use entry::tell_notes;
pub use entry::{resume, run};
pub use run::{EXIT_STOPPED, EXIT_STOPPED_IN_SETUP};
