//! `history.csv`: one line per time step (step, time, dt, Newton iterations, residuals, ...), written by rank 0.
//!
//! Format: a header line with the column names, then one line per [`History::row`], comma-separated,
//! `\n`-terminated, flushed to the OS after every row so the file can be followed while the run goes on.
//! Real columns print the shortest decimal that parses back to the same `f64` (see
//! `io::fmt_real`: `0.5`, `1.5e-7`, `NaN`); integer columns print as integers (`12`).

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::io::fmt_real;

/// Largest integer an `f64` holds exactly (2^53).
const MAX_EXACT_INT: f64 = 9_007_199_254_740_992.0;

/// The `history.csv` writer; on ranks other than 0 a no-op handle that still checks row lengths.
pub(crate) struct History {
    path: PathBuf,
    file: Option<File>,
    columns: Vec<String>,
    integer: Vec<bool>,
}

impl History {
    /// Creates (truncating) the CSV at `path` and writes the header, on the root rank only
    /// (`is_root`); other ranks get a handle whose [`row`](Self::row) only checks its arguments.
    ///
    /// `columns` are the column names in order; those also listed in `integer_columns` (for example
    /// `"step"`, `"newton_its"`) are printed as integers, and a non-integral value there is an error.
    /// Names must be non-empty, unique, and free of `,`, `"` and line breaks.
    pub(crate) fn create(path: &Path, columns: &[&str], integer_columns: &[&str], is_root: bool) -> Result<Self> {
        let mut h = History::create_handle(path, columns, integer_columns)?;
        if is_root {
            let mut f = File::create(path).map_err(|e| Error::io(path, e))?;
            writeln!(f, "{}", columns.join(",")).map_err(|e| Error::io(path, e))?;
            h.file = Some(f);
        }
        Ok(h)
    }

    /// A handle with checked columns and no file yet.
    fn create_handle(path: &Path, columns: &[&str], integer_columns: &[&str]) -> Result<Self> {
        if columns.is_empty() {
            return Err(Error::io(path, "history needs at least one column"));
        }
        for (i, c) in columns.iter().enumerate() {
            if c.is_empty() || c.contains([',', '"', '\n', '\r']) {
                return Err(Error::io(path, format!("invalid column name {c:?}")));
            }
            if columns[..i].contains(c) {
                return Err(Error::io(path, format!("column {c:?} given twice")));
            }
        }
        if let Some(bad) = integer_columns.iter().find(|c| !columns.contains(c)) {
            return Err(Error::io(path, format!("integer column {bad:?} is not among the columns")));
        }
        Ok(History {
            path: path.to_path_buf(),
            file: None,
            columns: columns.iter().map(|c| c.to_string()).collect(),
            integer: columns.iter().map(|c| integer_columns.contains(c)).collect(),
        })
    }

    /// Reopens the CSV at `path` to continue it after its first `keep` rows (rank 0 truncates
    /// the rest): the header must be `columns`, and the file must hold at least `keep` rows.
    pub(crate) fn reopen(
        path: &Path,
        columns: &[&str],
        integer_columns: &[&str],
        keep: usize,
        is_root: bool,
    ) -> Result<Self> {
        let mut h = History::create_handle(path, columns, integer_columns)?;
        if is_root {
            let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
            let mut lines = text.split_inclusive('\n');
            let head = lines.next().unwrap_or("");
            if head.trim_end() != columns.join(",") {
                // A run written before the µN force columns existed lacks them: say so, not "changed".
                let without_un: Vec<&str> = columns.iter().copied().filter(|c| !c.ends_with("_uN")).collect();
                return Err(Error::io(
                    path,
                    if without_un.len() < columns.len() && head.trim_end() == without_un.join(",") {
                        "was written by an earlier version of poroplast (its forces have no µN columns): it cannot \
                         be continued; rerun it (`poroplast run` with --force, or into a new --out)"
                    } else {
                        "its columns are not this run's (was the scene changed?)"
                    },
                ));
            }
            let kept: Vec<&str> = lines.take(keep).collect();
            if kept.len() < keep || kept.last().is_some_and(|l| !l.ends_with('\n')) {
                return Err(Error::io(path, format!("has fewer than the {keep} complete rows of the checkpoint")));
            }
            let len = (head.len() + kept.iter().map(|l| l.len()).sum::<usize>()) as u64;
            let f = std::fs::OpenOptions::new().write(true).open(path).map_err(|e| Error::io(path, e))?;
            f.set_len(len).map_err(|e| Error::io(path, e))?;
            drop(f);
            h.file = Some(std::fs::OpenOptions::new().append(true).open(path).map_err(|e| Error::io(path, e))?);
        }
        Ok(h)
    }

    /// Appends one line and flushes it. `values` must have one value per column; values of
    /// integer columns must be integral (and below 2^53 in magnitude).
    pub(crate) fn row(&mut self, values: &[f64]) -> Result<()> {
        if values.len() != self.columns.len() {
            return Err(Error::io(
                &self.path,
                format!(
                    "row has {} values for {} columns ({})",
                    values.len(),
                    self.columns.len(),
                    self.columns.join(",")
                ),
            ));
        }
        let mut line = String::new();
        for (i, &v) in values.iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            if self.integer[i] {
                if !v.is_finite() || v.fract() != 0.0 || v.abs() > MAX_EXACT_INT {
                    return Err(Error::io(&self.path, format!("column {:?} is integer, got {v}", self.columns[i])));
                }
                line.push_str(&format!("{}", v as i64));
            } else {
                line.push_str(&fmt_real(v));
            }
        }
        line.push('\n');
        if let Some(f) = self.file.as_mut() {
            // One write per row, straight to the OS (no user-space buffer): nothing to flush later.
            f.write_all(line.as_bytes()).and_then(|()| f.flush()).map_err(|e| Error::io(&self.path, e))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("poroplast-history-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d.join("history.csv")
    }

    #[test]
    fn exact_content() {
        let p = tmp("exact");
        let mut h =
            History::create(&p, &["step", "time", "dt", "newton_its", "residual"], &["step", "newton_its"], true)
                .unwrap();
        h.row(&[0.0, 0.0, 0.1, 3.0, 1.25e-9]).unwrap();
        h.row(&[1.0, 0.1, 0.1, 12.0, 1.0 / 3.0]).unwrap();
        h.row(&[2.0, 0.30000000000000004, 2e-5, 0.0, f64::NAN]).unwrap();
        // Readable while the handle is still open: every row was flushed.
        let text = std::fs::read_to_string(&p).unwrap();
        assert_eq!(
            text,
            "step,time,dt,newton_its,residual\n\
             0,0,0.1,3,1.25e-9\n\
             1,0.1,0.1,12,0.3333333333333333\n\
             2,0.30000000000000004,2e-5,0,NaN\n"
        );
        drop(h);
        std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
    }

    #[test]
    fn column_count_mismatch_is_an_error() {
        let p = tmp("mismatch");
        let mut h = History::create(&p, &["step", "time"], &["step"], true).unwrap();
        let e = h.row(&[1.0]).unwrap_err();
        assert!(matches!(e, Error::Io { .. }));
        assert!(e.to_string().contains("1 values for 2 columns"), "{e}");
        assert!(h.row(&[1.0, 2.0, 3.0]).is_err());
        assert!(h.row(&[1.5, 2.0]).is_err(), "non-integral value in an integer column");
        assert!(h.row(&[f64::NAN, 2.0]).is_err());
        h.row(&[1.0, 2.0]).unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "step,time\n1,2\n");
        // Non-root handles write nothing but check the same way.
        let q = p.with_file_name("other.csv");
        let mut h = History::create(&q, &["a", "b"], &[], false).unwrap();
        assert!(h.row(&[1.0]).is_err());
        h.row(&[1.0, 2.0]).unwrap();
        assert!(!q.exists());
        std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
    }

    /// A history from before the µN columns is refused as an earlier version's; other headers as
    /// another scene's; neither is changed.
    #[test]
    fn an_earlier_versions_history_is_named_as_such() {
        let p = tmp("earlier");
        let old = "step,time,force_total_mg,height\n0,0,0,200\n1,1,2,190\n";
        std::fs::write(&p, old).unwrap();
        let now = ["step", "time", "force_total_mg", "force_total_uN", "height"];
        let e = History::reopen(&p, &now, &["step"], 1, true).err().unwrap().to_string();
        assert!(e.contains("written by an earlier version of poroplast") && e.contains("rerun it"), "{e}");
        let e = History::reopen(&p, &["step", "time", "width"], &["step"], 1, true).err().unwrap().to_string();
        assert!(e.contains("its columns are not this run's"), "{e}");
        assert_eq!(std::fs::read_to_string(&p).unwrap(), old);
        // The same header is continued after the checkpoint's rows.
        let h = History::reopen(&p, &["step", "time", "force_total_mg", "height"], &["step"], 1, true).unwrap();
        drop(h);
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "step,time,force_total_mg,height\n0,0,0,200\n");
        std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
    }

    #[test]
    fn bad_columns() {
        let p = tmp("bad");
        assert!(History::create(&p, &[], &[], true).is_err());
        assert!(History::create(&p, &["a", "a"], &[], true).is_err());
        assert!(History::create(&p, &["a,b"], &[], true).is_err());
        assert!(History::create(&p, &["a"], &["b"], true).is_err());
        std::fs::remove_dir_all(p.parent().unwrap()).unwrap();
    }
}
