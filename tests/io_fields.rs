//! Runs `tests/support/io_fields.rs` (the `io_fields` example target) under `mpirun` (1, 2 and 3 ranks, with empty pieces, a crash and
//! argument errors; 10-node tetrahedra, and 6-node triangles of a meridian) and checks the output
//! with `tests/support/check_fields.py` (h5py + numpy), and, where `pvpython` is installed, with
//! ParaView's own XDMF readers (`tests/support/check_paraview.py`).
//!
//! Environment: `POROPLAST_PYTHON` picks the Python (else the first of `python3`, `/usr/bin/python3`
//! that imports h5py and numpy); `POROPLAST_NO_PARAVIEW=1` skips the ParaView check (with a
//! warning); `POROPLAST_REQUIRE_PARAVIEW=1` (CI) makes a missing `pvpython` a failure. Like every
//! integration test these need `mpirun`: none returns early without it (`tests/architecture.rs`).

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

const MANIFEST: &str = env!("CARGO_MANIFEST_DIR");

/// The example binary, built next to this test (cargo test builds examples; if only this test
/// target was built, build the example now).
fn example() -> &'static Path {
    static EXE: OnceLock<PathBuf> = OnceLock::new();
    EXE.get_or_init(|| {
        let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
        let exe = deps.parent().unwrap().join("examples").join("io_fields");
        if !exe.exists() {
            let profile_release = deps.parent().unwrap().file_name().is_some_and(|n| n == "release");
            let mut c = Command::new(env!("CARGO"));
            c.args(["build", "--example", "io_fields", "--manifest-path", &format!("{MANIFEST}/Cargo.toml")]);
            if profile_release {
                c.arg("--release");
            }
            let st = c.status().expect("run cargo build --example io_fields");
            assert!(st.success() && exe.exists(), "could not build {}", exe.display());
        }
        exe
    })
}

/// A Python that imports h5py and numpy.
fn python() -> &'static str {
    static PY: OnceLock<String> = OnceLock::new();
    PY.get_or_init(|| {
        let candidates: Vec<String> = match std::env::var("POROPLAST_PYTHON") {
            Ok(p) => vec![p],
            Err(_) => vec!["python3".into(), "/usr/bin/python3".into()],
        };
        for p in &candidates {
            let ok = Command::new(p)
                .args(["-c", "import h5py, numpy"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .is_ok_and(|s| s.success());
            if ok {
                return p.clone();
            }
        }
        panic!("no Python with h5py and numpy among {candidates:?}; install them or set POROPLAST_PYTHON");
    })
}

/// Runs `cmd` with a time limit, so that a hang fails the test instead of blocking it.
fn run_limited(mut cmd: Command, limit: Duration) -> Output {
    let mut child = cmd.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("spawn");
    let t0 = Instant::now();
    loop {
        if child.try_wait().expect("wait").is_some() {
            return child.wait_with_output().expect("output");
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            let out = child.wait_with_output().expect("output");
            panic!(
                "{cmd:?} did not finish in {limit:?} (hang?)\nstdout:\n{}\nstderr:\n{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn out_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mpi_fields").join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn mpirun(ranks: usize, dir: &Path, args: &[&str]) -> Output {
    let _cores = crate::common::cores(ranks);
    let mut c = Command::new("mpirun");
    c.args(["--oversubscribe", "-n", &ranks.to_string()])
        .arg(example())
        .arg(dir)
        .args(args)
        // No 2 s wait before the ranks of a failed launch are killed (tests/common/mod.rs).
        .env("OMPI_MCA_odls_base_sigkill_timeout", "0");
    crate::common::mpi_env(&mut c);
    run_limited(c, Duration::from_secs(120))
}

fn text(o: &Output) -> String {
    format!("stdout:\n{}\nstderr:\n{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

fn check(dir: &Path, steps: usize) {
    let mut c = Command::new(python());
    c.arg(format!("{MANIFEST}/tests/support/check_fields.py"))
        .arg(dir)
        .args(["--steps", &steps.to_string(), "--straight-edges", "--expect"])
        .arg(dir.join("expect.json"));
    let o = run_limited(c, Duration::from_secs(120));
    assert!(o.status.success(), "check_fields.py failed on {}\n{}", dir.display(), text(&o));
}

fn run_case(name: &str, ranks: usize, case: &str) -> PathBuf {
    let dir = out_dir(name);
    let o = mpirun(ranks, &dir, &[case]);
    assert!(o.status.success(), "mpirun -n {ranks} io_fields {case} failed\n{}", text(&o));
    check(&dir, 3);
    dir
}

/// Opens `dir` with each of ParaView's three XDMF readers (`tests/support/check_paraview.py`),
/// unless `POROPLAST_NO_PARAVIEW=1` or `pvpython` is missing (then a warning; a failure with
/// `POROPLAST_REQUIRE_PARAVIEW=1`, as in CI). The three share one `pvpython` (1.5 s to start);
/// should that fail, each runs in a process of its own to name the failing one (an XDMF 3 reader
/// may abort the process).
fn paraview_check(dir: &Path) {
    let no_pv = std::env::var("POROPLAST_NO_PARAVIEW").is_ok_and(|v| v == "1");
    static HAS_PV: OnceLock<bool> = OnceLock::new();
    let has_pv =
        *HAS_PV.get_or_init(|| Command::new("pvpython").arg("--version").output().is_ok_and(|o| o.status.success()));
    // CI installs ParaView (.ci/run): there a missing pvpython is a failure, not a skip.
    let required = std::env::var("POROPLAST_REQUIRE_PARAVIEW").is_ok_and(|v| v == "1");
    assert!(
        has_pv || !required,
        "pvpython not found, and POROPLAST_REQUIRE_PARAVIEW=1 (ci/setup-paraview.sh installs it)"
    );
    if no_pv || !has_pv {
        eprintln!(
            "\n******** WARNING: ParaView reader check SKIPPED: {} ********\n\
             ******** (ci/setup.sh installs paraview + python3-paraview where Debian has them) ********\n",
            if no_pv { "POROPLAST_NO_PARAVIEW=1" } else { "pvpython not found" }
        );
        return;
    }
    let check = |readers: &[&str]| {
        let mut c = Command::new("pvpython");
        c.arg(format!("{MANIFEST}/tests/support/check_paraview.py")).arg(dir).args(readers);
        let o = run_limited(c, Duration::from_secs(300));
        (o.status.success() && String::from_utf8_lossy(&o.stdout).contains("check_paraview: OK"), o)
    };
    const READERS: [&str; 3] = ["XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT"];
    if check(&READERS).0 {
        return;
    }
    for reader in READERS {
        let (ok, o) = check(&[reader]);
        assert!(ok, "ParaView {reader} check failed on {}\n{}", dir.display(), text(&o));
    }
    panic!("ParaView's readers failed together on {} but each passed alone", dir.display());
}

#[test]
fn two_ranks_split_and_paraview() {
    let dir = run_case("split2", 2, "split");
    paraview_check(&dir);
}

#[test]
fn two_ranks_meridian_and_paraview() {
    // check_fields.py with expect.json ("family": "Tri6"), then without it: the family is then
    // inferred from the width of /mesh/topology.
    let dir = run_case("meridian2", 2, "meridian");
    let mut c = Command::new(python());
    c.arg(format!("{MANIFEST}/tests/support/check_fields.py")).arg(&dir).args(["--steps", "3", "--straight-edges"]);
    let o = run_limited(c, Duration::from_secs(120));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && out.contains("check_fields: OK") && out.contains(": Tri6, 9 nodes, 2 cells, 3 steps"),
        "check_fields.py (inferred)\n{}",
        text(&o)
    );
    paraview_check(&dir);
}

#[test]
fn two_ranks_last_rank_owns_no_cells() {
    run_case("nocells2", 2, "nocells-last");
}

#[test]
fn two_ranks_last_rank_owns_nothing() {
    run_case("empty2", 2, "empty-last");
}

#[test]
fn three_ranks_first_rank_owns_no_cells() {
    run_case("split3", 3, "split");
}

#[test]
fn single_rank() {
    run_case("single", 1, "split");
}

#[test]
fn errors_on_one_rank_reach_all_ranks() {
    for case in ["bad-len", "bad-names"] {
        let dir = out_dir(case);
        let o = mpirun(2, &dir, &[case]);
        let out = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(3), "{case}: expected exit code 3\n{}", text(&o));
        for r in 0..2 {
            assert!(
                out.contains(&format!("EXPECTED_ERROR rank {r}: ")),
                "{case}: rank {r} did not report\n{}",
                text(&o)
            );
        }
        // The failed step wrote nothing; the step before it is intact.
        check(&dir, 1);
    }
    let o = mpirun(2, &out_dir("bad-mesh"), &["bad-mesh"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(2), "bad-mesh: expected exit code 2\n{}", text(&o));
    for r in 0..2 {
        assert!(out.contains(&format!("ERROR rank {r}: ")) && out.contains("do not tile"), "bad-mesh\n{}", text(&o));
    }
    let out = String::from_utf8_lossy(&mpirun(2, &out_dir("bad-len-msg"), &["bad-len"]).stdout).to_string();
    assert!(out.contains("has 8 values on this rank, expected 7"), "{out}");
    assert!(out.contains("EXPECTED_ERROR rank 0: ") && out.contains("(reported by rank 1)"), "{out}");
}

#[test]
fn crashed_run_keeps_completed_steps() {
    for k in [0, 2] {
        let dir = out_dir(&format!("abort{k}"));
        let o = mpirun(2, &dir, &["split", "--abort-after", &k.to_string()]);
        assert!(!o.status.success(), "MPI_Abort should make mpirun fail\n{}", text(&o));
        check(&dir, k);
    }
}

#[test]
fn running_run_is_readable() {
    let dir = out_dir("running");
    let mut c = Command::new("mpirun");
    c.args(["--oversubscribe", "-n", "2"])
        .arg(example())
        .arg(&dir)
        .args(["split", "--pause-after", "2"])
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    crate::common::mpi_env(&mut c);
    let mut child = c.spawn().expect("spawn mpirun");
    let t0 = Instant::now();
    while !dir.join("paused").exists() {
        if t0.elapsed() > Duration::from_secs(120) || child.try_wait().unwrap().is_some() {
            let _ = child.kill();
            panic!("the run did not pause");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    // The file is still open for writing by both ranks: two complete steps must be visible.
    let result = std::panic::catch_unwind(|| check(&dir, 2));
    std::fs::write(dir.join("resume"), "").unwrap();
    let st = child.wait().unwrap();
    if let Err(e) = result {
        std::panic::resume_unwind(e);
    }
    assert!(st.success());
    std::fs::remove_file(dir.join("paused")).unwrap();
    std::fs::remove_file(dir.join("resume")).unwrap();
    check(&dir, 3);
}
