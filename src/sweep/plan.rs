//! The cases of a sweep as the store knows them — each case's signature and run directory — and
//! summary.csv written from their states on disk.

use super::schedule;
use super::store::{self, CaseRecord, Signature};
use super::study::Study;
use super::summary::{self, Observations, Row, State};
use crate::error::{Error, Result};
use crate::parallel::{broadcast_vec, on_root};
use mpi::topology::SimpleCommunicator;
use std::path::{Path, PathBuf};

/// The cases of a sweep as the store knows them: each case's signature and run directory.
pub(super) struct Plan {
    pub(super) sigs: Vec<Signature>,
    pub(super) dirs: Vec<PathBuf>,
}

/// What rank 0 sends the others of the signatures (they read no scene file again).
#[derive(serde::Serialize, serde::Deserialize)]
struct Signatures {
    case: Vec<Signature>,
}

impl Plan {
    /// The signatures (rank 0's, who reads the scenes) and directories of the study's cases in
    /// the store `store`; `petsc`: the command line's options.
    pub(super) fn of(world: &SimpleCommunicator, study: &Study, petsc: &[String], store: &Path) -> Result<Plan> {
        let text = on_root(world, || {
            let mut options = study.petsc.clone();
            options.extend(petsc.iter().cloned());
            let case = study
                .cases
                .iter()
                .map(|c| Signature::of(&c.scene, study.overrides(c), options.clone()))
                .collect::<Result<Vec<_>>>()?;
            toml::to_string(&Signatures { case }).map_err(|e| Error::Sweep(format!("the cases' signatures: {e}")))
        })?;
        let mut bytes = text.unwrap_or_default().into_bytes();
        broadcast_vec(world, 0, &mut bytes);
        let sigs = toml::from_str::<Signatures>(&String::from_utf8_lossy(&bytes))
            .map_err(|e| Error::Sweep(format!("the cases' signatures: {e}")))?
            .case;
        let dirs = study.cases.iter().zip(&sigs).map(|(c, s)| store::case_dir(store, c, s)).collect();
        Ok(Plan { sigs, dirs })
    }
}

/// The state of a case claimed in this session that has not ended.
pub(super) const RUNNING: &str = "running";

/// summary.csv from every case's state on disk; returns the rows.
pub(super) fn write_summary(root: &Path, study: &Study, plan: &Plan, observations: &Observations) -> Result<Vec<Row>> {
    let rows: Vec<Row> = study
        .cases
        .iter()
        .zip(plan.dirs.iter().zip(&plan.sigs))
        .map(|(c, (dir, sig))| {
            let state = match CaseRecord::read(dir, sig) {
                Some(r) => State::Ended(r),
                None if schedule::claimed(root, dir) => State::Open(RUNNING),
                None if dir.join("run.toml").exists() => State::Open("interrupted"),
                None => State::Open("pending"),
            };
            Row { case: c.clone(), state, dir: dir.clone() }
        })
        .collect();
    summary::write(root, study, &rows, observations)?;
    Ok(rows)
}
