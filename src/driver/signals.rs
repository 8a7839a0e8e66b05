//! Stop requests: SIGTERM, SIGINT and SIGUSR1 (which `mpirun` forwards to every rank) set a
//! flag; the time loop asks all ranks at each step boundary, writes a checkpoint and stops. A
//! second signal before that ends the process at once.

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
        let err = |sig: i32, e: std::io::Error| Error::Solver(format!("cannot catch signal {sig}: {e}"));
        for sig in SIGNALS {
            // A second signal while the first is pending ends the process at once (an
            // impatient Ctrl-C): exit code 128 + signal, what a shell reports for a kill by it.
            // (Registered first: it must see the flag before this signal sets it.)
            let id = signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, Arc::clone(&flag))
                .map_err(|e| err(sig, e))?;
            ids.push(id);
            ids.push(signal_hook::flag::register(sig, Arc::clone(&flag)).map_err(|e| err(sig, e))?);
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
