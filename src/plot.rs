//! `poroplast plot`: the run's figures, drawn by `scripts/plot_run.py` (matplotlib; no ParaView,
//! no display). The binary only finds the script and a Python, and passes the arguments on: one
//! command to remember, printed at the end of every run.

use crate::error::{Error, Result};
use std::os::unix::process::ExitStatusExt;
use std::path::PathBuf;
use std::process::Command;

/// The script, relative to the repository root.
const SCRIPT: &str = "scripts/plot_run.py";

/// Runs `python3 scripts/plot_run.py ARGS` (the Python from `$POROPLAST_PYTHON`, default
/// `python3`), with `$POROPLAST_BIN` this executable; returns its exit code.
pub fn plot(args: &[String]) -> Result<i32> {
    let script = script()?;
    let python = std::env::var_os("POROPLAST_PYTHON").unwrap_or_else(|| "python3".into());
    let mut cmd = Command::new(&python);
    cmd.arg(&script).args(args);
    if let Ok(exe) = std::env::current_exe() {
        cmd.env("POROPLAST_BIN", exe);
    }
    let status = cmd.status().map_err(|e| {
        Error::System(format!("cannot start {python:?} for {} ({e}): poroplast plot needs Python 3 with numpy, h5py and matplotlib (ci/setup.sh installs them)", script.display()))
    })?;
    Ok(status.code().unwrap_or_else(|| 128 + status.signal().unwrap_or(0)))
}

/// `$POROPLAST_SCRIPTS/plot_run.py`, else the script beside the sources this binary was built
/// from, else beside the executable's repository (`target/release/poroplast` → `scripts/`).
fn script() -> Result<PathBuf> {
    let mut tried = Vec::new();
    if let Some(dir) = std::env::var_os("POROPLAST_SCRIPTS") {
        tried.push(PathBuf::from(dir).join("plot_run.py"));
    }
    tried.push(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(SCRIPT));
    if let Ok(exe) = std::env::current_exe() {
        if let Some(root) = exe.parent().and_then(|d| d.parent()).and_then(|d| d.parent()) {
            tried.push(root.join(SCRIPT));
        }
    }
    tried.iter().find(|p| p.is_file()).cloned().ok_or_else(|| {
        let list: Vec<String> = tried.iter().map(|p| p.display().to_string()).collect();
        Error::System(format!(
            "poroplast plot runs {SCRIPT} of the poroplast sources, and found it at none of {}: set POROPLAST_SCRIPTS to the \
             sources' scripts/ directory",
            list.join(", ")
        ))
    })
}
