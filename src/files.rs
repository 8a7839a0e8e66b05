//! Files replaced whole: written under a temporary name next to the target, then renamed over
//! it, so that a reader, or a resume after a kill, finds the old file or the new one, never a
//! part of one.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Makes `path` by `write(tmp)` into `path.<pid>-<n>.tmp` (its directory created if missing),
/// then renames it over `path`; the temporary file is removed if that fails. The temporary name
/// is this process's and this call's, so several processes or threads may write the same file
/// (a sweep's groups, its summary.csv, a cached mesh): each rename installs a whole one.
pub(crate) fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(format!(".{}-{}.tmp", std::process::id(), CALLS.fetch_add(1, Ordering::Relaxed)));
    let tmp = PathBuf::from(tmp);
    let r = write(&tmp).and_then(|()| std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e)));
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r
}

/// [`write_atomically`] of a text.
pub(crate) fn write_text_atomically(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, |tmp| std::fs::write(tmp, text).map_err(|e| Error::io(tmp, e)))
}

/// `from` copied over `to` ([`write_atomically`]).
pub(crate) fn copy_atomically(from: &Path, to: &Path) -> Result<()> {
    write_atomically(to, |tmp| {
        std::fs::copy(from, tmp).map(drop).map_err(|e| Error::io(tmp, format!("cannot copy {}: {e}", from.display())))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_replaced_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("poroplast-files-{}", std::process::id()));
        let path = dir.join("sub").join("a.txt");
        write_text_atomically(&path, "one").unwrap();
        write_text_atomically(&path, "two").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "two");
        // A failed write leaves the old file, and no temporary one.
        let failed = write_atomically(&path, |tmp| {
            std::fs::write(tmp, "par").unwrap();
            Err(Error::io(tmp, "stopped"))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "two");
        let left: Vec<_> = std::fs::read_dir(path.parent().unwrap()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left, ["a.txt"]);
        copy_atomically(&path, &dir.join("b.txt")).unwrap();
        assert_eq!(std::fs::read_to_string(dir.join("b.txt")).unwrap(), "two");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
