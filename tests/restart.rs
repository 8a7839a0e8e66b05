//! Checkpoint and restart: a run killed (`kill -9`) or stopped by a signal, then resumed with
//! `poroplast resume`, gives the history of the uninterrupted run — the same rows and times, and
//! every value equal to 1e-10 on the same rank count; on another rank count to solver
//! tolerance; a checkpoint or fields file damaged by the kill is replaced by the one before.
//! The scene: the remodelling experiment on a coarse mesh, to t = 8 s (the ramp and
//! the start of the hold), checkpoints every 5 steps.

use crate::common::*;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Child, Command};
use std::time::{Duration, Instant};

const SETS: [&str; 6] = [
    "mesh.params.h=40",
    "mesh.params.h_pole=20",
    "time.t_end=8",
    "output.checkpoint_every=5",
    "output.fields_every=4",
    "output.fields_at=[]",
];

fn args(out: &Path, extra: &[&str]) -> Vec<String> {
    let mut a = vec!["run".to_string(), "remodel_40".into(), "--out".into(), out.display().to_string(), "-q".into()];
    for s in SETS.iter().chain(extra) {
        a.extend(["--set".into(), s.to_string()]);
    }
    a
}

/// Starts a run in its own process group: the binary itself (1 rank, MPI singleton) or under
/// mpirun.
fn spawn(np: usize, out: &Path) -> Child {
    spawn_with(np, out, &[])
}

/// [`spawn`] with more `--set` overrides.
fn spawn_with(np: usize, out: &Path, extra: &[&str]) -> Child {
    launch(np).args(args(out, extra)).process_group(0).spawn().expect("the run could not be started")
}

/// The uninterrupted run on 1 rank that the killed and stopped runs are compared with, run once
/// per test process: its directory.
fn uninterrupted() -> &'static Path {
    static RUN: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    RUN.get_or_init(|| {
        let reference = scratch("restart_uninterrupted").join("reference");
        assert!(spawn(1, &reference).wait().unwrap().success(), "the reference run failed");
        reference
    })
}

/// [`spawn_with`], once the run has written the checkpoint of `step`.
fn running(np: usize, out: &Path, extra: &[&str], step: usize) -> Child {
    let mut child = spawn_with(np, out, extra);
    wait_for_checkpoint(&mut child, out, step);
    child
}

/// Waits until the checkpoint of `step` exists (or the run ended).
fn wait_for_checkpoint(child: &mut Child, out: &Path, step: usize) {
    let file = out.join(format!("checkpoints/step-{step:08}.h5"));
    let start = Instant::now();
    while !file.exists() {
        assert!(child.try_wait().unwrap().is_none(), "the run ended before writing {}", file.display());
        assert!(start.elapsed() < Duration::from_secs(300), "no {} after 300 s", file.display());
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The step of the newest checkpoint of a run directory.
fn newest_checkpoint(out: &Path) -> usize {
    std::fs::read_dir(out.join("checkpoints"))
        .unwrap()
        .filter_map(|e| {
            let n = e.unwrap().file_name().into_string().unwrap();
            n.strip_prefix("step-")?.strip_suffix(".h5")?.parse().ok()
        })
        .max()
        .expect("a checkpoint")
}

/// The run in `dir` says it stopped by a signal, and its newest checkpoint is the step it
/// stopped at.
fn assert_stopped_with_its_checkpoint(dir: &Path) {
    let why = std::fs::read_to_string(dir.join("status.txt")).unwrap();
    assert!(why.starts_with("stopped by a signal after step"), "{why}");
    let step: usize = why["stopped by a signal after step ".len()..].split(' ').next().unwrap().parse().unwrap();
    assert_eq!(newest_checkpoint(dir), step, "the checkpoint of the step it stopped at");
}

/// Sends `sig` to the process group of `child`.
fn signal_group(child: &Child, sig: &str) {
    let ok = Command::new("kill").args([sig, "--", &format!("-{}", child.id())]).status().unwrap().success();
    assert!(ok, "kill {sig} failed");
}

/// Sends `sig` to `child` alone.
fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill").args([sig, &child.id().to_string()]).status().unwrap().success();
    assert!(ok, "kill {sig} failed");
}

/// Same columns, and [`assert_history_within`] at `tol`.
fn assert_same_history(a: &History, b: &History, tol: f64, what: &str) {
    assert_eq!(a.names, b.names, "{what}: columns");
    assert_history_within(a, b, tol, what);
}

/// The comparison itself: NaN in both passes in a column documented to be NaN, and fails in any
/// other; a NaN against a number fails in both.
#[test]
fn nan_is_equal_only_in_the_documented_columns() {
    let history = |force: f64, r3: f64| History {
        names: ["step", "time", "force_total_mg", "R3"].map(String::from).to_vec(),
        rows: vec![vec![0.0, 0.0, 1.0, f64::NAN], vec![1.0, 0.5, force, r3]],
    };
    let same = |a: History, b: History| {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| assert_same_history(&a, &b, 1e-10, "test"))).is_ok()
    };
    assert!(same(history(2.0, 3.0), history(2.0, 3.0)));
    assert!(same(history(2.0, f64::NAN), history(2.0, f64::NAN)), "R3 is NaN before contact");
    assert!(!same(history(2.0, f64::NAN), history(2.0, 3.0)), "NaN against a number");
    assert!(!same(history(f64::NAN, 3.0), history(f64::NAN, 3.0)), "a NaN force is a failure");
    assert!(!same(history(2.0, 3.0), history(2.0 + 1e-6, 3.0)), "a different force");
}

/// [`NAN_COLUMNS`] are the columns docs/reference-run-directory.md's `history.csv` table says
/// may be NaN: a row of that table that mentions NaN names exactly these.
#[test]
fn nan_columns_are_the_documented_ones() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/reference-run-directory.md")).unwrap();
    let table = doc.split("## `history.csv`").nth(1).expect("the history.csv section").split("\n## ").next().unwrap();
    let mut documented: Vec<&str> = table
        .lines()
        .filter(|l| l.starts_with("| `") && l.contains("NaN"))
        .flat_map(|l| l.split('|').nth(1).unwrap().split('`').skip(1).step_by(2))
        .collect();
    documented.sort();
    let mut ours = NAN_COLUMNS.to_vec();
    ours.sort();
    assert_eq!(documented, ours, "the history.csv columns the docs say may be NaN");
}

/// A resumed run's summary is the whole run's: the uninterrupted run's peak force and largest
/// p (to 1e-10; its step and place the same), and the same steps.
fn assert_same_summary(a: &Path, b: &Path, what: &str) {
    let (sa, sb) = (Summary::read(a), Summary::read(b));
    let close = |k: &str| {
        let (x, y) = (sa.num(k).unwrap(), sb.num(k).unwrap());
        assert!((x - y).abs() <= 1e-10 * x.abs().max(1.0), "{what}: {k} {y} vs the uninterrupted {x}");
    };
    for k in ["plates.peak_force_mg", "pressure.max_p_kPa"] {
        close(k);
    }
    for k in ["steps", "t_end_s", "plates.peak_force_time_s", "pressure.max_p_time_s"] {
        assert_eq!(sa.num(k), sb.num(k), "{what}: {k}");
    }
    assert_eq!(sa.max_p_at(), sb.max_p_at(), "{what}: the place of the largest p");
    let status = std::fs::read_to_string(b.join("status.txt")).unwrap();
    assert!(status.starts_with("completed: ") && status.contains("summary.toml"), "{what}: {status}");
}

fn resume(np: usize, dir: &Path) {
    run_ok(np, &["resume", &dir.display().to_string(), "-q"]);
    let status = std::fs::read_to_string(dir.join("status.txt")).unwrap();
    assert!(status.starts_with("completed"), "{status}");
}

#[test]
fn killed_or_stopped_runs_resume_to_the_uninterrupted_history() {
    // The shared run first: a test waiting for another to finish it holds no core.
    let reference = uninterrupted();
    let _cores = cores(1); // every run of the test, one at a time
    let d = scratch("restart_same_ranks");
    let a = History::read(reference);
    assert!(a.rows.len() > 30, "{} rows", a.rows.len());

    // kill -9 after the checkpoint of step 15: at most the steps since are lost, then redone.
    let killed = d.join("killed");
    let mut child = running(1, &killed, &[], 15);
    signal_group(&child, "-KILL");
    child.wait().unwrap();
    assert!(!killed.join("status.txt").exists(), "a killed run says nothing");
    // As if the kill had cut the writing of the newest checkpoint and of fields.h5 short: the
    // checkpoint before it and the copy of the fields taken at the last checkpoint take over.
    let cut_short = |p: &Path, keep: u64| {
        let f = std::fs::OpenOptions::new().write(true).open(p).unwrap();
        f.set_len(keep).unwrap();
    };
    let newest = killed.join(format!("checkpoints/step-{:08}.h5", newest_checkpoint(&killed)));
    cut_short(&newest, 1000);
    let fields_len = std::fs::metadata(killed.join("fields.h5")).unwrap().len();
    cut_short(&killed.join("fields.h5"), fields_len / 2);
    let out = poroplast(1, &["resume", &killed.display().to_string(), "-q"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("trying the checkpoint before it"), "{stderr}");
    assert!(stderr.contains("the damaged file is kept as"), "{stderr}");
    assert!(killed.join("fields.damaged.h5").is_file());
    assert_same_history(&a, &History::read(&killed), 1e-10, "kill -9, damaged files, resumed");
    assert_same_summary(reference, &killed, "kill -9, resumed");
    let xdmf = std::fs::read_to_string(killed.join("fields.xdmf")).unwrap();
    let ref_xdmf = std::fs::read_to_string(reference.join("fields.xdmf")).unwrap();
    assert_eq!(xdmf.matches("<Time Value=").count(), ref_xdmf.matches("<Time Value=").count());

    // SIGTERM: a checkpoint at the next step boundary, a clean stop with exit code 75. After
    // the checkpoint of step 20 (t = 5.08 s), past the largest p (at the end of the ramp, 5 s):
    // the resumed run's summary has it from the checkpoint.
    let stopped = d.join("stopped");
    let mut child = running(1, &stopped, &[], 20);
    signal(&child, "-TERM");
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(75), "exit code of a stopped run");
    assert_stopped_with_its_checkpoint(&stopped);
    let rows_at_stop = History::read(&stopped).rows.len();
    assert!(rows_at_stop < a.rows.len(), "stopped after {rows_at_stop} rows of {}", a.rows.len());
    resume(1, &stopped);
    assert_same_history(&a, &History::read(&stopped), 1e-10, "SIGTERM, resumed");
    assert_same_summary(reference, &stopped, "SIGTERM, resumed");
    // The fields continue too: one XDMF step per fields.h5 step, times increasing.
    let xdmf = std::fs::read_to_string(stopped.join("fields.xdmf")).unwrap();
    let ref_xdmf = std::fs::read_to_string(reference.join("fields.xdmf")).unwrap();
    assert_eq!(xdmf.matches("<Time Value=").count(), ref_xdmf.matches("<Time Value=").count());
}

#[test]
fn a_run_directory_in_use_is_refused() {
    let _cores = cores(1); // every run of the test, one at a time
    let d = scratch("restart_in_use");
    let run = d.join("run");
    let mut child = running(1, &run, &[], 5);
    // A second job into the same directory (a resubmission while the first still runs).
    let dir = run.display().to_string();
    for args in [vec!["resume", dir.as_str()], vec!["run", "terzaghi", "--out", dir.as_str(), "--force"]] {
        let out = poroplast(1, &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} went ahead while the run was going");
        assert!(stderr.contains("is in use by another poroplast run (pid"), "{args:?}: {stderr}");
    }
    // The lock goes with the process, however it ends.
    signal_group(&child, "-KILL");
    child.wait().unwrap();
    resume(1, &run);
}

#[test]
fn signals_that_arrive_twice_still_stop_with_a_checkpoint() {
    let _cores = cores(1); // every run of the test, one at a time
                           // A scheduler signals every process of a job and mpirun forwards the signal too: a rank
                           // can get it twice (or SIGINT from the terminal and SIGTERM from mpirun). Still one clean
                           // stop with a checkpoint.
    let d = scratch("restart_two_signals");
    let run = d.join("run");
    let mut child = running(1, &run, &[], 5);
    signal(&child, "-INT");
    signal(&child, "-TERM");
    assert_eq!(child.wait().unwrap().code(), Some(75), "a clean stop");
    assert_stopped_with_its_checkpoint(&run);
    resume(1, &run);
}

#[test]
fn the_iterative_solver_resumes_exactly_from_a_periodic_checkpoint() {
    let _cores = cores(1); // every run of the test, one at a time
                           // The fieldsplit preset's AMG keeps its interpolation between setups, which a checkpoint
                           // cannot save: at the periodic checkpoints the uninterrupted run renews it, as a resumed
                           // one starts.
    let d = scratch("restart_fieldsplit");
    let fieldsplit = ["solver.preset=\"fieldsplit\""];
    let reference = d.join("reference");
    assert!(spawn_with(1, &reference, &fieldsplit).wait().unwrap().success(), "the reference run failed");
    let killed = d.join("killed");
    let mut child = running(1, &killed, &fieldsplit, 15);
    signal_group(&child, "-KILL");
    child.wait().unwrap();
    resume(1, &killed);
    let (a, b) = (History::read(&reference), History::read(&killed));
    assert_same_history(&a, &b, 1e-10, "fieldsplit, kill -9, resumed");
    assert_eq!(a.col("ksp_its"), b.col("ksp_its"), "the same Krylov iterations");
}

#[test]
fn a_two_rank_run_stopped_by_mpirun_resumes_on_one_rank() {
    let reference = uninterrupted();
    let _cores = cores(2); // its runs, on 2 ranks and then 1
    let d = scratch("restart_other_ranks");
    // mpirun forwards SIGUSR1 to the ranks and exits with their code.
    let stopped = d.join("stopped");
    let mut child = running(2, &stopped, &[], 10);
    signal(&child, "-USR1");
    assert_eq!(child.wait().unwrap().code(), Some(75), "mpirun's exit code after SIGUSR1");
    assert_stopped_with_its_checkpoint(&stopped);
    resume(1, &stopped);
    // Another partition: the same steps, values to solver tolerance.
    assert_same_history(&History::read(reference), &History::read(&stopped), 1e-6, "2 ranks, resumed on 1");
    // The fields written on 1 rank use their own mesh numbering (/mesh_1).
    let xdmf = std::fs::read_to_string(stopped.join("fields.xdmf")).unwrap();
    assert!(xdmf.contains("/mesh_1/coordinates") && xdmf.contains("/mesh/coordinates"));
}

/// Ctrl-C under mpirun: Open MPI's mpirun (4.1) answers SIGINT (and SIGTERM) by setting its own
/// exit status to 1 before any rank has seen a signal, then sends the ranks SIGTERM, and SIGKILL
/// 1 s later (`odls_base_sigkill_timeout`); it cannot be told to forward SIGINT instead
/// (`ess_base_forward_signals` refuses it). The ranks still checkpoint and stop, and
/// `status.txt` says so: that, not mpirun's exit code, is what a resume loop under mpirun keys on
/// (docs/howto-long-runs.md, "Stopping a run").
#[test]
fn ctrl_c_to_mpirun_stops_the_ranks_with_a_checkpoint() {
    let _cores = cores(2);
    let d = scratch("restart_sigint_mpirun");
    // mpirun takes its time to pass the signal on (measured: 13 steps, about 1 s): a longer run,
    // lest it complete first.
    let stopped = d.join("stopped");
    let mut child = running(2, &stopped, &["time.t_end=30"], 10);
    signal(&child, "-INT");
    let status = child.wait().unwrap();
    assert_stopped_with_its_checkpoint(&stopped);
    assert_eq!(status.code(), Some(1), "Open MPI's mpirun exits 1 after SIGINT, whatever the ranks return");
}

/// Ctrl-C to `poroplast mpirun`: as a terminal sends it, to the launcher's process group (mpirun
/// has its own). The ranks checkpoint and stop, and the exit code is theirs, 75, as on one rank.
#[test]
fn ctrl_c_to_poroplast_mpirun_stops_with_75_and_a_checkpoint() {
    let _cores = cores(2);
    let d = scratch("restart_sigint_launcher");
    let stopped = d.join("stopped");
    let mut words: Vec<String> = ["mpirun", "-n", "2", "--mpirun-arg=--oversubscribe"].map(String::from).to_vec();
    words.extend(args(&stopped, &["time.t_end=30"]));
    let mut child = launch(1).args(&words).process_group(0).spawn().expect("poroplast mpirun could not be started");
    wait_for_checkpoint(&mut child, &stopped, 10);
    signal_group(&child, "-INT");
    let status = child.wait().unwrap();
    assert_stopped_with_its_checkpoint(&stopped);
    assert_eq!(status.code(), Some(75), "poroplast mpirun's exit code after Ctrl-C");
}

/// Ctrl-C to `poroplast mpirun` during the set-up (the 3-D quarter: mesh, partition, PETSc,
/// settling and the first step take a second or more): the launcher holds the stop back until both
/// ranks catch signals (their files in its ready directory), then the ranks stop at the set-up's
/// next check with exit code 76 and nothing written, instead of dying of SIGUSR1 (exit 138).
#[test]
fn ctrl_c_during_the_set_up_stops_with_76_and_writes_nothing() {
    let _cores = cores(2);
    let d = scratch("restart_sigint_setup");
    let stopped = d.join("stopped");
    let words = ["mpirun", "-n", "2", "--mpirun-arg=--oversubscribe", "run", "reference", "--out"];
    let mut child =
        launch(1).args(words).arg(&stopped).process_group(0).spawn().expect("poroplast mpirun could not be started");
    // Signalled as soon as its ranks are there: at once, the ready directory's files being the
    // earliest sign of them (a signal before them would be held back too).
    let ready = std::env::temp_dir().join(format!("poroplast-launch-{}", child.id()));
    let start = Instant::now();
    while std::fs::read_dir(&ready).map_or(0, |d| d.count()) < 2 {
        assert!(child.try_wait().unwrap().is_none(), "the run ended before its ranks were ready");
        assert!(start.elapsed() < Duration::from_secs(60), "no ready ranks in {} after 60 s", ready.display());
        std::thread::sleep(Duration::from_millis(2));
    }
    signal_group(&child, "-INT");
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(76), "poroplast mpirun's exit code after Ctrl-C in the set-up");
    assert!(!stopped.exists(), "a run stopped in its set-up wrote {}", stopped.display());
    assert!(!ready.exists(), "the launcher left its ready directory behind");
}

#[test]
fn resume_refuses_what_it_cannot_continue_and_restarts_what_never_checkpointed() {
    let _cores = cores(1); // every run of the test, one at a time
    let d = scratch("restart_refusals");
    let fails = |dir: &Path, expect: &str| {
        let out = poroplast(1, &["resume", &dir.display().to_string()]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "resume {} should fail", dir.display());
        let line = stderr.lines().find(|l| l.starts_with("poroplast: error:")).unwrap_or_else(|| panic!("{stderr}"));
        assert!(line.contains(expect), "`{expect}` expected in: {line}");
    };
    fails(&d.join("nothing"), "not a run directory");
    // A completed run: nothing to do, and nothing changes.
    let run = d.join("run");
    run_ok(1, &["run", "terzaghi", "--set", "time.t_end=0.002", "--out", &run.display().to_string(), "-q"]);
    let before = std::fs::read(run.join("history.csv")).unwrap();
    let out = run_ok(1, &["resume", &run.display().to_string()]);
    assert!(out.contains("nothing to resume"), "{out}");
    assert_eq!(before, std::fs::read(run.join("history.csv")).unwrap());
    // Killed before its first checkpoint: it runs again from t = 0, to the same history.
    std::fs::remove_file(run.join("status.txt")).unwrap();
    std::fs::write(run.join("history.csv"), &before[..before.len() / 2]).unwrap();
    run_ok(1, &["resume", &run.display().to_string(), "-q"]);
    let again = std::fs::read_to_string(run.join("history.csv")).unwrap();
    let strip = |t: &str| t.lines().map(|l| l.rsplit_once(',').unwrap().0.to_string()).collect::<Vec<_>>(); // no wall_s
    assert_eq!(strip(&again), strip(&String::from_utf8(before).unwrap()));
    // A new run written over it (--force) does not inherit its checkpoints or its status.
    let r = run.display().to_string();
    let rerun = |every: &str| {
        let set = format!("output.checkpoint_every={every}");
        run_ok(1, &["run", "terzaghi", "--set", "time.t_end=0.002", "--set", &set, "--out", &r, "--force", "-q"]);
    };
    rerun("1");
    assert!(run.join("checkpoints").is_dir());
    rerun("0");
    assert!(!run.join("checkpoints").exists(), "the earlier run's checkpoints were left behind");
}

/// The same on the meridian (`mesh.geometry = axisymmetric`, fine enough that the run outlasts the
/// signal), with surface tension (γ = 5 mN/m): killed after the checkpoint of step 10 and
/// resumed, the history of the uninterrupted run to 1e-10.
#[test]
fn a_killed_meridian_run_resumes_to_the_uninterrupted_history() {
    let _cores = cores(1); // every run of the test, one at a time
    let d = scratch("restart_meridian");
    let meridian = ["mesh.geometry=axisymmetric", "mesh.params.h=15", "mesh.params.h_pole=5", "surface.tension=5"];
    let reference = d.join("reference");
    assert!(spawn_with(1, &reference, &meridian).wait().unwrap().success(), "the reference run failed");
    let a = History::read(&reference);
    let killed = d.join("killed");
    let mut child = running(1, &killed, &meridian, 10);
    signal_group(&child, "-KILL");
    child.wait().unwrap();
    assert!(History::read(&killed).rows.len() < a.rows.len(), "the run ended before the kill");
    resume(1, &killed);
    assert_same_history(&a, &History::read(&killed), 1e-10, "meridian, kill -9, resumed");
}
