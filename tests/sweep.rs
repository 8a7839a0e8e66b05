//! `poroplast sweep`: the cases of a study under one mpirun, in groups of k ranks — each case's
//! history equal to the same case run alone; a bad case failing alone; a sweep killed with
//! `kill -9` resuming to the same summary, and a sweep directory of the earlier layout
//! continued; sweeps sharing a case store running each case once; bad input refused before
//! anything is written. The scene: the axisymmetric reference on a coarse meridian, to t = 3 s
//! (part of the ramp).

use crate::common::*;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// The overrides of every case (with the study's `set`).
const BASE: [&str; 4] = ["time.t_end=3", "mesh.params.h=25", "mesh.params.h_pole=5", "output.fields_every=4"];

/// A study of 4 cases: the surface tension (none, 5 mN/m) × a linked (compression, t_ramp) axis.
fn grid_study(dir: &Path, extra_set: &[&str]) -> PathBuf {
    let set: Vec<String> = BASE.iter().chain(extra_set).map(|s| format!("\"{s}\"")).collect();
    let text = format!(
        "scene = \"reference_axi\"\nset = [{}]\n\n[[grid]]\nkey = \"surface.tension\"\nvalues = [0, 5]\n\n\
         [[grid]]\nkeys = [\"plates.compression\", \"plates.t_ramp\"]\nvalues = [[0.2, 4], [0.3, 5]]\n",
        set.join(", ")
    );
    let p = dir.join("study.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// The overrides of the grid's cases, in case order.
fn grid_cases() -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for gamma in ["0", "5"] {
        for (c, t) in [("0.2", "4"), ("0.3", "5")] {
            out.push(vec![
                format!("surface.tension={gamma}"),
                format!("plates.compression={c}"),
                format!("plates.t_ramp={t}"),
            ]);
        }
    }
    out
}

fn sweep(np: usize, study: &Path, out: &Path, k: usize) -> std::process::Output {
    poroplast(np, &["sweep", &study.display().to_string(), "--out", &out.display().to_string(), "-k", &k.to_string()])
}

/// A sweep on 2 ranks, one case per rank, its cases in the store `cases`.
fn sweep_in(study: &Path, out: &Path, cases: &Path) -> std::process::Output {
    let (s, o, c) = (study.display().to_string(), out.display().to_string(), cases.display().to_string());
    poroplast(2, &["sweep", &s, "--out", &o, "--cases-dir", &c, "-k", "1"])
}

fn ok(out: &std::process::Output, what: &str) -> String {
    expect_success(out, what)
}

/// The case directories of a sweep, in case order (summary.csv's `dir`, relative to the sweep
/// directory or absolute).
fn case_dirs(root: &Path) -> Vec<PathBuf> {
    let (header, rows) = summary(root);
    let dir = header.iter().position(|h| h == "dir").unwrap();
    rows.iter().map(|r| root.join(&r[dir])).collect()
}

/// summary.csv as rows of fields (plain fields: these studies have no quoted ones).
fn summary(root: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(root.join("summary.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    (header, lines.map(|l| l.split(',').map(String::from).collect()).collect())
}

/// Largest difference between two histories, every column but the wall time, relative to the
/// column's largest magnitude (at least 1); panics if the rows or columns differ.
fn history_difference(a: &History, b: &History, what: &str) -> f64 {
    assert_eq!(a.names, b.names, "{what}: columns");
    assert_eq!(a.rows.len(), b.rows.len(), "{what}: rows");
    let mut worst = 0.0f64;
    for name in a.names.iter().filter(|n| *n != "wall_s") {
        let (x, y) = (a.col(name), b.col(name));
        let scale = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        for (u, v) in x.iter().zip(&y) {
            worst = worst.max((u - v).abs() / scale);
        }
    }
    worst
}

#[test]
fn cases_equal_the_same_cases_run_alone() {
    let _cores = cores(2); // the sweep on 2 ranks
    let d = scratch("sweep_equal");
    let study = grid_study(&d, &[]);
    let t = Instant::now();
    let out = sweep(4, &study, &d.join("k2"), 2);
    let stdout = ok(&out, "sweep -k 2");
    let k2_s = t.elapsed().as_secs_f64();
    assert!(stdout.contains("in 2 group(s) of 2 rank(s)"), "{stdout}");
    let t = Instant::now();
    ok(&sweep(4, &study, &d.join("k1"), 1), "sweep -k 1");
    let k1_s = t.elapsed().as_secs_f64();
    let (header, rows) = summary(&d.join("k2"));
    assert_eq!(rows.len(), 4);
    let status = header.iter().position(|h| h == "status").unwrap();
    assert!(rows.iter().all(|r| r[status] == "ok"), "{rows:?}");

    let mut worst = (0.0f64, 0.0f64);
    for (i, (case, (dir2, dir1))) in
        grid_cases().iter().zip(case_dirs(&d.join("k2")).iter().zip(case_dirs(&d.join("k1")))).enumerate()
    {
        for (np, swept, w) in [(2, dir2, &mut worst.0), (1, &dir1, &mut worst.1)] {
            let alone = d.join(format!("alone-{i}-{np}"));
            let mut args = vec!["run".to_string(), "reference_axi".into(), "--out".into(), alone.display().to_string()];
            for s in BASE.iter().map(|s| s.to_string()).chain(case.iter().cloned()) {
                args.extend(["--set".into(), s]);
            }
            args.push("-q".into());
            run_ok(np, &args.iter().map(|s| s.as_str()).collect::<Vec<_>>());
            let diff =
                history_difference(&History::read(&alone), &History::read(swept), &format!("case {i}, {np} rank(s)"));
            assert!(diff <= 1e-10, "case {i} on {np} rank(s): the sweep's history differs by {diff:e}");
            *w = w.max(diff);
        }
    }
    eprintln!(
        "sweep of 4 cases on 4 ranks: k = 2 {k2_s:.1} s, k = 1 {k1_s:.1} s; largest difference from the cases \
         run alone: {:e} (2 ranks), {:e} (1 rank)",
        worst.0, worst.1
    );
}

#[test]
fn a_bad_case_fails_alone() {
    let _cores = cores(1); // one group: which cases fail does not depend on the groups
    let d = scratch("sweep_bad_case");
    let set: Vec<String> = BASE.iter().map(|s| format!("\"{s}\"")).collect();
    let text = format!(
        "scene = \"reference_axi\"\nset = [{}]\n[[case]]\nset = [\"material.mu=15\"]\n[[case]]\nset = [\"material.mu=-3\"]\n\
         [[case]]\nset = [\"plates.group=nowhere\"]\n[[case]]\nset = [\"material.mu=25\"]\n",
        set.join(", ")
    );
    let study = d.join("bad.toml");
    std::fs::write(&study, text).unwrap();
    let root = d.join("sweep");
    let out = sweep(1, &study, &root, 1);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "a sweep with failed cases exits non-zero");
    assert!(stderr.contains("2 of 4 cases failed"), "{stderr}");
    let (header, rows) = summary(&root);
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let status: Vec<&str> = rows.iter().map(|r| r[col("status")].as_str()).collect();
    assert_eq!(status, ["ok", "failed", "failed", "ok"]);
    assert!(rows[1][col("error")].contains("material.mu"), "{:?}", rows[1]);
    assert!(rows[2][col("error")].contains("physical group"), "{:?}", rows[2]);
    assert!(rows[0][col("max:force_total_mg")].parse::<f64>().unwrap() > 0.0);
    assert!(rows[3][col("steps")].parse::<usize>().unwrap() > 0);
}

#[test]
fn cases_with_their_own_scenes() {
    let _cores = cores(1); // one group
                           // No base scene: each case names its own — a shipped scene by name, the same scene by its
                           // file (the same case: the same history), and the name again with an override.
    let d = scratch("sweep_scenes");
    let set: Vec<String> = BASE.iter().map(|s| format!("\"{s}\"")).collect();
    let file = scene("reference_axi");
    let text = format!(
        "set = [{}]\n[[case]]\nscene = \"reference_axi\"\n[[case]]\nscene = '{file}'\n\
         [[case]]\nscene = \"reference_axi\"\nset = [\"material.mu=25\"]\n",
        set.join(", ")
    );
    let study = d.join("scenes.toml");
    std::fs::write(&study, &text).unwrap();
    let root = d.join("sweep");
    ok(&sweep(1, &study, &root, 1), "the sweep");
    let (header, rows) = summary(&root);
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let scenes: Vec<&str> = rows.iter().map(|r| r[col("scene")].as_str()).collect();
    assert_eq!(scenes, ["reference_axi", file.as_str(), "reference_axi"]);
    assert!(rows.iter().all(|r| r[col("status")] == "ok"), "{rows:?}");
    // The shipped scene and its file are two cases (a case is its scene's name or path and text).
    let dirs = case_dirs(&root);
    let name = |i: usize| dirs[i].file_name().unwrap().to_string_lossy().into_owned();
    assert!(name(0).starts_with("reference_axi-") && name(1).starts_with("reference_axi-"), "{dirs:?}");
    assert_ne!(dirs[0], dirs[1]);
    let diff = history_difference(&History::read(&dirs[0]), &History::read(&dirs[1]), "name and file");
    assert!(diff <= 1e-10, "the scene by name and by file differ by {diff:e}");
    let peak = |r: &Vec<String>| r[col("max:force_total_mg")].parse::<f64>().unwrap();
    assert!(peak(&rows[2]) > 1.1 * peak(&rows[0]), "material.mu=25 had no effect: {rows:?}");
    // A case's scene that does not load is refused before anything is written.
    let bad = d.join("bad.toml");
    std::fs::write(&bad, text.replace("scene = \"reference_axi\"\nset", "scene = \"no_such_scene\"\nset")).unwrap();
    let out = sweep(1, &bad, &d.join("bad"), 1);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("a case's scene"), "{stderr}");
    assert!(!d.join("bad").exists());
}

#[test]
fn each_case_runs_once_when_the_groups_end_at_different_times() {
    let _cores = cores(2); // the sweep on 2 ranks
                           // A long case (the second) among short ones on 2 groups: one group runs the long case while
                           // the other runs the short ones and ends first. Its ranks must wait for the other group
                           // before the claims are cleared, or that group, when its long case ends, would find the
                           // short ones after it unclaimed and run them again (before the fix: whenever world rank 0's
                           // group took the first case, as it usually does).
    let d = scratch("sweep_once");
    let set: Vec<String> = BASE.iter().map(|s| format!("\"{s}\"")).collect();
    let text = format!(
        "set = [{}]\nscene = \"reference_axi\"\n[[case]]\nset = []\n[[case]]\nset = [\"time.t_end=30\", \"mesh.params.h=12\", \"mesh.params.h_pole=3\"]\n\
         [[case]]\nset = [\"material.mu=25\"]\n[[case]]\nset = [\"material.mu=30\"]\n",
        set.join(", ")
    );
    let study = d.join("once.toml");
    std::fs::write(&study, text).unwrap();
    for round in 0..2 {
        let root = d.join(format!("sweep-{round}"));
        let stdout = ok(&sweep(2, &study, &root, 1), "the sweep");
        for i in 0..4 {
            let ended = stdout.lines().filter(|l| l.starts_with(&format!("sweep: case {i} "))).count();
            assert_eq!(ended, 1, "case {i} ended {ended} times:\n{stdout}");
        }
    }
}

/// The processes whose parent is `pid` (Linux /proc).
fn children(pid: u32) -> Vec<u32> {
    std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse::<u32>().ok())
        .filter(|p| {
            std::fs::read_to_string(format!("/proc/{p}/stat")).ok().is_some_and(|s| {
                // pid (comm) state ppid ...: comm may hold spaces, so split after its ')'.
                s.rsplit_once(')').and_then(|(_, r)| r.split_whitespace().nth(1)?.parse::<u32>().ok()) == Some(pid)
            })
        })
        .collect()
}

#[test]
fn a_killed_sweep_resumes_to_the_same_summary() {
    let _cores = cores(2); // the sweep on 2 ranks
    let d = scratch("sweep_killed");
    // Longer cases (t = 30 s, about 40 steps): the kill comes while one is early in its run.
    let study = grid_study(&d, &["output.checkpoint_every=3", "time.t_end=30"]);
    let reference = d.join("reference");
    ok(&sweep(2, &study, &reference, 1), "the uninterrupted sweep");

    // kill -9 once a case has written a checkpoint (a case is then half done).
    let killed = d.join("killed");
    let mut child = launch(2)
        .arg("sweep")
        .arg(&study)
        .arg("--out")
        .arg(&killed)
        .args(["-k", "1"])
        .stdout(std::process::Stdio::null())
        .process_group(0)
        .spawn()
        .unwrap();
    let start = Instant::now();
    let checkpointed = || {
        killed.join("cases").is_dir()
            && std::fs::read_dir(killed.join("cases")).unwrap().map(|e| e.unwrap().path()).any(|c| {
                std::fs::read_dir(c.join("checkpoints")).is_ok_and(|mut e| e.next().is_some())
                    && !c.join("case.toml").exists()
            })
    };
    while !checkpointed() {
        assert!(child.try_wait().unwrap().is_none(), "the sweep ended before it could be killed");
        assert!(start.elapsed() < Duration::from_secs(300), "no checkpoint after 300 s");
        std::thread::sleep(Duration::from_millis(5));
    }
    // mpirun and its ranks (which Open MPI puts in process groups of their own), at once.
    let ranks = children(child.id());
    assert!(!ranks.is_empty(), "no ranks under mpirun");
    let mut targets = vec![format!("-{}", child.id())];
    targets.extend(ranks.iter().map(|p| p.to_string()));
    let ok_kill = Command::new("kill").arg("-KILL").arg("--").args(&targets).status().unwrap();
    assert!(ok_kill.success());
    child.wait().unwrap();
    while ranks.iter().any(|p| Path::new(&format!("/proc/{p}")).exists()) {
        std::thread::sleep(Duration::from_millis(5));
    }
    let (_, partial) = summary(&killed);
    assert_eq!(partial.len(), 4, "a killed sweep leaves a summary of every case");

    let stdout = ok(&sweep(2, &study, &killed, 1), "the resumed sweep");
    assert!(stdout.contains("to run in 2 group(s)"), "{stdout}");
    assert!(stdout.contains("continues its interrupted run"), "no case resumed: {stdout}");
    let (ha, a) = summary(&reference);
    let (hb, b) = summary(&killed);
    assert_eq!(ha, hb);
    let wall = ha.iter().position(|h| h == "wall_s").unwrap();
    for (ra, rb) in a.iter().zip(&b) {
        for (j, (x, y)) in ra.iter().zip(rb).enumerate().filter(|(j, _)| *j != wall) {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(u), Ok(v)) => assert!((u - v).abs() <= 1e-10 * u.abs().max(1.0), "{}: {x} vs {y}", ha[j]),
                _ => assert_eq!(x, y, "{}", ha[j]),
            }
        }
    }
    for (ca, cb) in case_dirs(&reference).iter().zip(case_dirs(&killed)) {
        let diff = history_difference(&History::read(ca), &History::read(&cb), &cb.display().to_string());
        assert!(diff <= 1e-10, "{}: {diff:e}", cb.display());
    }
    // Completed: a third run has nothing to do.
    let stdout = ok(&sweep(2, &study, &killed, 2), "the sweep again");
    assert!(stdout.contains("4 already complete, 0 to run"), "{stdout}");

    // The uninterrupted sweep as an earlier version left it (cases/NNN_<overrides>/, each
    // case.toml with its overrides only): continued, its cases move into the store, complete.
    let before = std::fs::read_to_string(reference.join("summary.csv")).unwrap();
    for (i, (dir, case)) in case_dirs(&reference).iter().zip(grid_cases()).enumerate() {
        let record = std::fs::read_to_string(dir.join("case.toml")).unwrap();
        let legacy: String = record
            .lines()
            .filter(|l| !l.starts_with("scene") && !l.starts_with("petsc"))
            .map(|l| format!("{l}\n"))
            .collect();
        std::fs::write(dir.join("case.toml"), legacy).unwrap();
        let name = case.iter().map(|s| s.replace('=', "-")).collect::<Vec<_>>().join("__");
        std::fs::rename(dir, reference.join("cases").join(format!("{i:03}_{name}"))).unwrap();
    }
    let stdout = ok(&sweep(2, &study, &reference, 1), "the sweep of the earlier layout");
    assert!(stdout.contains("4 case(s) of an earlier version's layout moved"), "{stdout}");
    assert!(stdout.contains("4 already complete, 0 to run"), "{stdout}");
    assert_eq!(std::fs::read_to_string(reference.join("summary.csv")).unwrap(), before);
}

#[test]
fn sweeps_sharing_a_store_run_each_case_once() {
    let _cores = cores(2); // the sweep on 2 ranks
                           // Study b shares one case with study a, names it twice, and adds one: only that one runs,
                           // and b's summary has b's observables of a's case (read from its history when b's summary
                           // is written).
    let d = scratch("sweep_shared");
    let store = d.join("store");
    let study = |name: &str, mus: &[&str], observe: &str| {
        let set: Vec<String> = BASE.iter().map(|s| format!("\"{s}\"")).collect();
        let cases: String = mus.iter().map(|m| format!("[[case]]\nset = [\"material.mu={m}\"]\n")).collect();
        let p = d.join(name);
        std::fs::write(&p, format!("scene = \"reference_axi\"\nset = [{}]\n{observe}\n{cases}", set.join(", ")))
            .unwrap();
        p
    };
    let a = study("a.toml", &["15", "25"], "");
    let stdout = ok(&sweep_in(&a, &d.join("a"), &store), "study a");
    assert!(stdout.contains("2 cases, 0 already complete, 2 to run"), "{stdout}");
    let b = study("b.toml", &["25", "35", "25"], "observe = [\"last:time\", \"max:force_total_mg\"]");
    let stdout = ok(&sweep_in(&b, &d.join("b"), &store), "study b");
    assert!(stdout.contains("3 cases, 2 already complete, 1 to run"), "{stdout}");
    assert_eq!(stdout.matches("sweep: case ").count(), 1, "{stdout}");
    assert!(stdout.contains("sweep: case 1 (material.mu=35) ok"), "{stdout}");
    let (a_dirs, b_dirs) = (case_dirs(&d.join("a")), case_dirs(&d.join("b")));
    assert!(a_dirs[1] == b_dirs[0] && b_dirs[0] == b_dirs[2] && b_dirs[0].starts_with(&store), "{a_dirs:?} {b_dirs:?}");
    let (ha, ra) = summary(&d.join("a"));
    let (hb, rb) = summary(&d.join("b"));
    let value = |h: &[String], r: &Vec<String>, c: &str| r[h.iter().position(|x| x == c).unwrap()].clone();
    assert_eq!(value(&hb, &rb[0], "last:time"), "3");
    assert_eq!(value(&hb, &rb[0], "max:force_total_mg"), value(&ha, &ra[1], "max:force_total_mg"));
    assert_eq!(value(&hb, &rb[2], "wall_s"), value(&ha, &ra[1], "wall_s"));
    assert!(!ha.contains(&"last:time".to_string()) && ha.contains(&"zero:probe_p".to_string()), "{ha:?}");
}

/// `poroplast case SCENE --set ... --cases-dir STORE [-- OPTIONS]` as TOML, or its error line.
fn case_in(store: &Path, scene: &str, set: &[&str], petsc: &[&str]) -> Result<toml::Table, String> {
    let mut args = vec!["case", scene, "--cases-dir", store.to_str().unwrap()];
    args.extend(set.iter().flat_map(|s| ["--set", *s]));
    args.push("--");
    args.extend(petsc);
    let out = poroplast(1, &args);
    if out.status.success() {
        Ok(toml::from_str(&String::from_utf8_lossy(&out.stdout)).unwrap())
    } else {
        Err(String::from_utf8_lossy(&out.stderr).into_owned())
    }
}

#[test]
fn a_case_is_found_by_what_it_runs() {
    // Two tiny Terzaghi cases of a scene file, one failing (µ out of range), on one rank.
    let _cores = cores(1);
    let d = scratch("sweep_case");
    let file = scene_variant("terzaghi", &d, &[("t_end = 100.0", "t_end = 0.004")]);
    let text = std::fs::read_to_string(&file).unwrap();
    let study = d.join("s.toml");
    std::fs::write(
        &study,
        format!("scene = '{file}'\n[[case]]\nset = [\"material.mu=12\"]\n[[case]]\nset = [\"material.mu=-3\"]\n"),
    )
    .unwrap();
    let root = d.join("sweep");
    assert!(!sweep(1, &study, &root, 1).status.success(), "the second case fails");
    let (store, dirs) = (root.join("cases"), case_dirs(&root));
    let status = |set: &[&str], petsc: &[&str]| {
        let t = case_in(&store, &file, set, petsc).unwrap();
        (t["status"].as_str().unwrap().to_string(), t.get("dir").map(|d| PathBuf::from(d.as_str().unwrap())))
    };
    assert_eq!(status(&["material.mu=12"], &[]), ("ok".into(), Some(dirs[0].clone())));
    let failed = case_in(&store, &file, &["material.mu=-3"], &[]).unwrap();
    assert_eq!(failed["status"].as_str(), Some("failed"));
    assert!(failed["error"].as_str().unwrap().contains("material.mu"), "{failed}");
    // The key names the run directory; the signature is the one case.toml records.
    let ok = case_in(&store, &file, &["material.mu=12"], &[]).unwrap();
    let key = ok["key"].as_str().unwrap();
    assert!(dirs[0].to_string_lossy().ends_with(&format!("-{key}")), "{ok}");
    let record: toml::Table = toml::from_str(&std::fs::read_to_string(dirs[0].join("case.toml")).unwrap()).unwrap();
    for k in ["scene", "scene_text", "set", "petsc"] {
        assert_eq!(ok[k], record[k], "{k}");
    }
    // Other overrides or options; the same ones on the file edited (ν, which no override sets).
    assert_eq!(status(&["material.mu=13"], &[]), ("absent".into(), None));
    assert_eq!(status(&["material.mu=12"], &["-ksp_rtol", "1e-9"]), ("absent".into(), None));
    std::fs::write(&file, text.replacen("nu = 0.2\n", "nu = 0.3\n", 1)).unwrap();
    assert_eq!(status(&["material.mu=12"], &[]), ("absent".into(), None));
    std::fs::write(&file, &text).unwrap();
    // A run directory without its outcome: interrupted (or running).
    std::fs::remove_file(dirs[0].join("case.toml")).unwrap();
    assert_eq!(status(&["material.mu=12"], &[]), ("unfinished".into(), Some(dirs[0].clone())));
    // Bad input: a key the scene has not, a store that is not there.
    let e = case_in(&store, &file, &["material.muu=12"], &[]).unwrap_err();
    assert!(e.contains("unknown field `muu`"), "{e}");
    let e = case_in(&d.join("nowhere"), &file, &[], &[]).unwrap_err();
    assert!(e.contains("nowhere: cannot read the case store"), "{e}");
}

#[test]
fn bad_input_is_refused_before_anything_is_written() {
    let _cores = cores(2); // the sweep on 2 ranks
    let d = scratch("sweep_bad_input");
    let study = grid_study(&d, &[]);
    let root = d.join("sweep");
    let check = |out: std::process::Output, expect: &str| {
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "accepted; stderr: {stderr}");
        assert!(stderr.contains(expect), "expected `{expect}` in: {stderr}");
        assert!(!root.exists(), "{} was created", root.display());
    };
    check(sweep(4, &study, &root, 3), "--ranks-per-case 3 does not divide the 4 MPI rank(s)");
    for (text, expect) in [
        ("scene = \"reference_axi\"\nset = []\n[[grid]]\nkey = \"material.mu\"\nvalues = []\n", "no values"),
        ("scene = \"reference_axi\"\nsets = []\n[[case]]\nset = []\n", "unknown field `sets`"),
        ("scene = \"no_such_scene\"\n[[case]]\nset = []\n", "base scene"),
        ("scene = \"reference_axi\"\n", "no cases"),
        // A typo in a grid key, and a value of the wrong type in one case: found before any case
        // runs (a value out of range fails its case alone: `a_bad_case_fails_alone`).
        (
            "scene = \"reference_axi\"\n[[grid]]\nkey = \"material.muu\"\nvalues = [15, 25]\n",
            "case 0 (material.muu=15): scene builtin:reference_axi: --set material.muu=15: unknown field `muu`",
        ),
        (
            "scene = \"reference_axi\"\n[[case]]\nset = [\"material.mu=15\"]\n[[case]]\nset = [\"material.mu=soft\"]\n",
            "case 1 (material.mu=soft)",
        ),
    ] {
        let bad = d.join("bad.toml");
        std::fs::write(&bad, text).unwrap();
        check(sweep(2, &bad, &root, 1), expect);
    }
    // Another study into an existing sweep's directory.
    std::fs::create_dir_all(&root).unwrap();
    std::fs::write(root.join("study.toml"), "scene = \"cryer\"\n").unwrap();
    let out = sweep(2, &study, &root, 1);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("holds the sweep of another study"), "{stderr}");
    assert_eq!(std::fs::read_dir(&root).unwrap().count(), 1, "the other sweep's directory was changed");
}

#[test]
fn petsc_options_do_not_pass_from_a_case_to_the_next() {
    let _cores = cores(1); // one group runs the cases in turn
                           // One group runs the three cases in turn: the first's PETSc option (a loose Newton
                           // tolerance) must not reach the third, which must equal its run alone; the fieldsplit
                           // preconditioner (Schur complement, GAMG, hypre) set up again after PETSc was finalised.
    let d = scratch("sweep_isolation");
    let set: Vec<String> = BASE.iter().map(|s| format!("\"{s}\"")).collect();
    let text = format!(
        "scene = \"reference_axi\"\nset = [{}]\n[[case]]\nset = ['solver.preset=\"fieldsplit\"', \"petsc.snes_rtol=1e-3\"]\n\
         [[case]]\nset = []\n[[case]]\nset = ['solver.preset=\"fieldsplit\"']\n",
        set.join(", ")
    );
    let study = d.join("iso.toml");
    std::fs::write(&study, text).unwrap();
    let root = d.join("sweep");
    ok(&sweep(1, &study, &root, 1), "the sweep");
    let alone = d.join("alone");
    let mut args = vec!["run", "reference_axi", "--out"];
    let out = alone.display().to_string();
    args.push(&out);
    for s in &BASE {
        args.extend(["--set", s]);
    }
    args.extend(["--set", "solver.preset=\"fieldsplit\"", "-q"]);
    run_ok(1, &args);
    let dirs = case_dirs(&root);
    let diff = history_difference(&History::read(&alone), &History::read(&dirs[2]), "case 2");
    assert!(diff <= 1e-10, "the third case differs from its run alone by {diff:e}");
    let newton = |dir: &Path| History::read(dir).col("newton_its").iter().sum::<f64>();
    assert!(newton(&dirs[0]) < newton(&dirs[2]), "the loose tolerance of the first case had no effect");
}

/// Every file under `dir` (relative path, contents), sorted.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p);
            } else {
                out.push((p.strip_prefix(dir).unwrap().to_path_buf(), std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn a_session_with_other_petsc_options_is_refused() {
    let _cores = cores(2); // the sweep on 2 ranks
                           // The command line's `-- OPTIONS` are part of a sweep: a later session with others would
                           // skip cases run with the first ones and run (or resume) the rest with its own.
    let d = scratch("sweep_options");
    let set: Vec<String> = BASE.iter().map(|s| format!("\"{s}\"")).collect();
    let study = d.join("opts.toml");
    std::fs::write(&study, format!("scene = \"reference_axi\"\nset = [{}]\n[[case]]\nset = []\n", set.join(", ")))
        .unwrap();
    let root = d.join("sweep");
    let session = |petsc: &[&str]| {
        let (s, r) = (study.display().to_string(), root.display().to_string());
        let mut args = vec!["sweep", &s, "--out", &r, "-k", "1"];
        if !petsc.is_empty() {
            args.push("--");
            args.extend(petsc);
        }
        poroplast(1, &args)
    };
    ok(&session(&["-snes_rtol", "1e-9"]), "the first session");
    let recorded = std::fs::read_to_string(root.join("sweep.toml")).unwrap();
    assert!(recorded.contains("-snes_rtol") && recorded.contains("1e-9"), "{recorded}");
    let before = snapshot(&root);
    for other in [&[][..], &["-snes_rtol", "1e-6"], &["-snes_rtol", "1e-9", "-ksp_rtol", "1e-12"]] {
        let out = session(other);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{other:?} accepted: {stderr}");
        assert!(
            stderr.contains("`-snes_rtol 1e-9`") && stderr.contains("sweep.toml") && stderr.contains("same options"),
            "{other:?}: {stderr}"
        );
        if let [_, v, ..] = other {
            assert!(stderr.contains(v), "{other:?}: {stderr}");
        } else {
            assert!(stderr.contains("given none"), "{stderr}");
        }
        assert!(snapshot(&root) == before, "{other:?}: the sweep directory was changed");
    }
    let stdout = ok(&session(&["-snes_rtol", "1e-9"]), "the same options again");
    assert!(stdout.contains("1 already complete, 0 to run"), "{stdout}");
}
