//! `poroplast case SCENE [--set KEY=VALUE ...] [--cases-dir DIR] [-- PETSC OPTIONS]`: a case as
//! the sweeps know it — its `Signature` and key — and, in a case store, where it is and how it
//! ended. Scripts find their cases with it rather than by matching `case.toml` files themselves,
//! which would have to know what makes a case (the scene's text, for one).

use super::store::{CaseRecord, Signature};
use crate::error::{Error, Result};
use crate::scene::LoadedScene;
use std::path::{Path, PathBuf};

/// What a case store holds of a case.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Status {
    /// Completed: its `case.toml` says ok.
    Ok,
    /// Ended in an error (its line).
    Failed(String),
    /// A run directory without an outcome: interrupted, or running now.
    Unfinished,
    /// No run directory of the case.
    Absent,
}

impl Status {
    fn word(&self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed(_) => "failed",
            Status::Unfinished => "unfinished",
            Status::Absent => "absent",
        }
    }
}

/// The case `sig` in the store `store`: its run directory and status. Any directory of the store
/// named after the case's key counts (`<readable part>-<key>`: the readable part depends on how
/// a study split its overrides); a completed one wins over a failed one, which wins over an
/// unfinished one. Err if `store` is not a directory.
pub(crate) fn find(store: &Path, sig: &Signature) -> Result<(Status, Option<PathBuf>)> {
    let entries = std::fs::read_dir(store).map_err(|e| {
        Error::io(store, format!("cannot read the case store ({e}); it is a sweep's DIR/cases or its --cases-dir"))
    })?;
    let suffix = format!("-{}", sig.key());
    let mut dirs: Vec<PathBuf> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(&suffix) && e.path().is_dir())
        .map(|e| e.path())
        .collect();
    dirs.sort();
    let status = |d: &Path| match CaseRecord::read(d, sig) {
        Some(r) if r.ok() => Status::Ok,
        Some(r) => Status::Failed(r.error),
        None => Status::Unfinished,
    };
    let rank = |s: &Status| match s {
        Status::Ok => 0,
        Status::Failed(_) => 1,
        _ => 2,
    };
    Ok(dirs
        .into_iter()
        .map(|d| (status(&d), d))
        .min_by_key(|(s, _)| rank(s))
        .map_or((Status::Absent, None), |(s, d)| (s, Some(d))))
}

/// The text `poroplast case` prints (TOML): the case's key and signature and, with a store, its
/// status, run directory and error. The overrides are checked against the scene first, as a
/// sweep checks them (keys and types; a value out of range is the failure of the case).
pub fn describe(scene: &str, set: &[String], petsc: &[String], store: Option<&Path>) -> Result<String> {
    LoadedScene::check_keys(scene, set)?;
    let sig = Signature::of(scene, set.to_vec(), petsc.to_vec())?;
    let mut t = toml::Table::new();
    t.insert("key".into(), sig.key().into());
    t.insert("scene".into(), sig.scene.clone().into());
    t.insert("scene_text".into(), sig.scene_text.clone().into());
    t.insert("set".into(), sig.set.clone().into());
    t.insert("petsc".into(), sig.petsc.clone().into());
    let mut text = format!(
        "# the case a sweep runs for this scene, overrides and PETSc options (its case.toml records the same)\n{}",
        toml::to_string(&t).map_err(|e| Error::Sweep(format!("the case's signature: {e}")))?
    );
    if let Some(store) = store {
        let (status, dir) = find(store, &sig)?;
        let mut t = toml::Table::new();
        t.insert("status".into(), status.word().into());
        if let Some(d) = dir {
            t.insert("dir".into(), d.display().to_string().into());
        }
        if let Status::Failed(e) = &status {
            t.insert("error".into(), e.clone().into());
        }
        text += &format!(
            "# in the case store {}: ok, failed, unfinished (interrupted, or running now) or absent\n{}",
            store.display(),
            toml::to_string(&t).map_err(|e| Error::Sweep(format!("the case's status: {e}")))?
        );
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A store with the case `sig` in the given states, each in a directory of its own name.
    fn store(name: &str, dirs: &[(&str, Option<Option<&str>>)], sig: &Signature) -> PathBuf {
        let root = std::env::temp_dir().join(format!("poroplast-find-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).unwrap();
        for (slug, record) in dirs {
            let d = root.join(format!("{slug}-{}", sig.key()));
            std::fs::create_dir_all(&d).unwrap();
            if let Some(error) = record {
                CaseRecord::of(&d, sig, error.map(String::from)).write(&d).unwrap();
            }
        }
        root
    }

    #[test]
    fn a_store_says_where_a_case_is_and_how_it_ended() {
        let sig = Signature::of("cryer", vec!["material.mu=3".into()], vec![]).unwrap();
        let other = Signature::of("cryer", vec!["material.mu=4".into()], vec![]).unwrap();
        let s = store("states", &[("a", None), ("b", Some(Some("diverged"))), ("c", Some(None))], &sig);
        assert_eq!(find(&s, &sig).unwrap(), (Status::Ok, Some(s.join(format!("c-{}", sig.key())))));
        assert_eq!(find(&s, &other).unwrap(), (Status::Absent, None));
        let s = store("failed", &[("a", None), ("b", Some(Some("diverged")))], &sig);
        assert_eq!(find(&s, &sig).unwrap().0, Status::Failed("diverged".into()));
        let s = store("unfinished", &[("a", None)], &sig);
        assert_eq!(find(&s, &sig).unwrap(), (Status::Unfinished, Some(s.join(format!("a-{}", sig.key())))));
        // A record of another signature in a directory of this key (it cannot be this case's).
        let d = s.join(format!("z-{}", sig.key()));
        std::fs::create_dir_all(&d).unwrap();
        CaseRecord::of(&d, &other, None).write(&d).unwrap();
        assert_eq!(find(&s, &sig).unwrap().0, Status::Unfinished);
        let e = find(&s.join("missing"), &sig).unwrap_err().to_string();
        assert!(e.contains("cannot read the case store"), "{e}");
        let _ = std::fs::remove_dir_all(&s);
    }

    #[test]
    fn the_description_is_toml_and_checks_the_keys() {
        let text = describe("cryer", &["material.mu=3".into()], &["-ksp_rtol".into(), "1e-9".into()], None).unwrap();
        let t: toml::Table = toml::from_str(&text).unwrap();
        let sig =
            Signature::of("cryer", vec!["material.mu=3".into()], vec!["-ksp_rtol".into(), "1e-9".into()]).unwrap();
        assert_eq!(t["key"].as_str(), Some(sig.key().as_str()));
        assert_eq!(t["scene_text"].as_str(), Some(sig.scene_text.as_str()));
        assert_eq!(t["petsc"].as_array().unwrap().len(), 2);
        assert!(!t.contains_key("status"));
        let e = describe("cryer", &["material.muu=3".into()], &[], None).unwrap_err().to_string();
        assert!(e.contains("muu"), "{e}");
    }
}
