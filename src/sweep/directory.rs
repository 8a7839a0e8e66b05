//! The sweep directory: created or reopened, locked for the session, and held to the study and
//! the command-line PETSc options of its first session (`study.toml`, `sweep.toml`).

use crate::error::{Error, Result};
use crate::io::rundir;
use std::path::Path;

/// Creates or reopens the sweep directory (rank 0) and locks it for this session: a directory
/// of another study, of the same study with other command-line PETSc options (`petsc`), or one
/// that is not a sweep's, is refused untouched. The study file and the options are written at
/// the first session (atomically, each only when absent: a later session rewrites neither).
pub(super) fn open_dir(root: &Path, text: &str, petsc: &[String], is_root: bool) -> Result<rundir::RunLock> {
    if is_root {
        let copy = root.join("study.toml");
        match std::fs::read_to_string(&copy) {
            Ok(was) if was != text => {
                return Err(Error::io(
                    root,
                    "holds the sweep of another study (its study.toml differs from the study file given): \
                     choose another --out",
                ))
            }
            Ok(_) => {
                same_options(root, petsc)?;
            }
            Err(_) if root.is_dir() && std::fs::read_dir(root).map_or(true, |mut d| d.next().is_some()) => {
                return Err(Error::io(root, "exists, is not empty and is not a sweep directory: choose another --out"))
            }
            Err(_) => std::fs::create_dir_all(root).map_err(|e| Error::io(root, format!("cannot create: {e}")))?,
        }
    }
    let lock = rundir::lock(root, is_root)?;
    if is_root {
        // Again with the lock held (a session may have ended between the look above and the
        // lock); study.toml before sweep.toml, so that a directory with a study.toml is a sweep's.
        let copy = root.join("study.toml");
        if !copy.exists() {
            rundir::write_text_atomically(&copy, text)?;
        }
        if !same_options(root, petsc)? {
            let record = SweepRecord { petsc: petsc.to_vec() };
            let path = root.join(SweepRecord::FILE);
            let toml = toml::to_string(&record).map_err(|e| Error::io(&path, e))?;
            rundir::write_text_atomically(
                &path,
                &format!("# the PETSc options (`-- OPTIONS`) of every session of this sweep\n{toml}"),
            )?;
        }
    }
    Ok(lock)
}

/// What a sweep directory records of the command line (`sweep.toml`): its `-- PETSC OPTIONS`,
/// which every session must repeat, so that every case of the sweep — run, resumed, or skipped
/// as complete — runs with the same options.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
struct SweepRecord {
    petsc: Vec<String>,
}

impl SweepRecord {
    const FILE: &'static str = "sweep.toml";
}

/// Whether the sweep directory `root` records command-line PETSc options (false: none yet, at
/// the first session, or a sweep of an earlier version, which did not record them); an error if
/// they are not `petsc`.
fn same_options(root: &Path, petsc: &[String]) -> Result<bool> {
    let path = root.join(SweepRecord::FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(Error::io(&path, e)),
    };
    let was: SweepRecord = toml::from_str(&text).map_err(|e| Error::io(&path, e.message().to_string()))?;
    if was.petsc != petsc {
        let show = |o: &[String]| if o.is_empty() { "none".to_string() } else { format!("`{}`", o.join(" ")) };
        return Err(Error::io(
            root,
            format!(
                "this sweep's cases run with the PETSc options (`-- OPTIONS`) {} (its {}), this session was given {}: \
                 every case of a sweep runs with the same options — give the same ones, or choose another --out",
                show(&was.petsc),
                SweepRecord::FILE,
                show(petsc)
            ),
        ));
    }
    Ok(true)
}
