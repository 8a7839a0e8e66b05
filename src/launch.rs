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
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The command line that runs `poroplast ARGS` again as this process was run: this executable's
/// absolute path, under `poroplast mpirun -n N` when `ranks` > 1 (so that Ctrl-C stops it
/// cleanly); words with spaces or quotes quoted for a POSIX shell. What a run prints for the user
/// to paste (`resume DIR`, `plot DIR`).
pub(crate) fn command(ranks: usize, args: &[&str]) -> String {
    let exe = std::env::current_exe().map_or_else(|_| "poroplast".to_string(), |p| p.display().to_string());
    let n = ranks.to_string();
    let mut words = vec![exe.as_str()];
    if ranks > 1 {
        words.extend(["mpirun", "-n", &n]);
    }
    words.extend(args);
    words.iter().map(|w| shell_word(w)).collect::<Vec<_>>().join(" ")
}

/// `w` as one word of a POSIX shell: as it is when it holds only safe characters, else in single
/// quotes.
fn shell_word(w: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "/._-+=:,@%".contains(c);
    if !w.is_empty() && w.chars().all(safe) {
        w.to_string()
    } else {
        format!("'{}'", w.replace('\'', "'\\''"))
    }
}

/// The environment variable naming the directory where each rank, once it catches stop
/// signals, leaves a file: until all have, a stop is held back, since a rank still loading would
/// die of SIGUSR1's default action ("exited on signal 10") instead of stopping cleanly.
const READY_DIR: &str = "POROPLAST_READY_DIR";

/// How long a stop waits for ranks that never say they are ready (on other nodes, whose temporary
/// directory is not this one's).
const READY_WAIT: Duration = Duration::from_secs(10);

/// Says this rank catches stop signals (a file named after its pid in `$POROPLAST_READY_DIR`,
/// when a launcher set it). Quiet if it cannot: the launcher then waits its 10 s.
pub fn mark_ready() {
    if let Some(dir) = std::env::var_os(READY_DIR) {
        let _ = std::fs::write(PathBuf::from(dir).join(std::process::id().to_string()), b"");
    }
}

/// Runs `poroplast <command>` as `mpirun -n np <mpirun_args> <this executable> <command>`
/// (`mpirun` from `$POROPLAST_MPIRUN`, default `mpirun` in the PATH) until it ends, passing stop
/// signals on as described above once every rank catches them; returns its exit code (128 + the
/// signal if it was killed).
pub fn mpirun(np: u32, mpirun_args: &[String], command: &[String]) -> Result<i32> {
    let exe = std::env::current_exe().map_err(|e| Error::System(format!("cannot find this executable: {e}")))?;
    let launcher = std::env::var_os("POROPLAST_MPIRUN").unwrap_or_else(|| "mpirun".into());
    let ready = std::env::temp_dir().join(format!("poroplast-launch-{}", std::process::id()));
    std::fs::create_dir_all(&ready).map_err(|e| Error::io(&ready, e))?;
    // Caught from here on: a signal before the ranks are ready is passed on once they are.
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGUSR1])
        .map_err(|e| Error::System(format!("cannot catch SIGINT, SIGTERM and SIGUSR1: {e}")))?;
    let child = Command::new(&launcher)
        .arg("-n")
        .arg(np.to_string())
        .args(mpirun_args)
        .arg(exe)
        .args(command)
        .env(READY_DIR, &ready)
        // In the background of a terminal, mpirun must not read it (it would be stopped).
        .stdin(Stdio::null())
        .process_group(0)
        .spawn()
        .map_err(|e| Error::System(format!("cannot start {launcher:?}: {e}")));
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            let _ = std::fs::remove_dir_all(&ready);
            return Err(e);
        }
    };
    let pid = child.id().to_string();
    let handle = signals.handle();
    let dir = ready.clone();
    let forward = std::thread::spawn(move || {
        for _ in signals.forever() {
            wait_ready(&dir, np as usize);
            // No unsafe `kill(2)` here: the kill(1) of every system.
            let _ = Command::new("kill").args(["-USR1", &pid]).status();
        }
    });
    let status = child.wait().map_err(|e| Error::System(format!("waiting for {launcher:?}: {e}")));
    handle.close();
    let _ = forward.join();
    let _ = std::fs::remove_dir_all(&ready);
    let status = status?;
    Ok(status.code().unwrap_or_else(|| 128 + status.signal().unwrap_or(0)))
}

/// Until `np` ranks have marked themselves ready in `dir`, or [`READY_WAIT`] has passed.
fn wait_ready(dir: &Path, np: usize) {
    let start = Instant::now();
    while start.elapsed() < READY_WAIT {
        if std::fs::read_dir(dir).map_or(0, |d| d.count()) >= np {
            return;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_paste_into_a_shell() {
        assert_eq!(shell_word("runs/x-1"), "runs/x-1");
        assert_eq!(shell_word("my runs/x"), "'my runs/x'");
        assert_eq!(shell_word("it's"), "'it'\\''s'");
        let exe = std::env::current_exe().unwrap().display().to_string();
        assert_eq!(command(1, &["resume", "runs/a"]), format!("{} resume runs/a", shell_word(&exe)));
        assert_eq!(command(2, &["resume", "runs/a"]), format!("{} mpirun -n 2 resume runs/a", shell_word(&exe)));
    }
}
