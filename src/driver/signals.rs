//! Stop requests: SIGTERM, SIGINT and SIGUSR1 (which `mpirun` forwards to every rank) set a
//! flag; the time loop asks all ranks at each step boundary, writes a checkpoint and stops.
//! More signals before then change nothing: a scheduler that signals every process of a job
//! and `mpirun` forwarding the same signal deliver it twice, and that must not cost the
//! checkpoint.

use crate::error::{Error, Result};
use mpi::topology::SimpleCommunicator;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The signals that ask a run to checkpoint and stop.
pub const SIGNALS: [i32; 3] = [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT, signal_hook::consts::SIGUSR1];

pub struct StopRequest {
    flag: Arc<AtomicBool>,
    ids: Vec<signal_hook::SigId>,
}

impl StopRequest {
    /// Catches the stop signals until dropped.
    pub fn install() -> Result<StopRequest> {
        let flag = Arc::new(AtomicBool::new(false));
        let mut ids = Vec::new();
        for sig in SIGNALS {
            let id = signal_hook::flag::register(sig, Arc::clone(&flag))
                .map_err(|e| Error::System(format!("cannot catch signal {sig}: {e}")))?;
            ids.push(id);
        }
        Ok(StopRequest { flag, ids })
    }

    /// Whether any rank has been asked to stop (collective: every rank gets the same answer).
    pub fn requested(&self, world: &SimpleCommunicator) -> bool {
        crate::parallel::any(world, self.flag.load(Ordering::Relaxed))
    }
}

impl Drop for StopRequest {
    fn drop(&mut self) {
        for id in self.ids.drain(..) {
            signal_hook::low_level::unregister(id);
        }
    }
}
