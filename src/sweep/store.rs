//! The case store: where the cases of sweeps live, and how a case is known again.
//!
//! A case is what it runs — its [`Signature`]: its scene (a shipped scene's name or a file's
//! absolute path, and a hash of the scene's text), its overrides (the study's `set`, then its
//! own) and its PETSc options (the study's, then the command line's). Its run directory in the
//! store is named after the signature's hash (`<scene>__<overrides>-<16 hex digits>`), so that
//! any sweep that asks for the same case finds it there: complete (its `case.toml` says ok, for
//! this signature: skipped), interrupted (a run directory without an outcome: resumed from its
//! checkpoint) or failed (run again). The store is the sweep directory's `cases/`, or a
//! directory several sweeps share (`--cases-dir`): a study then runs only the cases no other
//! study has run.
//!
//! Two sweeps sharing a store may reach the same case at once: a group's leader holds the
//! case's claim lock (`CASE/.claim`, an `flock`) while it runs it; a leader that finds it held
//! waits for it, then finds the case complete.
//!
//! Sweep directories of earlier versions (`cases/NNN_<overrides>/`, whose `case.toml` holds the
//! overrides only) are moved into this layout when a sweep continues them ([`adopt_legacy`]).

use super::study::{Case, Study};
use crate::error::{Error, Result};
use crate::hash::Fnv;
use crate::io::rundir;
use crate::scene::BUILTIN;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a case runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct Signature {
    /// A shipped scene's name, or the scene file's absolute path.
    pub(crate) scene: String,
    /// FNV-1a hash of the scene's text (16 hex digits): an edited scene file is another case.
    pub(crate) scene_text: String,
    /// Every override, the study's first.
    pub(crate) set: Vec<String>,
    /// Every PETSc option, the study's first.
    pub(crate) petsc: Vec<String>,
}

impl Signature {
    /// The signature of a case of `scene` (a file, or a shipped scene's name) with these
    /// overrides and options.
    pub(crate) fn of(scene: &str, set: Vec<String>, petsc: Vec<String>) -> Result<Signature> {
        let path = Path::new(scene);
        let (scene, text) = if path.is_file() {
            let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
            let abs = std::fs::canonicalize(path).map_err(|e| Error::io(path, e))?;
            (abs.display().to_string(), text)
        } else if let Some((name, text)) = BUILTIN.iter().find(|(n, _)| *n == scene) {
            (name.to_string(), text.to_string())
        } else {
            return Err(Error::Sweep(format!("{scene}: no such scene file, and not a shipped scene")));
        };
        let mut h = Fnv::new();
        h.field(text.as_bytes());
        Ok(Signature { scene, scene_text: h.hex(), set, petsc })
    }

    /// The case's key: a hash of the whole signature (16 hex digits).
    pub(crate) fn key(&self) -> String {
        let mut h = Fnv::new();
        h.field(b"poroplast case 1");
        h.field(self.scene.as_bytes());
        h.field(self.scene_text.as_bytes());
        for list in [&self.set, &self.petsc] {
            h.field(&(list.len() as u64).to_le_bytes());
            for s in list {
                h.field(s.as_bytes());
            }
        }
        h.hex()
    }
}

/// The run directory of `case` (with signature `sig`) in the store `store`: a readable part —
/// its scene's stem and its own overrides, at most 80 characters — and the signature's key.
pub(crate) fn case_dir(store: &Path, case: &Case, sig: &Signature) -> PathBuf {
    let scene = case.own_scene.as_deref().unwrap_or(&case.scene);
    store.join(format!("{}-{}", slug(Some(stem(scene)), case), sig.key()))
}

/// A scene argument's file stem (a shipped scene's name is its own).
fn stem(scene: &str) -> String {
    Path::new(scene).file_stem().map(|x| x.to_string_lossy().into_owned()).unwrap_or_else(|| scene.to_string())
}

/// The readable part of a case's directory name: `scene` and the case's own overrides
/// (`KEY-VALUE`), joined by `__`, other characters than `[A-Za-z0-9_.-]` as `_`, at most 80.
fn slug(scene: Option<String>, case: &Case) -> String {
    scene
        .into_iter()
        .chain(case.pairs().iter().map(|(k, v)| format!("{k}-{v}")))
        .collect::<Vec<_>>()
        .join("__")
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') { c } else { '_' })
        .take(80)
        .collect()
}

/// The outcome of a case that ended (`case.toml` in its run directory).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct CaseRecord {
    /// "ok" or "failed".
    pub(crate) status: String,
    /// The error line of a failed case.
    #[serde(default)]
    pub(crate) error: String,
    pub(crate) scene: String,
    pub(crate) scene_text: String,
    pub(crate) set: Vec<String>,
    pub(crate) petsc: Vec<String>,
    /// The counters of timings.txt (`wall_s` its total; `counters::COUNTERS`), of an ok case.
    #[serde(default)]
    pub(crate) counters: BTreeMap<String, f64>,
}

/// The file of a case's outcome.
pub(crate) const RECORD: &str = "case.toml";

impl CaseRecord {
    /// The outcome of the case `sig` whose run ended in `dir` (`error`: its error, if it
    /// failed), with the counters of its timings.txt — of an ok case only: a failed run may have
    /// ended before writing them, and those in the directory would be an earlier run's.
    pub(crate) fn of(dir: &Path, sig: &Signature, error: Option<String>) -> CaseRecord {
        let counters = if error.is_none() { super::counters::counters(dir) } else { BTreeMap::new() };
        CaseRecord {
            status: if error.is_some() { "failed".into() } else { "ok".into() },
            // One line: the first of the message.
            error: error.map(|e| e.lines().next().unwrap_or_default().to_string()).unwrap_or_default(),
            scene: sig.scene.clone(),
            scene_text: sig.scene_text.clone(),
            set: sig.set.clone(),
            petsc: sig.petsc.clone(),
            counters,
        }
    }

    /// The record in `dir`, if there is one and it is of the case `sig`.
    pub(crate) fn read(dir: &Path, sig: &Signature) -> Option<CaseRecord> {
        let text = std::fs::read_to_string(dir.join(RECORD)).ok()?;
        let r: CaseRecord = toml::from_str(&text).ok()?;
        (r.signature() == *sig).then_some(r)
    }

    /// Writes the record into `dir` (atomically: a reader finds the whole record or none).
    pub(crate) fn write(&self, dir: &Path) -> Result<()> {
        let path = dir.join(RECORD);
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let text = toml::to_string(self).map_err(|e| Error::io(&path, e))?;
        rundir::write_text_atomically(&path, &format!("# the outcome of this case of a poroplast sweep\n{text}"))
    }

    pub(crate) fn signature(&self) -> Signature {
        Signature {
            scene: self.scene.clone(),
            scene_text: self.scene_text.clone(),
            set: self.set.clone(),
            petsc: self.petsc.clone(),
        }
    }

    pub(crate) fn ok(&self) -> bool {
        self.status == "ok"
    }
}

/// The claim lock of a case, held by the leader of the group that runs it (released on drop,
/// or when the process ends, however it ends).
pub(crate) struct Claim {
    _held: Option<std::fs::File>,
}

/// The claim file in a case's directory.
const CLAIM: &str = ".claim";

/// Takes the claim lock of the case directory `dir` (created if missing); if another process
/// holds it, calls `waiting` and waits for it. On a file system without locks the case runs
/// unguarded (with a warning), as a run does.
pub(crate) fn claim(dir: &Path, waiting: impl FnOnce()) -> Result<Claim> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, format!("cannot create ({e})")))?;
    let path = dir.join(CLAIM);
    let f = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
        .map_err(|e| Error::io(&path, format!("cannot create ({e})")))?;
    match f.try_lock() {
        Ok(()) => Ok(Claim { _held: Some(f) }),
        Err(std::fs::TryLockError::WouldBlock) => {
            waiting();
            f.lock().map_err(|e| Error::io(&path, e))?;
            Ok(Claim { _held: Some(f) })
        }
        Err(std::fs::TryLockError::Error(e)) => {
            eprintln!(
                "poroplast: warning: {}: cannot lock ({e}); another sweep sharing this case would not be kept out",
                path.display()
            );
            Ok(Claim { _held: None })
        }
    }
}

/// A case's record as sweeps of earlier versions wrote it (the overrides only).
#[derive(Deserialize)]
struct LegacyRecord {
    status: String,
    #[serde(default)]
    error: String,
    set: Vec<String>,
    #[serde(default)]
    counters: BTreeMap<String, f64>,
}

/// A case's run directory name in sweep directories of earlier versions: its index, its own
/// scene's stem if it has one, and its overrides (`003_material.mu-10__nu-0.3`).
fn legacy_dir_name(case: &Case) -> String {
    let slug = slug(case.own_scene.as_deref().map(stem), case);
    if slug.is_empty() {
        format!("{:03}_base", case.index)
    } else {
        format!("{:03}_{slug}", case.index)
    }
}

/// Moves the cases of a sweep directory `root` of an earlier version (`cases/NNN_<overrides>/`)
/// to their places in the store (`dirs`, by case), and gives the completed ones a record with
/// their signature (`sigs`): a completed case stays complete, an interrupted one is resumed.
/// Run by rank 0 with the sweep directory's lock held; safe to interrupt (the record is
/// rewritten before its directory moves, in one rename). Returns how many moved.
pub(crate) fn adopt_legacy(root: &Path, study: &Study, dirs: &[PathBuf], sigs: &[Signature]) -> Result<usize> {
    let mut moved = 0;
    for ((case, dir), sig) in study.cases.iter().zip(dirs).zip(sigs) {
        let old = root.join("cases").join(legacy_dir_name(case));
        if !old.is_dir() || dir.exists() || old == *dir {
            continue;
        }
        match std::fs::read_to_string(old.join(RECORD)) {
            Ok(text) => {
                if let Ok(r) = toml::from_str::<LegacyRecord>(&text) {
                    if r.set != sig.set {
                        continue; // another case's (not this study's)
                    }
                    let mut record = CaseRecord::of(&old, sig, (r.status != "ok").then(|| r.error.clone()));
                    record.counters = r.counters;
                    record.write(&old)?;
                } else if toml::from_str::<CaseRecord>(&text).map_or(true, |r| r.signature() != *sig) {
                    continue;
                }
            }
            Err(_) if old.join("run.toml").exists() => {} // interrupted: resumed from its checkpoint
            Err(_) => continue,
        }
        if let Some(parent) = dir.parent() {
            std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        }
        std::fs::rename(&old, dir).map_err(|e| {
            Error::io(&old, format!("cannot move this case of an earlier sweep to {} ({e})", dir.display()))
        })?;
        moved += 1;
    }
    Ok(moved)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study(text: &str) -> Study {
        Study::parse(Path::new("/nonexistent/s.toml"), text).unwrap()
    }

    #[test]
    fn a_case_is_what_it_runs() {
        let sig = |set: &[&str], petsc: &[&str]| {
            Signature::of(
                "reference_axi",
                set.iter().map(|s| s.to_string()).collect(),
                petsc.iter().map(|s| s.to_string()).collect(),
            )
            .unwrap()
        };
        let a = sig(&["material.mu=10"], &[]);
        assert_eq!(a.key(), sig(&["material.mu=10"], &[]).key());
        assert_eq!(a.key().len(), 16);
        assert_ne!(a.key(), sig(&["material.mu=10.0"], &[]).key());
        assert_ne!(a.key(), sig(&[], &["material.mu=10"]).key(), "an override is not an option");
        assert_ne!(a.key(), sig(&["material.mu=10"], &["-snes_rtol", "1e-9"]).key());
        let other = Signature::of("reference", a.set.clone(), vec![]).unwrap();
        assert_ne!(a.key(), other.key());
        assert!(Signature::of("no_such_scene", vec![], vec![]).is_err());
        let s = study("scene = \"reference_axi\"\n[[case]]\nset = [\"material.mu=10\", \"a=[1, 2]\"]\n");
        let dir = case_dir(Path::new("/s"), &s.cases[0], &a);
        let name = dir.file_name().unwrap().to_string_lossy().into_owned();
        assert_eq!(name, format!("reference_axi__material.mu-10__a-_1__2_-{}", a.key()));
    }

    #[test]
    fn records_match_their_signature_only() {
        let dir = std::env::temp_dir().join(format!("poroplast-record-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("timings.txt"), "total = 12.5\nsteps = 7\n").unwrap();
        let sig = Signature::of("cryer", vec!["a=1".into()], vec![]).unwrap();
        CaseRecord::of(&dir, &sig, None).write(&dir).unwrap();
        let r = CaseRecord::read(&dir, &sig).unwrap();
        assert!(r.ok() && r.counters.get("wall_s") == Some(&12.5) && r.counters.get("steps") == Some(&7.0));
        let mut other = sig.clone();
        other.petsc.push("-ksp_rtol".into());
        assert!(CaseRecord::read(&dir, &other).is_none());
        // A failed rerun does not show the timings.txt of the run before it.
        let failed = CaseRecord::of(&dir, &sig, Some("diverged\nmore".into()));
        assert!(failed.counters.is_empty() && failed.error == "diverged" && !failed.ok());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn an_earlier_sweeps_cases_move_into_the_store() {
        let root = std::env::temp_dir().join(format!("poroplast-legacy-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let s = study(
            "scene = \"cryer\"\nset = [\"time.t_end=1\"]\n[[case]]\nset = [\"a=1\"]\n[[case]]\nset = [\"a=2\"]\n\
             [[case]]\nset = [\"a=3\"]\n[[case]]\nset = [\"a=4\"]\n",
        );
        let sigs: Vec<Signature> =
            s.cases.iter().map(|c| Signature::of(&c.scene, s.overrides(c), vec![]).unwrap()).collect();
        let store = root.join("cases");
        let dirs: Vec<PathBuf> = s.cases.iter().zip(&sigs).map(|(c, g)| case_dir(&store, c, g)).collect();
        // 0 complete, 1 interrupted, 2 the record of another case, 3 never started.
        let old = |i: usize| store.join(legacy_dir_name(&s.cases[i]));
        assert_eq!(old(1).file_name().unwrap(), "001_a-2");
        for i in 0..3 {
            std::fs::create_dir_all(old(i)).unwrap();
            std::fs::write(old(i).join("run.toml"), "").unwrap();
        }
        let legacy =
            |set: &str| format!("status = \"ok\"\nset = [\"time.t_end=1\", \"{set}\"]\n[counters]\nwall_s = 2.5\n");
        std::fs::write(old(0).join(RECORD), legacy("a=1")).unwrap();
        std::fs::write(old(2).join(RECORD), legacy("a=9")).unwrap();
        assert_eq!(adopt_legacy(&root, &s, &dirs, &sigs).unwrap(), 2);
        let r = CaseRecord::read(&dirs[0], &sigs[0]).unwrap();
        assert!(r.ok() && r.counters.get("wall_s") == Some(&2.5));
        assert!(dirs[1].join("run.toml").exists() && CaseRecord::read(&dirs[1], &sigs[1]).is_none());
        assert!(old(2).is_dir() && !dirs[2].exists() && !dirs[3].exists());
        assert!(!old(0).exists() && !old(1).exists());
        // Again: nothing left to move.
        assert_eq!(adopt_legacy(&root, &s, &dirs, &sigs).unwrap(), 0);
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn a_claim_is_held_by_one_holder() {
        let dir = std::env::temp_dir().join(format!("poroplast-claim-{}", std::process::id()));
        let first = claim(&dir, || panic!("nobody holds it")).unwrap();
        // Another open file description of the same file: as another process's.
        let f = std::fs::OpenOptions::new().write(true).open(dir.join(CLAIM)).unwrap();
        assert!(matches!(f.try_lock(), Err(std::fs::TryLockError::WouldBlock)));
        drop(first);
        assert!(f.try_lock().is_ok());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
