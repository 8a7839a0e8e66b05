//! The standard output of the commands (the run log, `check`'s report, `scenes`, `show`). A
//! reader that goes away (`poroplast check my.toml | head -1`) closes the pipe: the write fails
//! with EPIPE, and `println!` would panic. Here a failed write ends the output quietly instead —
//! a run goes on with its files, a listing ends with exit code 0.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set once a write to standard output has failed: nothing more is written.
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Writes `text` to standard output as it is, flushed (a closed output is ignored).
pub fn print(text: &str) {
    if CLOSED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    if out.write_all(text.as_bytes()).and_then(|()| out.flush()).is_err() {
        CLOSED.store(true, Ordering::Relaxed);
    }
}

/// Writes `line` and a line break to standard output (a closed output is ignored).
pub fn line(line: &str) {
    print(&format!("{line}\n"));
}
