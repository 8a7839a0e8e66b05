//! What a run says ([`Voice`]): its log lines on rank 0's standard output at the level the run
//! was asked for, and warnings on standard error at every level.

use super::args::Log;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// The run's communicator and how much it prints.
#[derive(Clone, Copy)]
pub(super) struct Voice<'w> {
    world: &'w SimpleCommunicator,
    log: Log,
}

impl<'w> Voice<'w> {
    pub(crate) fn new(world: &'w SimpleCommunicator, log: Log) -> Voice<'w> {
        Voice { world, log }
    }

    pub(crate) fn world(&self) -> &'w SimpleCommunicator {
        self.world
    }

    pub(crate) fn rank0(&self) -> bool {
        self.world.rank() == 0
    }

    /// Whether the per-step progress lines print.
    pub(crate) fn steps(&self) -> bool {
        self.log == Log::Steps
    }

    /// A log line (rank 0; nothing when silent).
    pub(crate) fn say(&self, s: &str) {
        if self.rank0() && self.log != Log::Silent {
            crate::console::line(s);
        }
    }

    /// A warning that `-q` does not silence (rank 0, standard error).
    pub(crate) fn warn(&self, s: &str) {
        if self.rank0() {
            eprintln!("poroplast: warning: {s}");
        }
    }
}
