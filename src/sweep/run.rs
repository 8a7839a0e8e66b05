//! The course of a sweep: the study read and checked, the directory and the store opened, the
//! cases' order decided, the groups run, and the world's outcome agreed.

use super::args::SweepArgs;
use super::directory::open_dir;
use super::group::Group;
use super::plan::{write_summary, Plan};
use super::schedule;
use super::store::{self, CaseRecord};
use super::study::Study;
use super::summary::{Observations, State};
use crate::driver::{self, signals::StopRequest};
use crate::error::{Error, Result};
use crate::io::rundir;
use crate::parallel::{agree, agree_ranked, broadcast_vec, on_root, path_from_root};
use crate::scene::LoadedScene;
use mpi::topology::{Color, SimpleCommunicator};
use mpi::traits::*;
use std::path::PathBuf;

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
