//! Bad input gets one clear message naming the problem and a non-zero exit, and never touches
//! an earlier run's results (checked byte for byte, even with --force).

mod common;
use common::*;
use std::path::Path;

/// All files of a directory with their contents.
fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.display().to_string(), std::fs::read(&p).unwrap()))
        .collect();
    v.sort();
    v
}

/// Runs a failing case against the earlier run in `earlier` and checks message and intactness.
fn fails(earlier: &Path, args: &[&str], expect: &str) {
    let before = snapshot(earlier);
    let mut full: Vec<&str> = args.to_vec();
    let out_flag = ["--out", earlier.to_str().unwrap(), "--force", "-q"];
    let split = full.iter().position(|a| *a == "--").unwrap_or(full.len());
    for (i, a) in out_flag.iter().enumerate() {
        full.insert(split + i, a);
    }
    let out = poroplast(2, &full);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} should fail");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("poroplast: error:"))
        .unwrap_or_else(|| panic!("no error line in:\n{stderr}"));
    assert!(line.contains(expect), "message for {args:?} should mention `{expect}`:\n{line}");
    assert_eq!(stderr.lines().filter(|l| l.starts_with("poroplast: error:")).count(), 1, "one message only:\n{stderr}");
    assert_eq!(before, snapshot(earlier), "{args:?} modified the earlier run directory");
}

#[test]
fn bad_input_is_reported_and_earlier_results_survive() {
    let dir = scratch("bad_input");
    // An earlier, successful run.
    let ok = scene_variant("terzaghi", &dir, &[("t_end = 100.0", "t_end = 0.002")]);
    let earlier = dir.join("earlier");
    run_ok(1, &["run", &ok, "--out", earlier.to_str().unwrap(), "-q"]);
    assert!(earlier.join("history.csv").exists());

    let variant = |name: &str, edits: &[(&str, &str)]| {
        let d = dir.join(name);
        std::fs::create_dir_all(&d).unwrap();
        scene_variant("terzaghi", &d, edits)
    };
    // Mesh problems.
    let s = variant("missing_mesh", &[("geo = \"column.geo\"", "file = \"nowhere/column.msh\"")]);
    fails(&earlier, &["run", &s], "does not exist");
    let bad_msh = dir.join("malformed.msh");
    std::fs::write(&bad_msh, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n3 1 0 3\n1\n2\n3\n0 0 zero\n")
        .unwrap();
    let s = variant("malformed_mesh", &[("geo = \"column.geo\"", &format!("file = \"{}\"", bad_msh.display()))]);
    fails(&earlier, &["run", &s], "line");
    let s = variant("missing_group", &[("group = \"top\"\npressure", "group = \"lid\"\npressure")]);
    fails(&earlier, &["run", &s], "physical group \"lid\" not found");
    // Non-physical parameters.
    let s = variant("nu", &[("nu = 0.2", "nu = 0.5")]);
    fails(&earlier, &["run", &s], "material.nu = 0.5");
    let s = variant("perm", &[("permeability = 3.7729", "permeability = 0.0")]);
    fails(&earlier, &["run", &s], "material.permeability = 0");
    let s = variant("length", &[("H = 100.0", "H = -100.0")]);
    fails(&earlier, &["run", &s], "H = -100");
    let d = dir.join("radius");
    std::fs::create_dir_all(&d).unwrap();
    let s = scene_variant("cryer", &d, &[("R = 100.0", "R = 0.0")]);
    fails(&earlier, &["run", &s], "R = 0");
    // Unknown keys, in a table and at the top level.
    let s = variant("key", &[("nu = 0.2", "nu = 0.2\nviscosity = 1.0")]);
    fails(&earlier, &["run", &s], "unknown field `viscosity`");
    let s = variant("topkey", &[("name = \"terzaghi\"", "name = \"terzaghi\"\ngravity = true")]);
    fails(&earlier, &["run", &s], "unknown field `gravity`");
    // Unknown PETSc option (command line and scene).
    fails(&earlier, &["run", &ok, "--", "-ksp_rtoll", "1e-5"], "-ksp_rtoll");
    let s = variant("petsc", &[("[time]", "[petsc]\nsnes_monitorr = true\n\n[time]")]);
    fails(&earlier, &["run", &s], "-snes_monitorr");
    // Overriding the solver preset from the command line is not an unknown option (the
    // fieldsplit defaults it leaves unread were set by us, not the user).
    let d = dir.join("lu-override");
    run_ok(1, &["run", &ok, "--out", d.to_str().unwrap(), "-q", "--", "-ksp_type", "preonly", "-pc_type", "lu"]);
    // Mirroring across a group that is not a coordinate plane through the origin.
    let s = variant("mirror", &[("[material]", "mirror = [\"top\"]\n\n[material]")]);
    fails(&earlier, &["run", &s], "not in a plane x = 0, y = 0 or z = 0");
    // Remodelling, initial state and output times (on the relaxation scene's material).
    let rvariant = |name: &str, edits: &[(&str, &str)]| {
        let d = dir.join(name);
        std::fs::create_dir_all(&d).unwrap();
        scene_variant("relaxation", &d, edits)
    };
    let s = rvariant("lambda_p", &[("lambda_p = 0.001", "lambda_p = -0.001")]);
    fails(&earlier, &["run", &s], "material.remodelling.lambda_p = -0.001");
    let s = rvariant("sigma_y", &[("sigma_y = 2.0", "sigma_y = nan")]);
    fails(&earlier, &["run", &s], "material.remodelling.sigma_y = NaN");
    let s = rvariant("form", &[("sigma_y = 2.0", "sigma_y = 2.0, form = \"40c\"")]);
    fails(&earlier, &["run", &s], "material.remodelling.form = \"40c\"");
    let s = rvariant("integrator", &[("sigma_y = 2.0", "sigma_y = 2.0, integrator = \"rk4\"")]);
    fails(&earlier, &["run", &s], "material.remodelling.integrator = \"rk4\"");
    let s = rvariant("remodelling_key", &[("sigma_y = 2.0", "sigma_y = 2.0, eta = 1.0")]);
    fails(&earlier, &["run", &s], "unknown field `eta`");
    let s = rvariant("initial", &[("[[0.1180339887498949, 0.0, 0.0]", "[[-1.5, 0.0, 0.0]")]);
    fails(&earlier, &["run", &s], "det(I + G)");
    let s = rvariant("fields_at", &[("fields_every = 10", "fields_every = 10\nfields_at = [2000.0]")]);
    fails(&earlier, &["run", &s], "output.fields_at: 2000");
    // An integrator the finite-strain mixture is not discretised for; a solver preset, an
    // error tolerance and a chord rate that do not exist.
    let s = rvariant("bdf", &[]);
    fails(&earlier, &["run", &s, "--", "-ts_type", "bdf"], "-ts_type bdf");
    let s = rvariant("preset", &[("[output]", "[solver]\npreset = \"amg\"\n\n[output]")]);
    fails(&earlier, &["run", &s], "solver.preset = \"amg\"");
    let s = rvariant("tolerance", &[("[time]", "[time]\nerror_tolerance = -1e-3")]);
    fails(&earlier, &["run", &s], "time.error_tolerance");
    // A chord contraction factor that is not one.
    let s = rvariant("chord", &[]);
    fails(&earlier, &["run", &s, "--", "-poroplast_chord", "1.5"], "-poroplast_chord 1.5");
    // Command-line overrides: an unknown key, a wrong type, a value out of range, no value.
    fails(
        &earlier,
        &["run", &ok, "--set", "material.viscosity=1"],
        "--set material.viscosity=1: unknown field `viscosity`",
    );
    fails(
        &earlier,
        &["run", &ok, "--set", "material.mu=soft"],
        "--set material.mu=soft: invalid type: string \"soft\"",
    );
    fails(&earlier, &["run", &ok, "--set", "material.nu=0.5"], "material.nu = 0.5");
    fails(&earlier, &["run", &ok, "--set", "time.dt"], "--set time.dt: expected KEY=VALUE");
    fails(&earlier, &["run", &ok, "--set", "fem.stabilisation_fade=0"], "fem.stabilisation_fade = 0: must be positive");
    fails(&earlier, &["run", &ok, "--set", "time.dt_min=1e3"], "time.dt_min = 1000: must be below the first step");
    fails(&earlier, &["run", &ok, "--set", "fem.element=\"Q2\""], "fem.element = \"Q2\": use \"P2-P1\" or \"P1-P1\"");
    fails(
        &earlier,
        &["run", "reference", "--set", "fem.element=\"P1-P1\""],
        "fem.element = \"P1-P1\": not with plates",
    );
    // A scene that does not exist.
    fails(&earlier, &["run", "no-such-scene"], "not a builtin scene");
    // Without --force an existing run directory is refused, untouched.
    let before = snapshot(&earlier);
    let out = poroplast(1, &["run", &ok, "--out", earlier.to_str().unwrap(), "-q"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--force"));
    assert_eq!(before, snapshot(&earlier));
}

#[test]
fn check_validates_without_solving() {
    let dir = scratch("check");
    let out = run_ok(1, &["check", &scene("terzaghi")]);
    assert!(out.contains("ok"), "{out}");
    let s = scene_variant("terzaghi", &dir, &[("group = \"bottom\"", "group = \"floor\"")]);
    let out = poroplast(1, &["check", &s]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("physical group \"floor\" not found"));
    // The same through an override of the first [[bc]]'s group.
    let out = poroplast(1, &["check", &scene("terzaghi"), "--set", "bc.0.group=floor"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("physical group \"floor\" not found"));
}

#[test]
fn overrides_reach_the_run_and_its_resolved_scene() {
    let dir = scratch("overrides");
    let out = dir.join("run");
    let log = run_ok(
        1,
        &[
            "run",
            &scene("terzaghi"),
            "--set",
            "material.mu=24.5",
            "--set",
            "time.t_end=0.004",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(log.contains("overrides: --set material.mu=24.5 --set time.t_end=0.004"), "{log}");
    let resolved: toml::Table = toml::from_str(&std::fs::read_to_string(out.join("scene.toml")).unwrap()).unwrap();
    assert_eq!(resolved["material"]["mu"].as_float(), Some(24.5));
    assert_eq!(resolved["time"]["t_end"].as_float(), Some(0.004));
    let rows = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let last_t: f64 = rows.lines().last().unwrap().split(',').nth(1).unwrap().parse().unwrap();
    assert!((last_t - 0.004).abs() < 1e-12, "the run ends at the overridden t_end, not {last_t}");
}
