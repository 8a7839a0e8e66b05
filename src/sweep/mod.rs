//! `poroplast sweep STUDY.toml [--ranks-per-case k] [--out DIR] [--cases-dir DIR]`: the cases of
//! a study (a base scene and a grid or list of `--set` overrides, or a list of cases with their
//! own scenes, see [`study`]) run under one `mpirun -n N`.
//!
//! - The world splits into N/k groups of k consecutive ranks; each group runs one case at a
//!   time on its own communicator, through the driver's public entry points ([`driver::run`],
//!   [`driver::resume`]), which initialise PETSc on that communicator with the case's options
//!   and finalise it after: no PETSc option, object or log stage passes from a case to the next.
//! - Cases are handed out as groups become free ([`schedule`]): a group's leader claims the
//!   next case of a fixed order (longest first when `estimate_from` gives costs) by creating
//!   its claim file exclusively, and tells its group. Nothing waits on another group: the
//!   world meets only at the start and at the end. (A coordinating rank answering requests
//!   would have to be one that runs no case, or a thread, since world rank 0 runs cases too;
//!   rsmpi 0.8 has no one-sided atomics. The file system the run directories need anyway is
//!   the coordinator.)
//! - The cases live in a case store ([`store`]): each in a run directory named after what it
//!   runs (scene, overrides, PETSc options), with `case.toml`, its outcome, once it has ended.
//!   The store is the sweep directory's `cases/`, or one that several sweeps share
//!   (`--cases-dir`): a case any of them has completed is not run again.
//! - The sweep directory (`--out`, default `runs/sweep-<study>-<UTC time>`) holds `study.toml`
//!   (the study file) and `sweep.toml` (the command line's `-- PETSC OPTIONS`), both written at
//!   the first session, which a later session must match; `summary.csv` ([`summary`]: a row per
//!   case, with the observables of [`observable`]), `claims/` (this session's) and, by default,
//!   the store `cases/`.
//! - Every case's overrides are read into its scene before anything is written: an unknown key
//!   (or a value of the wrong type) is the sweep's error, naming the case. A case that fails
//!   later (a value out of range, its set-up, a solve that does not converge) is recorded with
//!   its error
//!   line; the group goes on to the next case.
//! - Resuming: the same command with `--out DIR`. Complete cases are skipped; a case with a run
//!   directory and no outcome (killed, or stopped by a signal) continues from its last
//!   checkpoint ([`driver::resume`]); a failed case runs again. A sweep directory of an earlier
//!   version (`cases/NNN_<overrides>/`) has its cases moved into the store first
//!   ([`store::adopt_legacy`]).
//! - A stop signal (SIGTERM, SIGINT, SIGUSR1) makes running cases checkpoint and stop (the
//!   driver's own handling), and every group stop before its next case; exit code 75 then.
//!   A signal that arrives while a case is being set up, before its time loop, is the
//!   process's (src/driver/signals.rs): the case stops at the end of its first step.
//! - summary.csv is rewritten by a group's leader after each case and by world rank 0 at the
//!   end, in case order, so a killed sweep leaves a usable partial one.

pub mod counters;
pub mod find;
pub mod schedule;
pub mod store;
pub mod study;
pub mod summary;

/// The observables of a history (the grammar lives with the history's reader, in `io`).
pub use crate::io::observable;

use crate::driver::{self, signals::StopRequest, RunArgs};
use crate::error::{Error, Result};
use crate::io::rundir;
use crate::parallel::{agree, agree_ranked, broadcast_vec, on_root, path_from_root};
use crate::scene::LoadedScene;
use mpi::topology::{Color, SimpleCommunicator};
use mpi::traits::*;
use std::path::{Path, PathBuf};
use std::time::Instant;
use store::{CaseRecord, Signature};
use study::{Case, Study};
use summary::{Observations, Row, State};

/// What `poroplast sweep` was asked to do.
#[derive(Debug, Clone)]
pub struct SweepArgs {
    /// The study file.
    pub study: PathBuf,
    /// Ranks of each case (k); must divide the world's size.
    pub ranks_per_case: usize,
    pub out: Option<PathBuf>,
    /// The case store (default: the sweep directory's `cases/`).
    pub cases_dir: Option<PathBuf>,
    /// PETSc options of every case (after the study's own).
    pub petsc: Vec<String>,
    /// A progress line per case ended.
    pub progress: bool,
}

/// The cases of a sweep as the store knows them: each case's signature and run directory.
struct Plan {
    sigs: Vec<Signature>,
    dirs: Vec<PathBuf>,
}

/// What rank 0 sends the others of the signatures (they read no scene file again).
#[derive(serde::Serialize, serde::Deserialize)]
struct Signatures {
    case: Vec<Signature>,
}

impl Plan {
    /// The signatures (rank 0's, who reads the scenes) and directories of the study's cases in
    /// the store `store`; `petsc`: the command line's options.
    fn of(world: &SimpleCommunicator, study: &Study, petsc: &[String], store: &Path) -> Result<Plan> {
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

/// Runs a study; returns the sweep directory. Any case failed: an error saying how many (the
/// others ran, all are in summary.csv).
pub fn sweep(world: &SimpleCommunicator, args: &SweepArgs) -> Result<PathBuf> {
    let (n, k) = (world.size() as usize, args.ranks_per_case);
    if k == 0 || n % k != 0 {
        return Err(Error::Sweep(format!(
            "--ranks-per-case {k} does not divide the {n} MPI rank(s) of this run: the ranks form groups of \
             k, one case per group at a time (choose k among the divisors of {n}, or start mpirun -n with a multiple of {k})"
        )));
    }
    // The study, as rank 0 reads it; and its base scene, which every case needs.
    let mut text = on_root(world, || {
        std::fs::read(&args.study).map_err(|e| Error::io(&args.study, format!("cannot read the study file: {e}")))
    })?
    .unwrap_or_default();
    broadcast_vec(world, 0, &mut text);
    let text = String::from_utf8_lossy(&text).into_owned();
    let study = agree(world, Study::parse(&args.study, &text))?;
    for scene in study.scenes() {
        let what = if study.per_case_scenes() { "a case's scene" } else { "the study's base scene" };
        let loaded =
            agree(world, LoadedScene::load(scene, &study.set)).map_err(|e| Error::Sweep(format!("{what}: {e}")))?;
        // Once here, not for every case (whose runs are quiet).
        driver::tell_notes(world, &loaded);
    }
    // Every case's override keys against its scene (rank 0): a typo in a grid key would
    // otherwise fail every case after the sweep directory had been made. (A value out of range
    // is the failure of its case alone, recorded in the summary.)
    on_root(world, || {
        study.cases.iter().try_for_each(|case| {
            LoadedScene::check_keys(&case.scene, &study.overrides(case))
                .map(drop)
                .map_err(|e| Error::Sweep(format!("case {} ({}): {e}", case.index, case.label())))
        })
    })?;
    // The study's observables against every case's history columns and end time (rank 0): a
    // typo would otherwise leave its column empty, and say nothing.
    if study.observe_given {
        on_root(world, || check_observables(&study))?;
    }
    let root = match &args.out {
        Some(o) => o.clone(),
        None => {
            crate::parallel::broadcast_path(world, Some(&rundir::default_run_dir(&format!("sweep-{}", study.name))))
        }
    };
    crate::driver::signals::stop_in_setup(world, "no case ran, nothing was written; run the command again")?;
    // The directory (locked for the session), the store, and the cases' order, by rank 0.
    let _lock = agree(world, open_dir(&root, &text, &args.petsc, world.rank() == 0))?;
    let store = match &args.cases_dir {
        Some(dir) => path_from_root(world, || {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, format!("cannot create the case store: {e}")))?;
            std::fs::canonicalize(dir).map_err(|e| Error::io(dir, e))
        })?,
        None => root.join("cases"),
    };
    let plan = Plan::of(world, &study, &args.petsc, &store)?;
    let observations = Observations::new(&study.observe);
    let mut order: Vec<u64> = on_root(world, || {
        schedule::reset_claims(&root)?;
        let moved = store::adopt_legacy(&root, &study, &plan.dirs, &plan.sigs)?;
        let todo = schedule::todo(&plan.dirs, &plan.sigs);
        let order = schedule::order(&study, &todo)?;
        let rows = write_summary(&root, &study, &plan, &observations)?;
        if args.progress {
            if moved > 0 {
                crate::console::line(&format!(
                    "sweep {}: {moved} case(s) of an earlier version's layout moved into the case store {}",
                    root.display(),
                    store.display()
                ));
            }
            let complete = rows.iter().filter(|r| matches!(&r.state, State::Ended(r) if r.ok())).count();
            crate::console::line(&format!(
                "sweep {}: {} cases, {complete} already complete, {} to run in {} group(s) of {k} rank(s)",
                root.display(),
                study.cases.len(),
                todo.len(),
                n / k
            ));
        }
        Ok(order.into_iter().map(|i| i as u64).collect())
    })?
    .unwrap_or_default();
    broadcast_vec(world, 0, &mut order);
    let order: Vec<usize> = order.into_iter().map(|i| i as usize).collect();
    let complete_before = study.cases.len() - order.len();

    let stop = agree(world, StopRequest::install())?;
    let color = world.rank() as usize / k;
    let group = world
        .split_by_color(Color::with_value(color as i32))
        .ok_or_else(|| Error::Mpi("splitting the ranks into groups gave no communicator".into()))?;
    let ctx = Group {
        comm: &group,
        index: color,
        root: &root,
        study: &study,
        plan: &plan,
        observations: &observations,
        args,
        stop: &stop,
    };
    let r = ctx.run(order, complete_before);
    drop(group);

    // The world meets again: the summary as it stands (no case runs now: a case without an
    // outcome is interrupted or pending), and one outcome for every rank. The barrier first:
    // rank 0 must not empty claims/ while another group still runs a case, or that group would
    // find every case unclaimed and run again the ones already done.
    world.barrier();
    let written = on_root(world, || {
        schedule::reset_claims(&root)?;
        write_summary(&root, &study, &plan, &observations).map(drop)
    });
    let (r, worst) = agree_ranked(world, r, |e| if matches!(e, Error::Stopped(_)) { 1 } else { 2 });
    if worst == 2 {
        // A rank stopped by the signal while another failed: the failure is the sweep's.
        r.map_err(|e| match e {
            Error::Stopped(m) => Error::Sweep(m),
            e => e,
        })?;
    }
    written?;
    if worst == 1 {
        let cases = args.cases_dir.as_ref().map(|c| format!(" --cases-dir {}", c.display())).unwrap_or_default();
        return Err(Error::Stopped(format!(
            "sweep stopped by a signal; running cases checkpointed. Continue with `poroplast sweep {} --out {}{cases}{}` \
             (and the same --ranks-per-case or another)",
            args.study.display(),
            root.display(),
            if args.petsc.is_empty() { String::new() } else { format!(" -- {}", args.petsc.join(" ")) }
        )));
    }
    let failed = on_root(world, || {
        Ok(plan.dirs.iter().zip(&plan.sigs).filter(|(d, s)| CaseRecord::read(d, s).is_some_and(|r| !r.ok())).count()
            as u64)
    })?;
    let mut failed = failed.unwrap_or(0);
    world.process_at_rank(0).broadcast_into(&mut failed);
    if failed > 0 {
        return Err(Error::Sweep(format!(
            "{failed} of {} cases failed; their errors are in {}",
            study.cases.len(),
            root.join("summary.csv").display()
        )));
    }
    Ok(root)
}

/// Creates or reopens the sweep directory (rank 0) and locks it for this session: a directory
/// of another study, of the same study with other command-line PETSc options (`petsc`), or one
/// that is not a sweep's, is refused untouched. The study file and the options are written at
/// the first session (atomically, each only when absent: a later session rewrites neither).
/// Every observable of the study applies to every case whose scene loads (a case whose scene
/// does not is its own failure, recorded when it runs).
fn check_observables(study: &Study) -> Result<()> {
    for case in &study.cases {
        let Ok(scene) = LoadedScene::load(&case.scene, &study.overrides(case)) else { continue };
        let columns = crate::observe::observers::history_column_names(&scene)?;
        for spec in &study.observe {
            crate::io::observable::check(spec, &columns, scene.scene.time.t_end).map_err(|e| {
                Error::Sweep(format!("observe {e}; in case {} ({}), before anything ran", case.index, case.label()))
            })?;
        }
    }
    Ok(())
}

fn open_dir(root: &Path, text: &str, petsc: &[String], is_root: bool) -> Result<rundir::RunLock> {
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

/// The state of a case claimed in this session that has not ended.
const RUNNING: &str = "running";

/// summary.csv from every case's state on disk; returns the rows.
fn write_summary(root: &Path, study: &Study, plan: &Plan, observations: &Observations) -> Result<Vec<Row>> {
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

/// One group of ranks, running cases one after another.
struct Group<'a> {
    comm: &'a SimpleCommunicator,
    index: usize,
    root: &'a Path,
    study: &'a Study,
    plan: &'a Plan,
    observations: &'a Observations,
    args: &'a SweepArgs,
    stop: &'a StopRequest,
}

impl Group<'_> {
    fn leader(&self) -> bool {
        self.comm.rank() == 0
    }

    /// Claims and runs cases until none is left (or a stop signal, or a failure of the sweep
    /// itself — a failed case is not one).
    fn run(&self, order: Vec<usize>, complete_before: usize) -> Result<()> {
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
