//! Shared helpers for the integration tests: run the binary under mpirun on cores shared by the
//! tests of a binary, read history.csv.
// Each test binary uses some of these.
#![allow(dead_code)]

use std::cell::Cell;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub mod young_laplace;

/// The machine's cores, of which a test holds one per MPI rank it runs. The test binaries run
/// side by side, each with as many tests at a time as there are cores (`ci/test.sh`), and take
/// cores from one pool: 1-rank runs go side by side while a 2-rank run has the two cores of a
/// 2-core machine to itself: no more processes than cores, whose MPI ranks would otherwise spin
/// against each other. The pool is a lock file per core (`CARGO_TARGET_TMPDIR/cores/`), so the
/// kernel frees a crashed test's cores.
pub struct Cores {
    n: usize,
    _locks: Vec<File>,
    since: std::time::Instant,
}

thread_local! {
    /// Cores the current test's thread holds: a launch within them takes no more.
    static HELD: Cell<usize> = const { Cell::new(0) };
}

/// Waits for `n` cores (at most the machine's), taken all at once or not at all: a waiter never
/// holds some cores while it waits for more (two 2-rank tests each holding one would wait for
/// each other forever). No queue: whenever cores are free, a waiting test that fits takes them,
/// so a 2-rank test does not keep a core idle while it waits for the second (it may wait longer
/// behind 1-rank tests; the work is the same). A test that launches several runs at once, or
/// must not share the machine, takes them all first.
pub fn cores(n: usize) -> Cores {
    let total = std::thread::available_parallelism().map_or(1, |c| c.get());
    let held = HELD.get();
    let need = n.min(total).saturating_sub(held);
    if need == 0 {
        return Cores { n: 0, _locks: Vec::new(), since: std::time::Instant::now() };
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cores");
    std::fs::create_dir_all(&dir).expect("the cores' lock directory");
    loop {
        let mut taken: Vec<File> = Vec::new();
        for i in 0..total {
            // A core this thread took is locked against its new handle too: never taken twice.
            let core =
                std::fs::OpenOptions::new().create(true).truncate(false).write(true).open(dir.join(format!("core{i}")));
            let core = core.expect("a core's lock file");
            if taken.len() < need && core.try_lock().is_ok() {
                taken.push(core);
            }
        }
        if taken.len() == need {
            HELD.set(held + need);
            return Cores { n: need, _locks: taken, since: std::time::Instant::now() };
        }
        drop(taken);
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}

impl Drop for Cores {
    fn drop(&mut self) {
        // The lock files close (and unlock) after this.
        HELD.set(HELD.get() - self.n);
        // POROPLAST_CORES_LOG=FILE: a line per hold (test, cores, seconds), to see which tests
        // take the machine's time (`POROPLAST_CORES_LOG=FILE ci/run-tests.sh`, docs/developer.md).
        if let (Ok(log), true) = (std::env::var("POROPLAST_CORES_LOG"), self.n > 0) {
            use std::io::Write;
            let test = std::thread::current().name().unwrap_or("?").to_string();
            let line = format!("{test} {} {:.3}\n", self.n, self.since.elapsed().as_secs_f64());
            if let Ok(mut f) = std::fs::OpenOptions::new().create(true).append(true).open(log) {
                let _ = f.write_all(line.as_bytes());
            }
        }
    }
}

/// Open MPI binds the ranks of a job of one or two to cores, counted from the first: two 1-rank
/// jobs side by side would share core 0 (measured: twice the time). Unbound, each has a core.
pub const NO_BINDING: &str = "none";

/// `poroplast` on `np` MPI ranks in the tests' MPI environment ([`mpi_env`]), to be given its
/// arguments. One rank is the binary itself, an MPI singleton: `mpirun -n 1` costs 0.4 s of
/// start-up and exit per launch, most of the time of a run that stops at its input (the tests
/// launch hundreds).
pub fn launch(np: usize) -> Command {
    let mut cmd = if np == 1 {
        Command::new(env!("CARGO_BIN_EXE_poroplast"))
    } else {
        let mut c = Command::new("mpirun");
        c.args(["-n", &np.to_string(), "--oversubscribe"]).arg(env!("CARGO_BIN_EXE_poroplast"));
        c
    };
    mpi_env(&mut cmd);
    cmd
}

/// Runs `poroplast <args>` on `np` MPI ranks ([`launch`]), on `np` cores. The tests of what
/// `mpirun` does with signals spawn [`launch`]'s command themselves.
pub fn poroplast(np: usize, args: &[&str]) -> Output {
    let _cores = cores(np);
    let mut cmd = launch(np);
    cmd.args(args);
    // After a rank exits non-zero, mpirun waits this long (1 s by default, twice) before killing
    // the others, which have finished too: a failing case then costs 2 s instead of 0.2 s. The
    // tests that stop runs by signals launch mpirun themselves and keep the default.
    cmd.env("OMPI_MCA_odls_base_sigkill_timeout", "0");
    cmd.output().expect("mpirun could not be started")
}

/// The environment of the tests' MPI launches: Open MPI as root, shared memory, ranks unbound
/// (see [`NO_BINDING`]), and the shared mesh cache.
pub fn mpi_env(cmd: &mut Command) -> &mut Command {
    cmd.env("OMPI_ALLOW_RUN_AS_ROOT", "1").env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    cmd.env("OMPI_MCA_btl", "self,vader").env("OMPI_MCA_pml", "ob1");
    cmd.env("OMPI_MCA_hwloc_base_binding_policy", NO_BINDING);
    cmd.env("POROPLAST_CACHE", cache_dir())
}

/// Runs and panics with both output streams if the run failed.
pub fn run_ok(np: usize, args: &[&str]) -> String {
    expect_success(&poroplast(np, args), &format!("poroplast {args:?} on {np} rank(s)"))
}

/// The standard output of a finished process; panics with both streams if it failed.
pub fn expect_success(out: &std::process::Output, what: &str) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{what} failed\nstdout:\n{stdout}\nstderr:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// Mesh cache shared by all tests (meshes are generated once).
pub fn cache_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesh-cache")
}

/// A fresh, empty directory for one test's outputs.
pub fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Path of a shipped scene file.
pub fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/scenes").join(format!("{name}.toml")).display().to_string()
}

/// Writes a variant of a shipped scene with some lines replaced (`from` → `to`), into `dir`.
pub fn scene_variant(name: &str, dir: &Path, edits: &[(&str, &str)]) -> String {
    let mut text = std::fs::read_to_string(scene(name)).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "scene {name} has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    let p = dir.join(format!("{name}-variant.toml"));
    std::fs::write(&p, text).unwrap();
    p.display().to_string()
}

/// All files under a directory (recursively) with their contents: an earlier run's, to show
/// that bad input left it untouched.
pub fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v = Vec::new();
    for p in std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()) {
        if p.is_dir() {
            v.extend(snapshot(&p));
        } else {
            v.push((p.display().to_string(), std::fs::read(&p).unwrap()));
        }
    }
    v.sort();
    v
}

/// The `history.csv` columns that may hold NaN: the Laplace reading where it does not apply
/// (before upper contact, too few free nodes) and the porosity of a material without a solid
/// fraction. docs/reference-run-directory.md says so in their rows and in no other
/// (`restart::nan_columns_are_the_documented_ones`); every other column is a number in every row.
pub const NAN_COLUMNS: [&str; 5] = ["R1", "R2", "R3", "sigma_app", "probe_porosity"];

/// Runs the scene file `scene` quietly on `np` ranks into `out` with the `--set` overrides `sets`;
/// its history.
pub fn run_with_sets(np: usize, scene: &Path, out: &Path, sets: &[String]) -> History {
    let mut args = vec!["run".to_string(), scene.display().to_string(), "-q".into(), "--out".into()];
    args.push(out.display().to_string());
    for s in sets {
        args.extend(["--set".to_string(), s.clone()]);
    }
    run_ok(np, &args.iter().map(String::as_str).collect::<Vec<_>>());
    History::read(out)
}

/// Same rows (step, time) and every column of `a` but the solver's work equal in `b` to `tol`
/// relative (with a floor of `tol` times the column's largest magnitude, for columns that pass
/// through zero), or NaN in both where a column is documented to be NaN ([`NAN_COLUMNS`]); a NaN
/// elsewhere fails. Returns the largest difference over its column's largest magnitude, and the
/// column.
pub fn assert_history_within(a: &History, b: &History, tol: f64, what: &str) -> (f64, String) {
    assert_eq!(a.col("step"), b.col("step"), "{what}: steps");
    assert_eq!(a.col("time"), b.col("time"), "{what}: times");
    // det_bp_max_dev is round-off (|det B_p − 1| ~ 1e-15): bounded, not compared.
    for name in ["det_bp_max_dev"].iter().filter(|n| a.names.iter().any(|m| m == *n)) {
        assert!(a.col(name).iter().chain(&b.col(name)).all(|v| v.abs() < 1e-12), "{what}: {name}");
    }
    let skip = ["wall_s", "newton_its", "ksp_its", "det_bp_max_dev"];
    let mut worst = (0.0, String::new());
    for name in a.names.iter().filter(|n| !skip.contains(&n.as_str())) {
        let (x, y) = (a.col(name), b.col(name));
        let scale = x.iter().filter(|v| v.is_finite()).fold(0.0f64, |m, v| m.max(v.abs()));
        let may_be_nan = NAN_COLUMNS.contains(&name.as_str());
        for (i, (u, v)) in x.iter().zip(&y).enumerate() {
            // NaN: a value that does not apply (the Laplace reading without contact), in both.
            let same = (u - v).abs() <= tol * u.abs().max(scale) || (may_be_nan && u.is_nan() && v.is_nan());
            assert!(same, "{what}: {name} at row {i}: {u} vs {v} (tol {tol})");
            if scale > 0.0 && (u - v).abs() / scale > worst.0 {
                worst = ((u - v).abs() / scale, name.clone());
            }
        }
    }
    worst
}

/// history.csv as named columns.
pub struct History {
    pub names: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl History {
    pub fn read(dir: &Path) -> History {
        let text = std::fs::read_to_string(dir.join("history.csv")).expect("history.csv");
        let mut lines = text.lines();
        let names: Vec<String> = lines.next().unwrap().split(',').map(|s| s.trim().to_string()).collect();
        let rows = lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split(',').map(|v| v.trim().parse::<f64>().unwrap()).collect())
            .collect();
        History { names, rows }
    }
    pub fn col(&self, name: &str) -> Vec<f64> {
        let i =
            self.names.iter().position(|n| n == name).unwrap_or_else(|| panic!("no column {name} in {:?}", self.names));
        self.rows.iter().map(|r| r[i]).collect()
    }
}

/// The run's Jacobian checks (`-poroplast_check_jacobian`): more than 3, each within 1e-7 on the
/// u and the p rows.
pub fn assert_jacobian_checks(stdout: &str) {
    let e = jacobian_errors(stdout);
    let u = e.iter().map(|x| x.0).fold(0.0, f64::max);
    let p = e.iter().map(|x| x.1).fold(0.0, f64::max);
    println!("{} checks: u rows {u:.2e}, p rows {p:.2e}", e.len());
    assert!(e.len() > 3, "{} checks", e.len());
    assert!(u < 1e-7 && p < 1e-7, "u rows {u}, p rows {p}");
}

/// Parses `jacobian check: ... u rows X, p rows Y` lines.
pub fn jacobian_errors(stdout: &str) -> Vec<(f64, f64)> {
    stdout
        .lines()
        .filter(|l| l.starts_with("jacobian check:"))
        .map(|l| {
            let num = |key: &str| -> f64 {
                let s = &l[l.find(key).unwrap() + key.len()..];
                s.trim_start().split([',', ' ']).next().unwrap().parse().unwrap()
            };
            (num("u rows"), num("p rows"))
        })
        .collect()
}

/// A converged value from `scripts/data/references.csv` (the one source of them: written by
/// scripts/references.py, read by the scripts and these tests): `case`, `observable` → the
/// extrapolated value.
pub fn converged(case: &str, observable: &str) -> f64 {
    converged_in("scripts/data/references.csv", case, observable)
}

/// A converged value from a file of the format of references.csv (`file` from the repository's
/// root; e.g. scripts/data/soft_aggregate_reference.csv).
pub fn converged_in(file: &str, case: &str, observable: &str) -> f64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (c, o, v) = (col("case"), col("observable"), col("extrapolated"));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|f| f.len() > v && f[c] == case && f[o] == observable)
        .unwrap_or_else(|| panic!("no converged {case} {observable} in {}", path.display()))[v]
        .parse()
        .unwrap()
}

/// A run's `summary.toml`.
pub struct Summary(toml::Table);

impl Summary {
    pub fn read(dir: &Path) -> Summary {
        let text = std::fs::read_to_string(dir.join("summary.toml")).expect("summary.toml");
        Summary(toml::from_str(&text).expect("summary.toml is TOML"))
    }

    /// The entry `key` (`section.key` inside a table) as a number; None where there is none.
    pub fn num(&self, key: &str) -> Option<f64> {
        let (table, key) = match key.split_once('.') {
            Some((section, key)) => (self.0.get(section)?.as_table()?, key),
            None => (&self.0, key),
        };
        let v = table.get(key)?;
        v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
    }

    /// The table `name` (empty if absent).
    pub fn table(&self, name: &str) -> toml::Table {
        self.0.get(name).and_then(|v| v.as_table()).cloned().unwrap_or_default()
    }

    /// The array of tables `name` (`[[hold]]`; empty if absent).
    pub fn array(&self, name: &str) -> Vec<toml::Table> {
        let tables = self.0.get(name).and_then(|v| v.as_array());
        tables.map_or(Vec::new(), |a| a.iter().filter_map(|v| v.as_table().cloned()).collect())
    }

    /// The largest p's place, `pressure.max_p_at_um`.
    pub fn max_p_at(&self) -> [f64; 3] {
        let a = self.0["pressure"]["max_p_at_um"].as_array().expect("max_p_at_um");
        std::array::from_fn(|i| a[i].as_float().unwrap())
    }
}
