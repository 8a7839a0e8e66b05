//! Stop requests: SIGTERM, SIGINT and SIGUSR1 (which `mpirun` forwards to every rank) set a
//! flag; the time loop asks all ranks at each step boundary, writes a checkpoint and stops.
//! More signals before then change nothing: a scheduler that signals every process of a job
//! and `mpirun` forwarding the same signal deliver it twice, and that must not cost the
//! checkpoint.
//!
//! `main` installs a request before MPI starts, for the whole process: a signal during the
//! set-up (mesh, partition, PETSc, settling, the first step) stops the command at the next of
//! the set-up's checks (`stop_in_setup`) with nothing written.
//!
//! The flag is the process's, not a request's: a request installed while another is (a sweep's
//! case, inside the sweep's own request) sees a signal that came before it, so a signal during a
//! case's set-up stops the case at its first step boundary.

use crate::error::{Error, Result};
use mpi::topology::SimpleCommunicator;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

/// The signals that ask a run to checkpoint and stop.
pub(crate) const SIGNALS: [i32; 3] =
    [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT, signal_hook::consts::SIGUSR1];

/// Set by a stop signal caught by any request of this process; never cleared (a process asked
/// to stop stays asked).
fn flag() -> &'static Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

pub struct StopRequest {
    ids: Vec<signal_hook::SigId>,
}

impl StopRequest {
    /// Catches the stop signals until dropped (while another request is installed too, each
    /// signal is caught once, by both, into the process's flag).
    pub fn install() -> Result<StopRequest> {
        let mut ids = Vec::new();
        for sig in SIGNALS {
            let id = signal_hook::flag::register(sig, Arc::clone(flag()))
                .map_err(|e| Error::System(format!("cannot catch signal {sig}: {e}")))?;
            ids.push(id);
        }
        Ok(StopRequest { ids })
    }

    /// Whether this process has been asked to stop (not collective).
    fn pending(&self) -> bool {
        flag().load(Ordering::Relaxed)
    }

    /// Whether any rank has been asked to stop (collective: every rank gets the same answer).
    pub(crate) fn requested(&self, world: &SimpleCommunicator) -> bool {
        crate::parallel::any(world, self.pending())
    }
}

/// What a run stopped during its set-up has done.
pub(crate) const NOTHING_WRITTEN: &str = "nothing was written; run the command again";

/// Stops a command asked to stop during its set-up, before it has written anything (collective:
/// every rank asks at the same point). `what`: what has not been done, for the message.
pub(crate) fn stop_in_setup(world: &SimpleCommunicator, what: &str) -> Result<()> {
    if crate::parallel::any(world, flag().load(Ordering::Relaxed)) {
        return Err(Error::StoppedInSetup(format!("stopped by a signal during the set-up: {what}")));
    }
    Ok(())
}

impl Drop for StopRequest {
    fn drop(&mut self) {
        for id in self.ids.drain(..) {
            signal_hook::low_level::unregister(id);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sweeps_request_passes_a_signal_to_a_case_installed_after_it() {
        // The sweep's request is installed; a signal comes while a case is being set up; the
        // case's run installs its own after its first step: that one must see the signal.
        let sweep = StopRequest::install().unwrap();
        assert!(!sweep.pending());
        signal_hook::low_level::raise(signal_hook::consts::SIGUSR1).unwrap();
        let case = StopRequest::install().unwrap();
        assert!(case.pending());
        drop(case);
        assert!(sweep.pending(), "the case's request took the sweep's signal with it");
    }
}
