//! Bad input gets one clear message naming the problem and a non-zero exit, and never touches
//! an earlier run's results (checked byte for byte, even with --force).

use crate::common::*;
use std::path::Path;

/// Runs a failing case against the earlier run in `earlier` and checks message and intactness.
fn fails(earlier: &Path, args: &[&str], expect: &str) {
    fails_as(2, earlier, args, expect, &format!("{args:?}"));
}

/// One tet10 (Gmsh 4.1 ASCII) with the mid-node of edge (0, 1) pulled past the opposite edge.
const TANGLED_TET10: &str =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"column\"\n$EndPhysicalNames\n\
$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n$Nodes\n1 10 1 10\n3 1 0 10\n1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n\
0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 0 1.2\n0.5 0.5 0\n0 0.5 0\n0 0 0.5\n0 0.5 0.5\n0.5 0 0.5\n$EndNodes\n\
$Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";

#[test]
fn bad_input_is_reported_and_earlier_results_survive() {
    let dir = scratch("bad_input");
    // An earlier, successful run.
    let ok = scene_variant("terzaghi", &dir, &[("t_end = 100.0", "t_end = 0.002")]);
    let earlier = dir.join("earlier");
    run_ok(1, &["run", &ok, "--out", earlier.to_str().unwrap(), "-q"]);
    assert!(earlier.join("history.csv").exists());
    // The 2-rank launches below, each a fraction of a second, in one hold of the cores (not a
    // wait for two free cores per launch).
    let _cores = cores(2);

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
    fails(&earlier, &["run", &s], "line 10: expected 3 node coordinates, got \"zero\"");
    let s = variant("missing_group", &[("group = \"top\"\npressure", "group = \"lid\"\npressure")]);
    fails(&earlier, &["run", &s], "physical group \"lid\" not found");
    // A .geo with a syntax error: gmsh's own complaint (file and line), whether the error hides
    // its parameters (a DefineConstant gmsh cannot read) or only stops the meshing.
    for (name, geo) in [
        ("broken_params", "DefineConstant H = 100;\nBox(1) = {0, 0, 0, 1, 1, 1};\n"),
        (
            "broken_body",
            "DefineConstant[ H = 100 ];\nDefineConstant[ W = 20 ];\nDefineConstant[ h = 10 ];\nBox(1) = {0, 0, 0, W, W, H;\n",
        ),
    ] {
        let d = dir.join(name);
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("broken.geo"), geo).unwrap();
        let s = scene_variant("terzaghi", &d, &[("geo = \"column.geo\"", "geo = \"broken.geo\"")]);
        let line = if name == "broken_params" { 1 } else { 4 };
        fails(&earlier, &["run", &s], &format!("broken.geo', line {line}: syntax error"));
    }
    // Non-physical parameters (scene values: src/scene/validation_tests.rs; here mesh parameters,
    // checked against the mesh source).
    let s = variant("length", &[("H = 100.0", "H = -100.0")]);
    fails(&earlier, &["run", &s], "H = -100");
    let d = dir.join("radius");
    std::fs::create_dir_all(&d).unwrap();
    let s = scene_variant("cryer", &d, &[("R = 100.0", "R = 0.0")]);
    fails(&earlier, &["run", &s], "R = 0");
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
    // A scene value out of range (one of src/scene/validation_tests.rs's), end to end.
    let s = rvariant("lambda_p", &[("lambda_p = 0.001", "lambda_p = -0.001")]);
    fails(&earlier, &["run", &s], "material.remodelling.lambda_p = -0.001");
    // An integrator the finite-strain mixture is not discretised for.
    let s = rvariant("bdf", &[]);
    fails(&earlier, &["run", &s, "--", "-ts_type", "bdf"], "-ts_type bdf");
    // A chord contraction factor that is not one.
    let s = rvariant("chord", &[]);
    fails(&earlier, &["run", &s, "--", "-poroplast_chord", "1.5"], "-poroplast_chord 1.5");
    // A command-line override the scene rejects (the rest: src/scene/validation_tests.rs).
    fails(
        &earlier,
        &["run", &ok, "--set", "material.viscosity=1"],
        "--set material.viscosity=1: unknown field `viscosity`",
    );
    // The plates experiment's own checks (one validation path with `check`, below).
    fails(
        &earlier,
        &["run", "reference", "--set", "mesh.params.h_pol=5"],
        "mesh.params.h_pol: sphere_quarter.geo has no parameter `h_pol`",
    );
    fails(&earlier, &["run", "reference", "--set", "plates.radius=120"], "plates.radius = 120");
    fails(&earlier, &["run", "reference", "--set", "plates.anchor=\"surface\""], "\"surface\" is not a point group");
    fails(&earlier, &["run", "reference", "--set", "plates.group=\"skin\""], "physical group \"skin\" not found");
    fails(
        &earlier,
        &["run", "reference", "--set", "plates.probe_point=[0.0, 0.0, 300.0]"],
        "probe \"probe_p\": point [0.0, 0.0, 300.0] is outside the mesh",
    );
    // A quadratic tetrahedron whose mid-edge node folds it over.
    let tangled = dir.join("tangled.msh");
    std::fs::write(&tangled, TANGLED_TET10).unwrap();
    let s = variant("tangled", &[("geo = \"column.geo\"", &format!("file = \"{}\"", tangled.display()))]);
    fails(&earlier, &["run", &s], "tetrahedron 1 (element tag) is tangled");
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
fn check_validates_as_run_does() {
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
    // `check` sets the run up and takes its first step as `run` does: what `run` refuses,
    // `check` refuses — PETSc options included.
    let out = poroplast(1, &["check", &scene("terzaghi"), "--", "-ksp_rtoll", "1e-5"]);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("-ksp_rtoll"));
    // It reports what the scene resolved to: the default 3-D mesh's 1,023 tets (6,276 dofs), the
    // element, and the accuracy class of its size (h/R = 0.2); the meridian's own class.
    let out = run_ok(1, &["check", "reference"]);
    assert!(out.contains("1023 tets") && out.contains("6276 dofs"), "{out}");
    assert!(out.contains("discretisation: Taylor–Hood P2–P1 on 1023 curved tets; mesh sphere_quarter.geo"), "{out}");
    assert!(
        out.contains("expected accuracy (plate force, h/R = 0.20): peak 0.5-1.3% low, F(35 s) within about 0.6%"),
        "{out}"
    );
    let out = run_ok(1, &["check", "reference", "--set", "mesh.geometry=axisymmetric", "--set", "fem.stabilisation=0"]);
    assert!(out.contains("curved meridian triangles; mesh sphere_meridian.geo"), "{out}");
    assert!(out.contains("h/R = 0.20): peak and F(35 s) within about 1%"), "{out}");
    let out = run_ok(1, &["check", &scene("terzaghi")]);
    assert!(!out.contains("expected accuracy"), "{out}");
    // Remodelling has its own classes, by the integrator.
    let out = run_ok(1, &["check", "remodel_40"]);
    assert!(out.contains("h/R = 0.20): peak about 0.5% low, F(35 s) within about 0.5% (trapezoidal"), "{out}");
    let out = run_ok(1, &["check", "remodel_40", "--set", "material.remodelling.integrator=\"implicit\""]);
    assert!(out.contains("peak about 1.5% low, F(35 s) about 1.4% high (backward-Euler"), "{out}");
    // The automatic sizes at R = 100 are the default mesh's, and the log says where they came from.
    let out =
        run_ok(1, &["check", "reference", "--set", "mesh.grading=\"auto\"", "--set", "mesh.params={ R = 100.0 }"]);
    assert!(out.contains("6276 dofs") && out.contains("sizes by mesh.grading = auto"), "{out}");
    for (set, expect) in [
        ("plates.radius=120", "plates.radius = 120"),
        ("plates.group=\"skin\"", "physical group \"skin\" not found"),
        ("plates.anchor=\"surface\"", "\"surface\" is not a point group"),
    ] {
        let out = poroplast(1, &["check", "reference", "--set", set]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(expect), "check --set {set}: {err}");
    }
    // A directory rank 0 cannot write into: every rank stops (no rank waits in a collective).
    let out = poroplast(2, &["run", &scene("terzaghi"), "--set", "time.t_end=0.002", "--out", "/proc/1", "--force"]);
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("/proc/1/.lock: cannot create"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
    let text = std::fs::read_to_string(out.join("scene.toml")).unwrap();
    let resolved: toml::Table = toml::from_str(&text).unwrap();
    // Every default written out, each key explained by its declaration.
    assert_eq!(resolved["fem"]["quadrature_degree"].as_integer(), Some(2));
    assert_eq!(resolved["solver"]["preset"].as_str(), Some("auto"));
    assert!(
        text.contains(
            "# drained shear modulus µ of the whole (what a lab measures) [kPa; required; valid (0, ∞)]\nmu = 24.5\n"
        ),
        "{text}"
    );
    assert_eq!(resolved["material"]["mu"].as_float(), Some(24.5));
    assert_eq!(resolved["time"]["t_end"].as_float(), Some(0.004));
    let rows = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let last_t: f64 = rows.lines().last().unwrap().split(',').nth(1).unwrap().parse().unwrap();
    assert!((last_t - 0.004).abs() < 1e-12, "the run ends at the overridden t_end, not {last_t}");
}

/// A battery over the kinds of bad input the run meets after reading its scene (on 1 and 2 ranks,
/// against an earlier run kept intact), and two scene errors as their path's witnesses: each
/// is (what, arguments after `run`, expected part of the one error line). `SCENE` in the
/// arguments is replaced by a file written for the case, `MESH` by a mesh file.
#[test]
fn every_kind_of_bad_input_gets_one_clear_message() {
    let dir = scratch("bad_input_battery");
    let ok = scene_variant("terzaghi", &dir, &[("t_end = 100.0", "t_end = 0.002")]);
    let earlier = dir.join("earlier");
    run_ok(2, &["run", &ok, "--out", earlier.to_str().unwrap(), "-q"]);
    let terzaghi_mesh = |file: &str| {
        let d = dir.join(file.replace(['.', '/'], "_"));
        std::fs::create_dir_all(&d).unwrap();
        scene_variant("terzaghi", &d, &[("geo = \"column.geo\"", &format!("file = \"{file}\""))])
    };
    let write = |name: &str, bytes: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p.display().to_string()
    };
    let good_msh = ONE_TET10;
    let cases: Vec<(&str, Vec<String>, &str)> = vec![
        // Scene errors (the whole range: src/scene/validation_tests.rs): a syntax error and a
        // non-physical value.
        ("TOML syntax", vec![write("syntax.toml", b"name = \"x\"\n[material\nmu = 1\n")], "line 2"),
        ("negative mu", vec!["reference".into(), "--set".into(), "material.mu=-1".into()], "material.mu = -1"),
        // Mesh files.
        ("mesh is a directory", vec![terzaghi_mesh(dir.to_str().unwrap())], "Is a directory"),
        ("empty mesh", vec![terzaghi_mesh(&write("empty.msh", b""))], "empty"),
        (
            "truncated mesh",
            vec![terzaghi_mesh(&write("truncated.msh", &good_msh.as_bytes()[..good_msh.len() / 2]))],
            "msh",
        ),
        ("binary garbage", vec![terzaghi_mesh(&write("garbage.msh", &[0u8, 159, 146, 150, 255, 1, 2, 3]))], "msh"),
        ("2-D mesh", vec![terzaghi_mesh(&write("flat.msh", FLAT_MESH.as_bytes()))], "no tetrahedra"),
        (
            "degenerate tetrahedron",
            vec![terzaghi_mesh(&write(
                "flat_tet.msh",
                good_msh.replacen("\n0 0 1\n0.5 0 0", "\n1 1 0\n0.5 0 0", 1).as_bytes(),
            ))],
            "tetrahedron 1 (element tag) is degenerate",
        ),
        (
            "duplicate node tags",
            vec![terzaghi_mesh(&write("dup.msh", good_msh.replacen("1\n2\n3\n4\n", "1\n2\n2\n4\n", 1).as_bytes()))],
            "node tag 2 defined twice",
        ),
        // PETSc options.
        ("PETSc value", vec![ok.clone(), "--".into(), "-ksp_max_it".into(), "-5".into()], "-ksp_max_it"),
        ("PETSc type", vec![ok.clone(), "--".into(), "-ksp_type".into(), "nonsense".into()], "-ksp_type nonsense"),
        ("PETSc number", vec![ok.clone(), "--".into(), "-ksp_rtol".into(), "abc".into()], "-ksp_rtol abc"),
        (
            "PETSc range",
            vec![ok.clone(), "--".into(), "-ksp_gmres_restart".into(), "0".into()],
            "while reading the PETSc options given: -ksp_gmres_restart 0",
        ),
        ("PETSc integer", vec![ok.clone(), "--".into(), "-snes_max_it".into(), "-1".into()], "-snes_max_it -1"),
        (
            "PETSc type read in the first solve",
            std::iter::once(ok.as_str())
                .chain(["--set", "solver.preset=\"fieldsplit\"", "--", "-fieldsplit_p_pc_type", "nonsense"])
                .map(String::from)
                .collect(),
            "-fieldsplit_p_pc_type nonsense",
        ),
        // A solve that cannot succeed: a solid too soft to carry its weight (on the meridian: the
        // same settling, a tenth of the 3-D quarter's cost).
        (
            "diverging solve",
            vec!["reference_axi".into(), "--set".into(), "material.mu=1e-4".into()],
            "settling under gravity",
        ),
    ];
    for np in [1, 2] {
        let _cores = cores(np); // the launches of a rank count in one hold
        for (what, args, expect) in &cases {
            let a: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
            let mut full = vec!["run"];
            full.extend(a);
            fails_as(np, &earlier, &full, expect, &format!("{what} ({np} rank(s))"));
        }
    }
    assert!(cases.len() >= 15);
    // More ranks than elements (one tet on 2 ranks).
    let one_tet = terzaghi_mesh(&write("one_tet.msh", good_msh.as_bytes()));
    fails_as(2, &earlier, &["run", &one_tet], "fewer than the 2 ranks", "more ranks than elements");
    // The command line: --out that is a file; an unknown subcommand (clap's own message).
    for np in [1, 2] {
        let out = poroplast(np, &["run", &ok, "--out", &ok, "-q"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains("exists and is not a directory"), "{err}");
        let out = poroplast(np, &["runn", &ok]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains("unrecognized subcommand 'runn'"), "{err}");
    }
    assert!(std::fs::read_to_string(&ok).unwrap().contains("t_end = 0.002"), "the scene file is intact");
}

/// One straight tet10 in a physical volume "column" (no surface groups).
const ONE_TET10: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"column\"\n$EndPhysicalNames\n\
$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n$Nodes\n1 10 1 10\n3 1 0 10\n1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n\
0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 0 0\n0.5 0.5 0\n0 0.5 0\n0 0 0.5\n0 0.5 0.5\n0.5 0 0.5\n$EndNodes\n\
$Elements\n1 1 1 1\n3 1 11 1\n1 1 2 3 4 5 6 7 8 9 10\n$EndElements\n";

/// Two triangles and no tetrahedron.
const FLAT_MESH: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n\
0 0 0\n1 0 0\n0 1 0\n1 1 0\n$EndNodes\n$Elements\n1 2 1 2\n2 1 2 2\n1 1 2 3\n2 2 4 3\n$EndElements\n";

/// A case that must fail on `np` ranks (written into `earlier` with --force): non-zero exit,
/// one error line containing `expect`, no panic, and `earlier` byte for byte as it was.
fn fails_as(np: usize, earlier: &Path, args: &[&str], expect: &str, what: &str) {
    let before = snapshot(earlier);
    let mut full: Vec<&str> = args.to_vec();
    let out_flag = ["--out", earlier.to_str().unwrap(), "--force", "-q"];
    let split = full.iter().position(|a| *a == "--").unwrap_or(full.len());
    for (i, a) in out_flag.iter().enumerate() {
        full.insert(split + i, a);
    }
    let out = poroplast(np, &full);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{what}: {args:?} should fail");
    let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("poroplast: error:")).collect();
    assert_eq!(lines.len(), 1, "{what}: one error line expected:\n{stderr}");
    assert!(lines[0].contains(expect), "{what}: `{expect}` expected in:\n{}", lines[0]);
    assert!(!stderr.contains("panicked"), "{what}: panic:\n{stderr}");
    assert_eq!(before, snapshot(earlier), "{what}: the earlier run directory changed");
}

/// `poroplast check my.toml | head -1`: the reader goes away and the output is a closed pipe.
/// Every command that prints must end quietly (exit 0, no panic), not with Rust's "failed
/// printing to stdout" (exit 101). The pipe's read end is closed before the command starts, so
/// that every write fails (a reader closing later would race with a short output).
#[test]
fn a_closed_standard_output_is_a_quiet_exit() {
    let _cores = cores(1); // `check` takes a step on one rank (an MPI singleton)
    for args in [&["scenes"][..], &["scenes", "--keys"], &["show", "reference"], &["check", "reference_axi"]] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let out = launch(1).args(args).stdout(writer).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?} into a closed pipe: {}\n{stderr}", out.status);
        assert!(stderr.is_empty(), "{args:?} into a closed pipe wrote to standard error:\n{stderr}");
    }
}

/// Mistakes found when the run is set up, before its first step: a body nothing holds (no
/// plates, no condition blocking its translation: otherwise the first step diverges with "SNES
/// reason -3"), a plate scene meshed with a handful of cells (a few dozen: a warning); and what `check` reports of the
/// material (the solid's and the aggregate's moduli).
#[test]
fn an_unheld_body_and_a_too_coarse_mesh_are_named() {
    let dir = scratch("unheld");
    let text = std::fs::read_to_string(scene("reference_axi")).unwrap();
    let (head, rest) = text.split_once("[plates]").unwrap();
    let no_plates = dir.join("no_plates.toml");
    std::fs::write(&no_plates, format!("{head}{}", &rest[rest.find("[time]").unwrap()..])).unwrap();
    let out = poroplast(1, &["check", no_plates.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("nothing holds the body along z: the scene has no [plates], no [[bc]]"),
        "{err}"
    );
    // Held at the bottom pole, the same body passes the check (without gravity, which a point
    // support could not carry).
    let held = dir.join("held.toml");
    let bc = "[[bc]]\ngroup = \"pole_bottom\"\ndisplacement = { z = 0.0 }\n\n";
    std::fs::write(&held, format!("{head}{bc}{}", &rest[rest.find("[time]").unwrap()..])).unwrap();
    run_ok(1, &["check", held.to_str().unwrap(), "--set", "material.gravity=[0.0, 0.0, 0.0]"]);
    // Sizes of the radius itself: 4 triangles, refused; 40 µm: 44, a warning.
    let out =
        poroplast(1, &["check", "reference_axi", "--set", "mesh.params.h=100", "--set", "mesh.params.h_pole=100"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("the mesh has 4 cells, fewer than 10: its sizes (R = 100, h = 100"),
        "{err}"
    );
    let out = poroplast(1, &["check", "reference_axi", "--set", "mesh.params.h=40", "--set", "mesh.params.h_pole=12"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success() && err.contains("warning: builtin:reference_axi: the mesh has 44 cells, fewer than 100"),
        "{err}"
    );
    // Φs = 0.6, µ = 20 kPa: the aggregate's G = 12 kPa, E = 2 G (1 + 0.2) = 28.8 kPa.
    let out = run_ok(1, &["check", "reference_axi"]);
    assert!(
        out.contains(
            "material: the solid's shear modulus µ = 20 kPa (ν = 0.2); the aggregate's drained shear modulus Φs µ = 12 \
             kPa, drained Young's modulus 2 Φs µ (1 + ν) = 28.8 kPa"
        ),
        "{out}"
    );
}

/// A scene file written for the previous version (the shipped `reference_axi` as it was, kept in
/// tests/data/scenes_v1) passes `check`, with a note naming its moved keys and what to write.
#[test]
fn a_scene_written_for_the_previous_version_still_runs() {
    let old = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes_v1/reference_axi.toml");
    let out = poroplast(1, &["check", old.to_str().unwrap()]);
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && stdout.contains("ok — mesh"), "{stdout}{stderr}");
    let note = format!(
        "note: {}: plates.t_ramp = 5 and plates.t_end = 40 are deprecated: write plates.ramp = 5, plates.hold = 30, \
         plates.release = 5",
        old.display()
    );
    assert!(stderr.contains(&note), "{stderr}");
}
