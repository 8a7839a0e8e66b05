//! Handing out cases to groups: a fixed priority order (longest first where costs are
//! estimated), and claims made by creating a file exclusively.
//!
//! A group's leader takes the next case by walking the order and creating
//! `DIR/claims/<case>` (the name of the case's directory in the store) with
//! `O_CREAT | O_EXCL` (`create_new`): the file system makes exactly one creation succeed, so
//! each case goes to one group, whichever asks first — no coordinating rank, no message to wait
//! for, no thread. `claims/` belongs to one session: world rank 0 empties it at the start, while
//! it holds the sweep directory's lock. (Another sweep sharing the store is kept out of a case
//! by the case's own claim lock, `store::claim`.)

use super::store::{CaseRecord, Signature};
use super::study::{Case, Study};
use super::summary::{label_key, read_wall_times};
use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// The claims directory of a sweep directory.
pub(crate) fn claims_dir(root: &Path) -> PathBuf {
    root.join("claims")
}

/// Empties the claims of an earlier session (world rank 0, with the sweep's lock held).
pub(crate) fn reset_claims(root: &Path) -> Result<()> {
    let dir = claims_dir(root);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    }
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))
}

/// The claim name of a case: its directory's name in the store.
pub(crate) fn claim_name(dir: &Path) -> String {
    dir.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

/// Whether the case in `dir` has been claimed in this session.
pub(crate) fn claimed(root: &Path, dir: &Path) -> bool {
    claims_dir(root).join(claim_name(dir)).exists()
}

/// The order in which the cases to run are tried: by estimated cost, longest first (a case
/// without an estimate counts as the mean of the others), else in case order.
pub(crate) fn order(study: &Study, todo: &[usize]) -> Result<Vec<usize>> {
    let mut order = todo.to_vec();
    let Some(path) = &study.estimate_from else { return Ok(order) };
    let walls = read_wall_times(path, study)?;
    let keys = study.label_keys();
    let cost: Vec<Option<f64>> =
        study.cases.iter().map(|c: &Case| walls.get(&label_key(c, &keys)).copied().filter(|w| w.is_finite())).collect();
    let known: Vec<f64> = todo.iter().filter_map(|&i| cost[i]).collect();
    if known.is_empty() {
        return Ok(order);
    }
    let mean = known.iter().sum::<f64>() / known.len() as f64;
    order.sort_by(|&a, &b| cost[b].unwrap_or(mean).total_cmp(&cost[a].unwrap_or(mean)));
    Ok(order)
}

/// A group leader's walk through the order.
pub(crate) struct Dispenser {
    root: PathBuf,
    /// The cases to try, in order: (case index, claim name).
    order: Vec<(usize, String)>,
    next: usize,
    who: String,
}

impl Dispenser {
    pub(crate) fn new(root: &Path, order: Vec<(usize, String)>, group: usize) -> Dispenser {
        Dispenser {
            root: root.to_path_buf(),
            order,
            next: 0,
            who: format!("group {group}, pid {}\n", std::process::id()),
        }
    }

    /// The next case this group claims, or None when every case is taken.
    pub(crate) fn claim(&mut self) -> Result<Option<usize>> {
        use std::io::Write;
        while let Some((index, name)) = self.order.get(self.next) {
            self.next += 1;
            let path = claims_dir(&self.root).join(name);
            match std::fs::OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(mut f) => {
                    // Who has it, for a person looking (the claim is the file's existence).
                    let _ = f.write_all(self.who.as_bytes());
                    return Ok(Some(*index));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(Error::io(&path, format!("cannot claim the case: {e}"))),
            }
        }
        Ok(None)
    }
}

/// The cases left to run: those without a record of a completed run, each case of the store
/// once (two cases of a study that run the same are one: the first stands for both).
pub(crate) fn todo(dirs: &[PathBuf], sigs: &[Signature]) -> Vec<usize> {
    let mut seen = std::collections::BTreeSet::new();
    (0..dirs.len())
        .filter(|&i| seen.insert(&dirs[i]) && !CaseRecord::read(&dirs[i], &sigs[i]).is_some_and(|r| r.ok()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_case_is_claimed_once() {
        let root = std::env::temp_dir().join(format!("poroplast-claims-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        reset_claims(&root).unwrap();
        let order: Vec<(usize, String)> = [2, 0, 1].iter().map(|&i| (i, format!("case-{i}"))).collect();
        let mut a = Dispenser::new(&root, order.clone(), 0);
        let mut b = Dispenser::new(&root, order, 1);
        assert_eq!(a.claim().unwrap(), Some(2));
        assert_eq!(b.claim().unwrap(), Some(0));
        assert_eq!(a.claim().unwrap(), Some(1));
        assert_eq!(b.claim().unwrap(), None);
        assert_eq!(a.claim().unwrap(), None);
        assert!(claimed(&root, Path::new("/store/case-1")));
        reset_claims(&root).unwrap();
        assert!(!claimed(&root, Path::new("/store/case-1")));
        let _ = std::fs::remove_dir_all(&root);
    }
}
