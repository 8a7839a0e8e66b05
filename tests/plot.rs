//! `scripts/plot_run.py` on what the solver writes: a shipped scene of every protocol type run
//! briefly and plotted — phases (`reference_axi`), a table (`tst_hold`), a table of two holds
//! (`tst_two_compressions`), no plates (`terzaghi`, a 3-D column), the 3-D quarter sphere, a sweep
//! of table runs — and runs without fields, cut short or damaged. Each answer is read from the
//! script's output: the line it prints per figure says which panels, phases and output times it
//! drew, its `note:` lines what it could not. (What the figures hold, number by number:
//! scripts/tests/test_runplots.py and test_slices.py.)

use crate::common::*;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `python3 scripts/plot_run.py <args>`: (exit code, stdout, stderr).
fn plot(args: &[&str]) -> (i32, String, String) {
    let _cores = cores(1);
    let out = Command::new("python3")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/plot_run.py"))
        .args(args)
        .env("POROPLAST_BIN", env!("CARGO_BIN_EXE_poroplast"))
        .env("MPLBACKEND", "Agg")
        .output()
        .expect("python3 could not be started");
    let (stdout, stderr) =
        (String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned());
    assert!(!stderr.contains("Traceback"), "plot_run.py {args:?}: a traceback\n{stderr}");
    (out.status.code().unwrap_or(-1), stdout, stderr)
}

/// Plots a directory that must draw: stdout, after checking the PNGs it names exist.
fn plot_ok(args: &[&str]) -> String {
    let (code, out, err) = plot(args);
    assert_eq!(code, 0, "plot_run.py {args:?}\n{out}\n{err}");
    for line in out.lines().filter(|l| !l.starts_with("note:")) {
        let png = PathBuf::from(line.split(".png:").next().unwrap().to_string() + ".png");
        let bytes = std::fs::read(&png).unwrap_or_else(|e| panic!("{}: {e}\n{out}", png.display()));
        assert!(bytes.starts_with(b"\x89PNG") && bytes.len() > 10_000, "{}: {} bytes", png.display(), bytes.len());
    }
    out
}

/// Runs a shipped scene on 1 rank into `dir/name` with the overrides; returns the run directory.
fn run(dir: &Path, name: &str, sets: &[&str]) -> PathBuf {
    let out = dir.join(name);
    let mut args = vec!["run", name, "--out", out.to_str().unwrap(), "-q"];
    sets.iter().for_each(|s| args.extend(["--set", s]));
    run_ok(1, &args);
    out
}

/// The line plot_run.py prints for figure `png`.
fn line<'a>(out: &'a str, png: &str) -> &'a str {
    out.lines().find(|l| l.contains(&format!("{png}:"))).unwrap_or_else(|| panic!("no {png} line in\n{out}"))
}

/// The tensiometry scenes' graded surface is for the Laplace reading; plotting needs none.
const COARSE_MERIDIAN: &str = "mesh.relative_sizes={ h = 0.3, h_pole = 0.1, r_pole = 0.5 }";

#[test]
fn a_phase_protocol_with_fields_at_the_times_asked() {
    let dir = scratch("plot_phases");
    let r = run(&dir, "reference_axi", &["time.t_end=6", "output.fields_at=[5.0]"]);
    let out = plot_ok(&[r.to_str().unwrap(), "--times", "5s, 6"]);
    assert!(
        line(&out, "plot_history.png").ends_with(
            "rows to t = 6 s; panels force_total_uN, probe_p, height/width; phases ramp 0-5 s, hold 5-35 s, \
             release 35-40 s"
        ),
        "{out}"
    );
    assert!(line(&out, "plot_fields.png").ends_with("p, von_mises, porosity at t = 5, 6 s on the deformed meridian"));
    assert!(!out.contains("note:"), "{out}");
    // 4.9 s is no output: drawn at the nearest, and said.
    let out = plot_ok(&[r.to_str().unwrap(), "--times", "4.9", "--fields", "porosity"]);
    assert!(out.contains("note: t = 4.9 s is not an output time: drawn at the nearest written, 5 s"), "{out}");
    assert!(line(&out, "plot_fields.png").ends_with("porosity at t = 5 s on the deformed meridian"), "{out}");
}

#[test]
fn table_protocols_one_hold_and_two() {
    let dir = scratch("plot_tables");
    let sets = [COARSE_MERIDIAN, "time.t_end=1", "output.fields_at=[0.5]"];
    let one = run(&dir, "tst_hold", &sets);
    let out = plot_ok(&[one.to_str().unwrap(), "--times", "0.5", "--fields", "p"]);
    // The shipped table's phases; with a surface tension, the σ_app panel.
    assert!(
        line(&out, "plot_history.png").ends_with(
            "panels force_total_uN, probe_p, height/width, sigma_app; phases ramp 0-5 s, hold 5-1005 s, \
             release 1005-1010 s"
        ),
        "{out}"
    );
    assert!(line(&out, "plot_fields.png").ends_with("p at t = 0.5 s on the deformed meridian"), "{out}");
    let two = run(&dir, "tst_two_compressions", &sets);
    let out = plot_ok(&[two.to_str().unwrap(), "--times", "0.5", "--fields", "p"]);
    assert!(
        line(&out, "plot_history.png").ends_with(
            "phases ramp 0-5 s, hold 5-1005 s, release 1005-1010 s, ramp 1300-1305 s, hold 1305-2305 s, \
             release 2305-2310 s"
        ),
        "{out}"
    );
    assert!(!out.contains("note:"), "{out}");
}

#[test]
fn no_plates_and_a_3d_quarter_sphere_are_cut_through_the_axis() {
    let dir = scratch("plot_3d");
    let column = run(&dir, "terzaghi", &["time.t_end=1", "output.fields_at=[0.5]"]);
    let out = plot_ok(&[column.to_str().unwrap(), "--times", "0.5"]);
    assert!(line(&out, "plot_history.png").contains("panels p_bottom, settlement, p_bottom_exact, settlement_exact"));
    // A column has no porosity field: the fields it has.
    assert!(
        line(&out, "plot_fields.png").ends_with("p, von_mises at t = 0.5 s on the section y = 0 (through the axis)"),
        "{out}"
    );
    let sphere = run(&dir, "reference", &["time.t_end=1", "mesh.params.h=50", "output.fields_at=[1.0]"]);
    let out = plot_ok(&[sphere.to_str().unwrap(), "--times", "1", "--fields", "p,von_mises", "--mid-plane"]);
    assert!(line(&out, "plot_history.png").contains("phases ramp 0-5 s"), "{out}");
    assert!(line(&out, "plot_fields.png").ends_with("p, von_mises at t = 1 s on the section y = 0 (through the axis)"));
    assert!(line(&out, "plot_fields_mid.png").ends_with("p, von_mises at t = 1 s on the section at mid-height"));
    assert!(!out.contains("note:"), "{out}");
}

#[test]
fn a_sweep_of_table_runs() {
    let dir = scratch("plot_sweep");
    let study = dir.join("tension.toml");
    std::fs::write(
        &study,
        format!(
            "scene = \"tst_hold\"\nset = [\"{COARSE_MERIDIAN}\", \"time.t_end=0.3\", \"output.fields_at=[0.3]\", \"output.fields=false\"]\n\
             [[grid]]\nkey = \"surface.tension\"\nvalues = [2.0, 5.0]\n"
        ),
    )
    .unwrap();
    let root = dir.join("sweep");
    run_ok(1, &["sweep", study.to_str().unwrap(), "--out", root.to_str().unwrap()]);
    let out = plot_ok(&[root.to_str().unwrap()]);
    assert!(
        line(&out, "plot_history.png").starts_with(&format!("{}: 2 run(s)", root.join("plot_history.png").display()))
    );
    assert!(line(&out, "plot_history.png").ends_with("phases ramp 0-5 s, hold 5-1005 s, release 1005-1010 s"), "{out}");
    // Its cases have no fields (output.fields = false): said, the history drawn.
    let case = std::fs::read_dir(root.join("cases")).unwrap().next().unwrap().unwrap().path();
    let out = plot_ok(&[case.to_str().unwrap()]);
    assert!(out.contains("note: no fields.h5 (output.fields = false): no field pictures"), "{out}");
}

#[test]
fn a_damaged_run_is_drawn_as_far_as_it_can_be() {
    let dir = scratch("plot_damaged");
    let r = run(&dir, "reference_axi", &["time.t_end=2", "mesh.params.h=25"]);
    // A run killed while writing: no status or summary, history.csv's last line and fields.h5 cut.
    for f in ["status.txt", "summary.toml"] {
        std::fs::remove_file(r.join(f)).unwrap();
    }
    let history = std::fs::read_to_string(r.join("history.csv")).unwrap();
    std::fs::write(r.join("history.csv"), &history[..history.len() - 20]).unwrap();
    let fields = std::fs::read(r.join("fields.h5")).unwrap();
    std::fs::write(r.join("fields.h5"), &fields[..fields.len() / 2]).unwrap();
    let _ = std::fs::remove_dir_all(r.join("checkpoints"));
    let out = plot_ok(&[r.to_str().unwrap()]);
    let rows = history.lines().count() - 2; // the header and the cut line
    assert!(line(&out, "plot_history.png").contains(&format!("1 run(s), {rows} rows")), "{out}");
    for note in [
        "note: history.csv: its last line is cut",
        "note: the run is in progress (no status.txt yet): drawn as far as it got",
        "note: no summary.toml",
        "note: fields.h5 cannot be read",
    ] {
        assert!(out.contains(note), "no `{note}` in\n{out}");
    }
    assert!(!out.contains("plot_fields.png"), "{out}");
    // Nothing readable: one line, exit 1.
    std::fs::write(r.join("history.csv"), "step,time\n").unwrap();
    std::fs::remove_file(r.join("fields.h5")).unwrap();
    let (code, out, err) = plot(&[r.to_str().unwrap()]);
    assert_eq!(code, 1, "{out}{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("nothing drawn") && err.contains("history.csv has no rows"), "{err}");
    // Neither a run nor a sweep; a time that is not one.
    let (code, _, err) = plot(&[dir.to_str().unwrap()]);
    assert!(code == 1 && err.contains("neither a run directory (history.csv) nor a sweep directory"), "{err}");
    let (code, _, err) = plot(&[r.to_str().unwrap(), "--times", "5 parsecs"]);
    assert!(code == 2 && err.contains("'5 parsecs' is not a time"), "{err}");
}

/// The 3-D reference run the user's guide names, at its own mesh: the quarter's section and the
/// mid-height section at the end of the ramp.
#[test]
#[ignore = "slow: the 3-D reference on 2 ranks to t = 6 s (about 40 s of CPU)"]
fn the_3d_reference_at_its_own_mesh() {
    let dir = scratch("plot_reference_3d");
    let r = dir.join("reference");
    run_ok(
        2,
        &[
            "run",
            "reference",
            "--set",
            "time.t_end=6",
            "--set",
            "output.fields_at=[5.0]",
            "--out",
            r.to_str().unwrap(),
            "-q",
        ],
    );
    let out = plot_ok(&[r.to_str().unwrap(), "--times", "5", "--mid-plane"]);
    assert!(line(&out, "plot_fields.png")
        .ends_with("p, von_mises, porosity at t = 5 s on the section y = 0 (through the axis)"));
    assert!(
        line(&out, "plot_fields_mid.png").ends_with("p, von_mises, porosity at t = 5 s on the section at mid-height")
    );
    assert!(!out.contains("note:"), "{out}");
}
