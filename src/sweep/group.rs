//! One group of ranks on its own communicator, claiming and running cases one after another.

use super::args::SweepArgs;
use super::plan::{write_summary, Plan, RUNNING};
use super::schedule;
use super::store::{self, CaseRecord};
use super::study::{Case, Study};
use super::summary::{Observations, Row, State};
use crate::driver::{self, signals::StopRequest, RunArgs};
use crate::error::{Error, Result};
use crate::parallel::{agree, on_root};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One group of ranks, running cases one after another.
pub(super) struct Group<'a> {
    pub(super) comm: &'a SimpleCommunicator,
    pub(super) index: usize,
    pub(super) root: &'a Path,
    pub(super) study: &'a Study,
    pub(super) plan: &'a Plan,
    pub(super) observations: &'a Observations,
    pub(super) args: &'a SweepArgs,
    pub(super) stop: &'a StopRequest,
}

impl Group<'_> {
    fn leader(&self) -> bool {
        self.comm.rank() == 0
    }

    /// Claims and runs cases until none is left (or a stop signal, or a failure of the sweep
    /// itself — a failed case is not one).
    pub(super) fn run(&self, order: Vec<usize>, complete_before: usize) -> Result<()> {
        let order = order.into_iter().map(|i| (i, schedule::claim_name(&self.plan.dirs[i]))).collect();
        let mut dispenser = schedule::Dispenser::new(self.root, order, self.index);
        let started = Instant::now();
        loop {
            if self.stop.requested(self.comm) {
                return Err(Error::Stopped("stopped by a signal".into()));
            }
            let next = agree(self.comm, if self.leader() { dispenser.claim() } else { Ok(None) })?;
            let mut index = next.map_or(-1, |i| i as i64);
            self.comm.process_at_rank(0).broadcast_into(&mut index);
            if index < 0 {
                return Ok(());
            }
            let case = &self.study.cases[index as usize];
            let (dir, sig) = (&self.plan.dirs[case.index], &self.plan.sigs[case.index]);
            // Kept from another sweep sharing the store while this group has the case; that
            // sweep may have completed it meanwhile.
            let _claim = agree(
                self.comm,
                if self.leader() {
                    store::claim(dir, || {
                        if self.args.progress {
                            crate::console::line(&format!(
                                "sweep: case {} ({}) is being run by another sweep: waiting for it",
                                case.index,
                                case.label()
                            ));
                        }
                    })
                    .map(Some)
                } else {
                    Ok(None)
                },
            )?;
            let done = self.leader() && CaseRecord::read(dir, sig).is_some_and(|r| r.ok());
            if crate::parallel::any(self.comm, done) {
                continue;
            }
            let t = Instant::now();
            let outcome = self.run_case(case);
            if let Err(e @ Error::Stopped(_)) = outcome {
                return Err(e);
            }
            let failed = outcome.err().map(|e| e.to_string());
            on_root(self.comm, || {
                let record = CaseRecord::of(dir, sig, failed.clone());
                record.write(dir)?;
                let rows = write_summary(self.root, self.study, self.plan, self.observations)?;
                if self.args.progress {
                    self.progress(&rows, case, &record, t.elapsed().as_secs_f64(), started, complete_before);
                }
                Ok(())
            })?;
        }
    }

    /// One case on this group: continued from its checkpoint when an earlier session left its
    /// run unfinished, else run from the start.
    fn run_case(&self, case: &Case) -> Result<PathBuf> {
        let dir = &self.plan.dirs[case.index];
        // A failed case's record goes (it runs again); an unfinished run continues.
        let resume = on_root(self.comm, || {
            let record = dir.join(store::RECORD);
            if record.exists() {
                std::fs::remove_file(&record).map_err(|e| Error::io(&record, e))?;
                return Ok(false);
            }
            Ok(dir.join("run.toml").exists())
        })?;
        let resume = crate::parallel::any(self.comm, resume == Some(true));
        if resume {
            if self.leader() && self.args.progress {
                crate::console::line(&format!(
                    "sweep: case {} ({}) continues its interrupted run",
                    case.index,
                    case.label()
                ));
            }
            // Nothing added: the run's record holds the options it started with (its
            // signature's, which are this session's: they name its directory).
            return driver::resume(self.comm, dir, &[], driver::Log::Silent);
        }
        let sig = &self.plan.sigs[case.index];
        let run = RunArgs {
            scene: case.scene.clone(),
            set: sig.set.clone(),
            out: Some(dir.clone()),
            force: true,
            petsc: sig.petsc.clone(),
            log: driver::Log::Silent,
        };
        // Stopped before it wrote anything, the case is as if it had not started: the sweep stops.
        driver::run(self.comm, &run).map_err(|e| match e {
            Error::StoppedInSetup(m) => Error::Stopped(m),
            e => e,
        })
    }

    /// The progress line of a case just ended (the group's leader): the sweep's counts from the
    /// `rows` [`write_summary`] has just read, and the ETA at the pace of this session.
    fn progress(&self, rows: &[Row], case: &Case, r: &CaseRecord, secs: f64, started: Instant, complete_before: usize) {
        let (mut ok, mut failed, mut running) = (0usize, 0usize, 0usize);
        for row in rows {
            match &row.state {
                State::Ended(r) if r.ok() => ok += 1,
                State::Ended(_) => failed += 1,
                State::Open(RUNNING) => running += 1,
                State::Open(_) => {}
            }
        }
        let total = self.study.cases.len();
        let ended_now = (ok + failed).saturating_sub(complete_before).max(1);
        let left = total - ok - failed;
        let eta = started.elapsed().as_secs_f64() / ended_now as f64 * left as f64;
        let what = if r.ok() { format!("ok in {secs:.1} s") } else { format!("FAILED in {secs:.1} s: {}", r.error) };
        crate::console::line(&format!(
            "sweep: case {} ({}) {what} [group {}] — {ok}/{total} done, {running} running, {failed} failed, eta {}",
            case.index,
            case.label(),
            self.index,
            crate::io::fmt_duration(eta)
        ));
    }
}
