//! The plates on the general contact path (`plates.contact = "tools"`: two plane tools with
//! frames, the curved split and the projection) give the history of the bounds' path (the
//! plane split on the surface u_z): the two solve one discrete problem, so they differ by the
//! Newton tolerance only.

use crate::common::*;

/// `reference_axi` (the meridian compression; 1 rank) through its 5-s ramp and 7 s of the hold
/// on both paths at snes_rtol 1e-10: the same steps, and every column within 1e-9 of its largest
/// value. Measured: 1.2e-10 (max_penetration); over the whole run 2.5e-10 (probe_porosity, forces
/// 2.0e-10) in 69 identical steps to the release at 39 s, shrinking with the tolerance (2.6e-8 at
/// the default 1e-8, 1.2e-11 at 1e-11). The tools'
/// columns agree with the plates': the upper tool's force is the plate force, its penetration
/// round-off.
#[test]
fn the_plates_as_tools_give_the_plates_history() {
    let _cores = cores(1);
    let dir = scratch("plate-paths");
    let run = |contact: &str| {
        let out = dir.join(contact);
        let set = format!("plates.contact={contact}");
        let out_dir = out.to_str().unwrap();
        let args = ["run", "reference_axi", "--out", out_dir, "-q", "--set", "time.t_end=12", "--set", &set];
        let tail = ["--", "-snes_rtol", "1e-10", "-snes_atol", "1e-12"];
        run_ok(1, &[&args[..], &tail[..]].concat());
        History::read(&out)
    };
    let (bounds, tools) = (run("bounds"), run("tools"));
    assert_same_history(&bounds, &tools, 1e-9);
    assert!(bounds.names.iter().all(|n| !n.starts_with("plate_upper")), "tool columns on the bounds' path");
    let (f_plate, f_tool) = (tools.col("force_total_uN"), tools.col("plate_upper_force_uN"));
    let peak = f_plate.iter().cloned().fold(0.0, f64::max);
    assert!(peak > 100.0, "peak {peak} µN");
    for (a, b) in f_plate.iter().zip(&f_tool) {
        assert!((a - b).abs() <= 1e-9 * peak, "plate force {a} µN, upper tool's {b} µN");
    }
    let (upper, lower) = (tools.col("plate_upper_penetration"), tools.col("plate_lower_penetration"));
    let pen = upper.iter().chain(&lower).cloned().fold(0.0, f64::max);
    assert!(pen <= 1e-10, "the plates' tools are entered by {pen} µm");
}

/// The general path takes displacement rows only for the upper plate: force control stays on the
/// bounds' path, and says so.
#[test]
fn force_control_on_the_plates_tools_is_refused() {
    let dir = scratch("plate-paths-force");
    let out = dir.join("run");
    let o = poroplast(1, &["run", "creep_plates", "--out", out.to_str().unwrap(), "--set", "plates.contact=tools"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "ran");
    assert!(err.contains("plates.contact = \"tools\": the upper plate's force control"), "{err}");
    assert!(!err.contains("panicked") && !out.exists(), "{err}");
}

/// The 3-D quarter (`elastic_155`, 2 ranks) through its ramp and 3 s of the hold: the nodes on
/// the symmetry planes touch the plates' tools too (their frames keep the held component as an
/// axis). Measured: 4.6e-11 (outflow), 33 identical steps, at snes_rtol 1e-10 (before that fix the
/// pole's nodes went through the upper plate unseen and the first step's force was 0).
#[test]
#[ignore = "slow tier: two 3-D runs of 8 s of the experiment (25 s on 2 cores)"]
fn the_quarters_plates_as_tools_give_the_plates_history() {
    let _cores = cores(2);
    let dir = scratch("plate-paths-quarter");
    let run = |contact: &str| {
        let out = dir.join(contact);
        let set = format!("plates.contact={contact}");
        let args = ["run", "elastic_155", "--out", out.to_str().unwrap(), "-q", "--set", "time.t_end=8"];
        let more = ["--set", "output.fields_at=[]", "--set", "time.land_on=[]", "--set", &set];
        run_ok(2, &[&args[..], &more[..], &["--", "-snes_rtol", "1e-10", "-snes_atol", "1e-12"][..]].concat());
        History::read(&out)
    };
    assert_same_history(&run("bounds"), &run("tools"), 1e-9);
}

/// The two paths' histories: the same steps, every column of the bounds' path within `rel` of its
/// largest value on the tools' path (which has the tools' columns besides).
fn assert_same_history(bounds: &History, tools: &History, rel: f64) {
    assert!(bounds.rows.len() > 20, "{} steps", bounds.rows.len());
    let (worst, name) = assert_history_within(bounds, tools, rel, "bounds against tools");
    println!("largest relative difference {worst:.2e} ({name})");
}
