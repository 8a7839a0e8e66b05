//! What a lab types on its first day, read right or refused before anything is written: `-q`
//! keeps the scene's notes; `poroplast columns` lists exactly the columns a run writes; a
//! study's misspelt observable, a modulus in Pa, a table row of three numbers or in milliseconds
//! are refused naming the fix, with an earlier run's directory untouched.

use crate::common::*;

/// One run of 0.1 s of `reference_axi` (its release ends after the run: a note) under `-q`.
#[test]
fn quiet_keeps_the_notes_and_columns_lists_the_history_header() {
    let d = scratch("lab_quiet");
    let out = d.join("run");
    let args = ["run", "reference_axi", "--out", out.to_str().unwrap(), "-q", "--set", "time.t_end=0.1"];
    let o = poroplast(1, &args);
    let stdout = expect_success(&o, "a quiet run");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("poroplast: note: builtin:reference_axi: the plates' release ends at 40 s"), "{stderr}");
    assert!(!stdout.lines().any(|l| l.starts_with("step ")), "-q printed progress lines:\n{stdout}");
    assert!(stdout.contains("summary:"), "-q dropped the summary:\n{stdout}");
    // The columns a scene's run writes, without running it: the header of the run just made.
    let cols = run_ok(1, &["columns", "reference_axi", "--set", "time.t_end=0.1"]);
    let header = std::fs::read_to_string(out.join("history.csv")).unwrap().lines().next().unwrap().to_string();
    assert_eq!(cols.lines().collect::<Vec<_>>().join(","), header);
}

#[test]
fn a_studys_misspelt_observable_is_refused_before_anything_runs() {
    let d = scratch("lab_observables");
    let cases = [
        ("max:force_totl_mg", "no column `force_totl_mg` in this scene's history (did you mean `force_total_mg`?)"),
        ("sigma_ap@2", "(did you mean `sigma_app`?)"),
        ("maxx:force_total_mg", "unknown kind `maxx:` (did you mean `max`?)"),
        ("force_total_mg@50", "t = 50 s is outside the run, [0, 2] s"),
    ];
    for (i, (spec, expect)) in cases.iter().enumerate() {
        let study = d.join(format!("s{i}.toml"));
        let text = format!(
            "scene = \"reference_axi\"\nset = [\"time.t_end=2\"]\nobserve = [\"force_total_mg@1s\", \"{spec}\"]\n\
             [[grid]]\nkey = \"material.mu\"\nvalues = [10, 20]\n"
        );
        std::fs::write(&study, text).unwrap();
        let out = d.join(format!("sweep{i}"));
        let o = poroplast(1, &["sweep", study.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{spec}: {stderr}");
        assert!(stderr.contains(expect), "{spec}: `{expect}` expected in\n{stderr}");
        assert!(!out.exists(), "{spec}: the sweep directory was made");
    }
    // A syntax error names the study and its line.
    let study = d.join("broken.toml");
    std::fs::write(&study, "scene = \"reference_axi\"\nobserve = [\"max:height\"\n[[grid]]\n").unwrap();
    let o = poroplast(1, &["sweep", study.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.contains("sweep: study ") && stderr.contains("broken.toml: line 3"), "{stderr}");
}

#[test]
fn unit_slips_and_malformed_tables_are_refused_and_earlier_results_survive() {
    let d = scratch("lab_slips");
    let earlier = d.join("earlier");
    run_ok(1, &["run", "terzaghi", "--set", "time.t_end=0.002", "--out", earlier.to_str().unwrap(), "-q"]);
    let before = snapshot(&earlier);
    let e = earlier.to_str().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &["reference_axi", "--set", "material.drained_youngs_modulus=28800"],
            "28800 looks like Pa (28800 Pa = 28.8 kPa; write that) — refused as a unit mistake",
        ),
        (
            &["tst_hold", "--set", "plates.table=[[0.0, 0.0], [5.0, 0.3, 60.0]]"],
            "plates.table row 2 = [5.0, 0.3, 60.0] has 3 number(s): each row is exactly [t (s), ũ = u / (2R)]",
        ),
        (
            &[
                "tst_hold",
                "--set",
                "plates.table=[[0.0, 0.0], [5000.0, 0.15], [605000.0, 0.15]]",
                "--set",
                "time.t_end=605",
                "--set",
                "output.fields_at=[]",
            ],
            "before the table's second row, at 5000 s: the plates do not finish their first move, and the table lasts \
             605000 s, longer than experiments do. Its times are seconds (milliseconds? divide them by 1000)",
        ),
        (&["tst_hold", "--set", "plates.compression=0.2"], "override the table"),
    ];
    for (args, expect) in cases {
        let mut full = vec!["run"];
        full.extend(args);
        full.extend(["--out", e, "--force"]);
        let o = poroplast(1, &full);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expect), "{args:?}: `{expect}` expected in\n{stderr}");
        assert_eq!(snapshot(&earlier), before, "{args:?} touched the earlier run");
    }
    // A table given on the command line replaces a scene's phases (the scene loads, and runs).
    run_ok(1, &["columns", "reference_axi", "--set", "plates.table=[[0.0, 0.0], [5.0, 0.2], [10.0, 0.0]]"]);
}
