//! `poroplast mpirun`: a command on N ranks under Open MPI's `mpirun`, stopped the way one
//! process is. Open MPI 4.1's `mpirun` answers SIGINT (Ctrl-C) and SIGTERM with its own exit
//! status 1, sends the ranks SIGTERM and kills them 1 s later, and cannot be told to forward
//! SIGINT; it does forward SIGUSR1 and then exits with the ranks' code. So `mpirun` runs in a
//! process group of its own (a terminal's Ctrl-C reaches only this launcher), and SIGINT,
//! SIGTERM and SIGUSR1 are passed to it as SIGUSR1: the ranks checkpoint and stop, and the exit
//! code is theirs (75), as for a run on one rank.

use crate::error::{Error, Result};
use signal_hook::consts::{SIGINT, SIGTERM, SIGUSR1};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::process::{Command, Stdio};

/// Runs `poroplast <command>` as `mpirun -n np <mpirun_args> <this executable> <command>`
/// (`mpirun` from `$POROPLAST_MPIRUN`, default `mpirun` in the PATH) until it ends, passing stop
/// signals on as described above; returns its exit code (128 + the signal if it was killed).
pub fn mpirun(np: u32, mpirun_args: &[String], command: &[String]) -> Result<i32> {
    let exe = std::env::current_exe().map_err(|e| Error::System(format!("cannot find this executable: {e}")))?;
    let launcher = std::env::var_os("POROPLAST_MPIRUN").unwrap_or_else(|| "mpirun".into());
    // Caught from here on: a signal before mpirun has started is passed on once it has.
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGUSR1])
        .map_err(|e| Error::System(format!("cannot catch SIGINT, SIGTERM and SIGUSR1: {e}")))?;
    let mut child = Command::new(&launcher)
        .arg("-n")
        .arg(np.to_string())
        .args(mpirun_args)
        .arg(exe)
        .args(command)
        // In the background of a terminal, mpirun must not read it (it would be stopped).
        .stdin(Stdio::null())
        .process_group(0)
        .spawn()
        .map_err(|e| Error::System(format!("cannot start {launcher:?}: {e}")))?;
    let pid = child.id().to_string();
    let handle = signals.handle();
    let forward = std::thread::spawn(move || {
        for _ in signals.forever() {
            // No unsafe `kill(2)` here: the kill(1) of every system.
            let _ = Command::new("kill").args(["-USR1", &pid]).status();
        }
    });
    let status = child.wait().map_err(|e| Error::System(format!("waiting for {launcher:?}: {e}")));
    handle.close();
    let _ = forward.join();
    let status = status?;
    Ok(status.code().unwrap_or_else(|| 128 + status.signal().unwrap_or(0)))
}
