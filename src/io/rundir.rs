//! The run directory: created once per run, refusing to mix a new run into an old one's files.
//!
//! Parallel use: rank 0 does the file-system work (pass `is_root`), then the caller does a barrier
//! before any rank writes into the directory. [`default_run_dir`] reads the clock, so compute the
//! name on rank 0 and broadcast it (or broadcast the seconds and use [`default_run_dir_at`]), lest
//! ranks straddling a second boundary disagree.

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::error::{Error, Result};
// Atomic writes live in `crate::files`; re-exported for the run directory's users.
pub(crate) use crate::files::{write_atomically, write_text_atomically};

/// Prepares `dir` for a run (root rank only; other ranks return `Ok` at once).
///
/// If `dir` exists and is not empty, fails unless `force`, leaving it untouched; with `force` the
/// existing files are kept and those this run writes are overwritten (nothing is deleted).
/// A missing directory is created with its parents.
pub(crate) fn prepare(dir: &Path, force: bool, is_root: bool) -> Result<()> {
    if !is_root {
        return Ok(());
    }
    match std::fs::metadata(dir) {
        Ok(m) if !m.is_dir() => Err(Error::io(dir, "exists and is not a directory; choose another --out")),
        Ok(_) => {
            let mut entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
            if entries.next().is_some() && !force {
                Err(Error::io(
                    dir,
                    "run directory exists and is not empty; pass --force to write into it anyway \
                     (files of the same name are overwritten) or choose another --out",
                ))
            } else {
                Ok(())
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, format!("cannot create: {e}")))
        }
        Err(e) => Err(Error::io(dir, e)),
    }
}

/// The lock file a run holds in its directory while it writes there (left behind, unlocked).
pub(crate) const LOCK_NAME: &str = ".lock";

/// An exclusive lock on a run directory (held by the root rank): a second run or `resume` into
/// the same directory — a job resubmitted while the first still runs — is refused instead of
/// mixing its files with the first's. The operating system releases it when the process ends,
/// however it ends.
pub(crate) struct RunLock {
    _held: Option<std::fs::File>,
}

/// Takes the lock of `dir` (root rank only; the others get an empty one), or says who holds it.
pub(crate) fn lock(dir: &Path, is_root: bool) -> Result<RunLock> {
    use std::io::{Read, Seek, Write};
    if !is_root {
        return Ok(RunLock { _held: None });
    }
    let path = dir.join(LOCK_NAME);
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .read(true)
        .write(true)
        .open(&path)
        .map_err(|e| Error::io(&path, format!("cannot create ({e})")))?;
    match f.try_lock() {
        Ok(()) => {
            let me = format!("pid {} on {}\n", std::process::id(), hostname());
            f.set_len(0)
                .and_then(|()| f.rewind())
                .and_then(|()| f.write_all(me.as_bytes()))
                .map_err(|e| Error::io(&path, e))?;
            Ok(RunLock { _held: Some(f) })
        }
        Err(std::fs::TryLockError::WouldBlock) => {
            let mut holder = String::new();
            let _ = f.read_to_string(&mut holder);
            let holder = holder.trim();
            let by = if holder.is_empty() { String::new() } else { format!(" ({holder})") };
            Err(Error::io(
                dir,
                format!("is in use by another poroplast run{by}: wait for it to end, or choose another --out"),
            ))
        }
        // A file system without locks (e.g. Lustre mounted without `flock`): run unguarded
        // rather than not at all.
        Err(std::fs::TryLockError::Error(e)) => {
            eprintln!(
                "poroplast: warning: {}: cannot lock ({e}); another job into this directory would not be refused",
                path.display()
            );
            Ok(RunLock { _held: None })
        }
    }
}

fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname").map(|h| h.trim().to_string()).unwrap_or_else(|_| "?".into())
}

/// Writes `contents` to `dir/name` (a plain file name, no separators), replacing any old file;
/// call on rank 0 only. For the resolved scene, options, timings and the like.
pub(crate) fn write_text(dir: &Path, name: &str, contents: &str) -> Result<()> {
    let path = dir.join(name);
    if name.is_empty() || name.contains(['/', '\\']) || name == "." || name == ".." {
        return Err(Error::io(&path, "expected a plain file name"));
    }
    std::fs::write(&path, contents).map_err(|e| Error::io(&path, e))
}

/// `runs/<scene_stem>-<YYYYmmdd-HHMMSS>` with the current UTC time. See the module note on ranks.
pub(crate) fn default_run_dir(scene_stem: &str) -> PathBuf {
    let secs = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    default_run_dir_at(scene_stem, secs)
}

/// `runs/<scene_stem>-<YYYYmmdd-HHMMSS>` for `unix_secs` seconds since 1970-01-01T00:00:00Z.
/// The stem is reduced to a plain name (a scene `name` of `../../x` or `/abs` stays in `runs/`).
pub(crate) fn default_run_dir_at(scene_stem: &str, unix_secs: u64) -> PathBuf {
    let safe: String = scene_stem
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') { c } else { '_' })
        .collect();
    let safe = safe.trim_start_matches('.');
    let safe = if safe.is_empty() { "run" } else { safe };
    Path::new("runs").join(format!("{safe}-{}", utc_stamp(unix_secs)))
}

/// `YYYYmmdd-HHMMSS` (UTC) for `unix_secs` seconds since the Unix epoch (proleptic Gregorian).
pub(crate) fn utc_stamp(unix_secs: u64) -> String {
    let days = (unix_secs / 86_400) as i64;
    let rem = unix_secs % 86_400;
    let (y, m, d) = civil_from_days(days);
    format!("{y:04}{m:02}{d:02}-{:02}{:02}{:02}", rem / 3600, rem / 60 % 60, rem % 60)
}

/// (year, month 1–12, day 1–31) of `days` since 1970-01-01 (H. Hinnant's `civil_from_days`).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097); // [0, 146096]
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // [0, 399]
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // [0, 365]
    let mp = (5 * doy + 2) / 153; // [0, 11], March-based
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

#[cfg(test)]
mod tests {
    #[test]
    fn default_run_dir_stays_in_runs() {
        for name in ["../../x", "/etc/passwd", "..", "a/b", ""] {
            let d = super::default_run_dir_at(name, 0);
            assert_eq!(d.components().count(), 2, "{name:?} -> {}", d.display());
            assert!(d.starts_with("runs"), "{name:?} -> {}", d.display());
            assert!(
                d.components().all(|c| matches!(c, std::path::Component::Normal(_))),
                "{name:?} -> {}",
                d.display()
            );
        }
        assert_eq!(super::default_run_dir_at("remodel_40", 0), std::path::Path::new("runs/remodel_40-19700101-000000"));
    }

    use super::*;

    fn tmp(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("poroplast-rundir-{}-{name}", std::process::id()))
    }

    #[test]
    fn known_epochs() {
        assert_eq!(utc_stamp(0), "19700101-000000");
        assert_eq!(utc_stamp(951_782_400), "20000229-000000"); // leap day of a /400 year
        assert_eq!(utc_stamp(978_307_199), "20001231-235959");
        assert_eq!(utc_stamp(1_000_000_000), "20010909-014640");
        assert_eq!(utc_stamp(1_234_567_890), "20090213-233130");
        assert_eq!(utc_stamp(1_709_210_096), "20240229-123456");
        assert_eq!(utc_stamp(2_147_483_647), "20380119-031407");
        assert_eq!(utc_stamp(4_107_542_400), "21000301-000000"); // 2100 is not a leap year
        assert_eq!(default_run_dir_at("cube", 1_234_567_890), Path::new("runs/cube-20090213-233130"));
        let now = default_run_dir("s");
        let s = now.to_str().unwrap();
        assert!(s.starts_with("runs/s-20") && s.len() == "runs/s-".len() + 15, "{s}");
    }

    #[test]
    fn refuses_non_empty_dir_and_leaves_it_untouched() {
        let d = tmp("nonempty");
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("history.csv"), "old run\n").unwrap();
        let e = prepare(&d, false, true).unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, Error::Io { .. }));
        assert!(msg.contains(d.to_str().unwrap()) && msg.contains("--force") && msg.contains("--out"), "{msg}");
        assert_eq!(std::fs::read_to_string(d.join("history.csv")).unwrap(), "old run\n");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        // Non-root ranks never touch the file system.
        prepare(&d, false, false).unwrap();
        // With force it is accepted, and nothing is deleted.
        prepare(&d, true, true).unwrap();
        assert_eq!(std::fs::read_to_string(d.join("history.csv")).unwrap(), "old run\n");
        // A file in the way.
        let f = d.join("history.csv");
        assert!(prepare(&f, true, true).is_err());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn creates_missing_and_accepts_empty() {
        let d = tmp("fresh").join("a/b");
        prepare(&d, false, true).unwrap();
        assert!(d.is_dir());
        prepare(&d, false, true).unwrap(); // exists but empty
        write_text(&d, "scene.toml", "x = 1\n").unwrap();
        assert_eq!(std::fs::read_to_string(d.join("scene.toml")).unwrap(), "x = 1\n");
        assert!(write_text(&d, "../escape", "").is_err());
        assert!(prepare(&d, false, true).is_err()); // no longer empty
        let nonroot = tmp("nonroot");
        prepare(&nonroot, false, false).unwrap();
        assert!(!nonroot.exists());
        std::fs::remove_dir_all(tmp("fresh")).unwrap();
    }
}
