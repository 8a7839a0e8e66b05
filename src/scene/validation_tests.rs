//! Scene validation without MPI or PETSc: every kind of bad scene (TOML syntax and types,
//! unknown keys at every level, non-physical values, inconsistent keys, bad overrides) gets one
//! error naming the problem, from [`LoadedScene::load`] as `run` and `check` call it. The same
//! message reaches the user as `poroplast: error: {message}`; that path, with an earlier run
//! left intact and every rank stopping, is tested end to end in tests/bad_input.rs.

use super::{LoadedScene, BUILTIN};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh directory for one scene file.
fn scratch() -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::env::temp_dir().join(format!(
        "poroplast-validation-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The message of loading builtin `scene` with lines replaced (`from` → `to`), written to a file,
/// and `--set` overrides `sets`; panics if it loads.
fn error_of(scene: &str, edits: &[(&str, &str)], sets: &[&str]) -> String {
    let arg = if edits.is_empty() {
        scene.to_string()
    } else {
        let mut text = BUILTIN.iter().find(|(n, _)| *n == scene).unwrap().1.to_string();
        for (from, to) in edits {
            assert!(text.contains(from), "scene {scene} has no `{from}`");
            text = text.replacen(from, to, 1);
        }
        let p = scratch().join(format!("{scene}.toml"));
        std::fs::write(&p, text).unwrap();
        p.display().to_string()
    };
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    match LoadedScene::load(&arg, &sets) {
        Ok(_) => panic!("{scene} {edits:?} {sets:?} loads"),
        Err(e) => e.to_string(),
    }
}

#[track_caller]
fn expect(scene: &str, edits: &[(&str, &str)], sets: &[&str], part: &str) {
    let msg = error_of(scene, edits, sets);
    assert!(msg.contains(part), "{scene} {edits:?} {sets:?}: `{part}` expected in: {msg}");
    assert_eq!(msg.lines().count(), 1, "one line expected: {msg}");
}

#[test]
fn toml_syntax_and_types_name_the_line_or_the_key() {
    let p = scratch().join("syntax.toml");
    std::fs::write(&p, "name = \"x\"\n[material\nmu = 1\n").unwrap();
    let msg = LoadedScene::load(&p.display().to_string(), &[]).err().unwrap().to_string();
    assert!(msg.contains("line 2"), "{msg}");
    expect("cryer", &[("nu = 0.2", "nu = [0.2]")], &[], "line");
    expect("reference", &[], &["time.dt=\"fast\""], "time.dt");
    // A wrong type in the tagged [material] table, which has another list (gravity): the key.
    expect(
        "reference",
        &[("phi_s = 0.6", "phi_s = [0.6]")],
        &[],
        "(`phi_s = [0.6]`): material.phi_s: invalid type: sequence, expected a number",
    );
    expect("terzaghi", &[], &["material.mu=soft"], "--set material.mu=soft: invalid type: string \"soft\"");
    expect("terzaghi", &[], &["time.dt"], "--set time.dt: expected KEY=VALUE");
    expect("no-such-scene", &[], &[], "not a builtin scene");
}

#[test]
fn unknown_keys_at_every_level_are_named() {
    for (set, field) in [
        ("plates.speed=1", "speed"),
        ("time.cfl=1", "cfl"),
        ("output.vtk=true", "vtk"),
        ("mesh.order=3", "order"),
        ("fem.degree=3", "degree"),
        ("solver.tol=1", "tol"),
        ("material.penalty.k=1", "k"),
        ("bc.0.slip=true", "slip"),
    ] {
        expect("reference", &[], &[set], &format!("unknown field `{field}`"));
    }
    expect("terzaghi", &[("nu = 0.2", "nu = 0.2\nviscosity = 1.0")], &[], "unknown field `viscosity`");
    expect(
        "terzaghi",
        &[("name = \"terzaghi\"", "name = \"terzaghi\"\ngravity = true")],
        &[],
        "unknown field `gravity`",
    );
    expect("terzaghi", &[], &["material.viscosity=1"], "--set material.viscosity=1: unknown field `viscosity`");
    expect("relaxation", &[("sigma_y = 2.0", "sigma_y = 2.0, eta = 1.0")], &[], "unknown field `eta`");
}

#[test]
fn unknown_variants_list_the_choices() {
    let rv = |from: &str, to: &str, part: &str| expect("relaxation", &[(from, to)], &[], part);
    rv(
        "sigma_y = 2.0",
        "sigma_y = 2.0, form = \"40c\"",
        "material.remodelling.form: unknown variant `40c`, expected one of `40b`, `40a`, `40b_tau`",
    );
    rv(
        "sigma_y = 2.0",
        "sigma_y = 2.0, integrator = \"rk4\"",
        "material.remodelling.integrator: unknown variant `rk4`, expected one of `implicit`, `trapezoidal`, `explicit`",
    );
    rv(
        "[output]",
        "[solver]\npreset = \"amg\"\n\n[output]",
        "solver.preset: unknown variant `amg`, expected one of `auto`, `direct`, `fieldsplit`, `lu`",
    );
    expect(
        "terzaghi",
        &[],
        &["fem.element=\"Q2\""],
        "--set fem.element=\"Q2\": unknown variant `Q2`, expected one of `P2-P1`, `P1-P1`, `auto`",
    );
}

#[test]
fn non_physical_values_are_named_with_their_value() {
    for (set, part) in [
        ("material.mu=-1", "material.mu = -1"),
        ("material.mu=nan", "material.mu = NaN"),
        ("material.mu=inf", "material.mu = inf"),
        ("material.nu=-1.5", "material.nu = -1.5"),
        ("material.phi_s=1.0", "material.phi_s = 1"),
        ("material.phi_s=0.0", "material.phi_s = 0"),
        ("material.k0=0.0", "material.k0 = 0"),
        ("plates.compression=1.0", "plates.compression = 1"),
        ("time.dt=0.0", "time.dt = 0"),
        ("time.dt=-1.0", "time.dt = -1"),
        ("plates.radius=0.0", "plates.radius = 0"),
        ("time.land_on=[nan]", "time.land_on"),
        ("time.steps=[1.0, 0.5]", "time.steps[1] = 0.5: the step end times must increase"),
        ("time.steps=[0.0]", "time.steps[0] = 0"),
        ("time.steps=[1.0, 1.0]", "time.steps[1] = 1"),
        (
            "time.steps=[1.0, 200.0]",
            "time.steps[1] = 200: the step end times must increase from above 0 to at most time.t_end = 100",
        ),
        ("time.steps=[nan]", "time.steps[0] = NaN"),
        ("plates.probe_point=[0.0, nan, 1.0]", "plates.probe_point = NaN"),
    ] {
        expect("reference", &[], &[set], part);
    }
    expect("terzaghi", &[("nu = 0.2", "nu = 0.5")], &[], "material.nu = 0.5");
    expect("terzaghi", &[], &["material.nu=0.5"], "material.nu = 0.5");
    expect("terzaghi", &[("permeability = 3.7729", "permeability = 0.0")], &[], "material.permeability = 0");
    let rv = |from: &str, to: &str, part: &str| expect("relaxation", &[(from, to)], &[], part);
    rv("lambda_p = 0.001", "lambda_p = -0.001", "material.remodelling.lambda_p = -0.001");
    rv("sigma_y = 2.0", "sigma_y = nan", "material.remodelling.sigma_y = NaN");
    rv("[[0.1180339887498949, 0.0, 0.0]", "[[-1.5, 0.0, 0.0]", "det(I + G)");
    rv("fields_every = 10", "fields_every = 10\nfields_at = [2000.0]", "output.fields_at: 2000");
    rv("[time]", "[time]\nerror_tolerance = -1e-3", "time.error_tolerance");
    expect("terzaghi", &[], &["fem.stabilisation_fade=0"], "fem.stabilisation_fade = 0: must be positive");
}

#[test]
fn inconsistent_keys_are_named_together() {
    expect("reference", &[], &["plates.t_ramp=50.0"], "plates.t_end = 40: must be at least ramp + release = 100");
    expect("reference", &[], &["time.dt=10"], "time.dt = 10 exceeds time.dt_max = 2");
    expect("terzaghi", &[], &["time.dt_min=1e3"], "time.dt_min = 1000: must be below the first step");
    expect(
        "terzaghi",
        &[],
        &["time.dt_max_ramp=0.1"],
        "time.dt_max_ramp caps the steps of the plates' loading ramp: the scene has no [plates]",
    );
    expect(
        "terzaghi",
        &[],
        &["mesh.grading=\"auto\""],
        "scales the mesh sizes by the aggregate's radius: give mesh.params.R",
    );
    // Overrides are applied together, then checked: the second completes the table the first
    // starts (the reference scene has no remodelling).
    expect(
        "reference",
        &[],
        &["material.remodelling.lambda_p=-1", "material.remodelling.sigma_y=2"],
        "material.remodelling.lambda_p = -1: must be finite and >= 0",
    );
    // Permeable plates need a thickness, a non-negative permeability, and drainage.
    expect("reference", &[], &["plates.permeability=3.7729e-4"], "plates.permeability needs plates.thickness");
    expect("reference", &[], &["plates.thickness=100"], "plates.thickness is only used with");
    expect(
        "reference",
        &[],
        &["plates.permeability=-1", "plates.thickness=100"],
        "plates.permeability = -1: must be >= 0",
    );
    expect(
        "reference",
        &[],
        &["plates.permeability=1e-4", "plates.thickness=100", "plates.drainage=false"],
        "plates.drainage = false seals",
    );
}

/// `model = "neo_hookean"`: the mixture's keys are checked as for Holmes–Mow, each bad value
/// named; Holmes–Mow's `alpha` is refused naming the keys to give instead.
#[test]
fn neo_hookean_keys_are_checked() {
    let nh = "material.model=neo_hookean";
    let loaded = LoadedScene::load("reference_axi", &[nh.to_string()]).unwrap();
    assert_eq!(loaded.scene.material.model().0, "neo_hookean");
    let cases = [
        (
            vec!["material.alpha=[0.1, 0.5, 0.25]"],
            "`alpha` is a Holmes–Mow key (its α's): model = \"neo_hookean\" takes `nu`",
        ),
        (vec!["material.mu=-3.0"], "material.mu = -3"),
        (vec!["material.nu=0.5"], "material.nu = 0.5"),
        (vec!["material.phi_s=1.0"], "material.phi_s = 1"),
        (vec!["material.k0=0.0"], "material.k0 = 0"),
    ];
    for (sets, part) in cases {
        expect("reference_axi", &[], &[&[nh][..], &sets[..]].concat(), part);
    }
    expect("reference_axi", &[("nu = 0.2\n", "")], &[nh], "[material] neo_hookean: give `nu` and one modulus");
}

/// `[surface]`: a negative tension, and values off by 10³ (N/m or µN/m for mN/m), are refused
/// with the unit named; an unknown key too.
#[test]
fn surface_tension_is_checked() {
    let add = |v: &str| format!("[surface]\ntension = {v}\n\n[plates]\n");
    let cases = [
        ("-1.0", "surface.tension = -1: must be finite and >= 0"),
        ("0.005", "looks like N/m (write 5 mN/m)"),
        ("5000.0", "looks like µN/m (write 5 mN/m)"),
    ];
    for (v, part) in cases {
        expect("reference", &[("[plates]\n", &add(v))], &[], part);
    }
}

/// `surface.adhesion`: negative, beyond complete wetting (w > 2γ), without a tension, off by
/// 10³, or without plates, each refused naming the reason; the range defaults to 0.05 R and is
/// checked.
#[test]
fn adhesion_is_checked() {
    let add = |v: &str| format!("[surface]\ntension = 5.0\n{v}\n\n[plates]\n");
    let cases = [
        ("adhesion = -1.0", "surface.adhesion = -1: must be finite and >= 0"),
        ("adhesion = 10.5", "surface.adhesion = 10.5 > 2 × surface.tension = 10: beyond complete wetting"),
        ("adhesion = 0.005", "surface.adhesion = 0.005: the unit is mN/m (= kPa µm)"),
        ("adhesion = 5000.0", "looks like µN/m (write 5 mN/m)"),
        ("adhesion = 5.0\nadhesion_range = 0.0", "surface.adhesion_range = 0: must be positive"),
    ];
    for (v, part) in cases {
        expect("reference", &[("[plates]\n", &add(v))], &[], part);
    }
    expect(
        "reference",
        &[("[plates]\n", "[surface]\ntension = 0.0\nadhesion = 5.0\n\n[plates]\n")],
        &[],
        "surface.adhesion = 5 without surface.tension",
    );
    expect(
        "cryer",
        &[("[verification]", "[surface]\ntension = 5.0\nadhesion = 5.0\n\n[verification]")],
        &[],
        "surface.adhesion = 5: the work of adhesion is to the plates, and this scene has no [plates]",
    );
    // Complete wetting itself is accepted; the range is 0.05 R unless given.
    let load = |v: &str| {
        let text = super::BUILTIN.iter().find(|(n, _)| *n == "reference").unwrap().1.replacen("[plates]\n", &add(v), 1);
        let p = scratch().join("adhesion.toml");
        std::fs::write(&p, text).unwrap();
        let s = LoadedScene::load(&p.display().to_string(), &[]).unwrap();
        let sf = s.scene.surface.clone().unwrap();
        (sf.adhesion, sf.adhesion_range, s.scene.plates.unwrap().radius())
    };
    let (w, range, r) = load("adhesion = 10.0");
    assert_eq!((w, range), (10.0, Some(0.05 * r)));
    assert_eq!(load("adhesion = 5.0\nadhesion_range = 0.3").1, Some(0.3));
    assert_eq!(load("").1, None);
}

/// `plates.table`: the protocol as rows; out of order, not from rest, a compression out of
/// range, or given beside the phases, each refused naming the row or the key.
#[test]
fn a_protocol_table_is_checked() {
    let phases = "compression = 0.3          # u_max = 0.3 * 2R = 60 um\nramp = 5.0                 # s: the plate rises\nhold = 30.0                # s: held\nrelease = 5.0              # s: the plate returns; then rest until time.t_end\n";
    let cases = [
        (
            "table = [[0.0, 0.0], [5.0, 0.3], [4.0, 0.3]]\n",
            "plates.table row 3: time 4 s does not come after row 2's 5 s",
        ),
        ("table = [[1.0, 0.0], [5.0, 0.3]]\n", "plates.table row 1 = [1, 0]: the table starts at rest"),
        ("table = [[0.0, 0.0], [5.0, 1.2]]\n", "plates.table row 2 compression = 1.2: must lie in [0, 1)"),
        (
            "table = [[0.0, 0.0], [5.0, 15.0]]\n",
            "plates.table row 2 compression = 15: must lie in [0, 1): 15 looks like a percentage (15% = 0.15 of 2R)",
        ),
        ("table = [[0.0, 0.0]]\n", "plates.table: 1 row(s)"),
        (
            "table = [[0.0, 0.0], [5.0, 0.3]]\nhold = 3.0\n",
            "plates.table gives the whole protocol; leave out plates.hold",
        ),
        (
            "table = [[0.0, 0.0], [5.0, 0.3, 60.0]]\n",
            "plates.table row 2 = [5.0, 0.3, 60.0] has 3 number(s): each row is exactly [t (s), ũ = u / (2R)]",
        ),
        ("table = [[0.0, 0.0], [5.0]]\n", "plates.table row 2 = [5.0] has 1 number(s)"),
        (
            "table = [[0.0, 0.0], [5000.0, 0.3], [350000.0, 0.3], [400000.0, 0.0]]\n",
            "the run ends (time.t_end = 100 s) before the table's second row, at 5000 s: the plates do not finish \
             their first move, and the table lasts 400000 s, longer than experiments do. Its times are seconds \
             (milliseconds? divide them by 1000)",
        ),
    ];
    for (table, part) in cases {
        expect("reference", &[(phases, table)], &[], part);
    }
    expect("reference", &[(phases, "ramp = 5.0\nhold = 30.0\nrelease = 5.0\n")], &[], "give plates.compression");
    expect("reference", &[], &["plates.compression=30"], "30 looks like a percentage (30% = 0.3 of 2R)");
    // On the command line a table replaces the phases; a phase cannot change a table.
    let t = LoadedScene::load("reference", &["plates.table=[[0.0, 0.0], [5.0, 0.2], [60.0, 0.2], [65.0, 0.0]]".into()])
        .unwrap();
    assert_eq!(t.scene.plates.as_ref().unwrap().protocol().ends(), [5.0, 60.0, 65.0]);
    let e = LoadedScene::load("tst_hold", &["plates.compression=0.2".into()]).unwrap_err().to_string();
    assert!(
        e.contains("this scene's protocol is a plates.table, which the phases cannot change: override the table"),
        "{e}"
    );
    // Two compressions: the summary's phases are the first ramp to the largest ũ, the hold to
    // its last row there, and the release to the next rest.
    let table = "table = [[0.0, 0.0], [5.0, 0.2], [60.0, 0.2], [65.0, 0.0], [120.0, 0.0], [125.0, 0.3], [400.0, 0.3], [405.0, 0.0]]\n";
    let mut text = super::BUILTIN.iter().find(|(n, _)| *n == "reference").unwrap().1.replacen(phases, table, 1);
    text = text.replacen("t_end = 100.0", "t_end = 500.0", 1);
    let p = scratch().join("two.toml");
    std::fs::write(&p, text).unwrap();
    let s = LoadedScene::load(&p.display().to_string(), &[]).unwrap();
    let plates = s.scene.plates.as_ref().unwrap();
    assert_eq!(plates.compression(), 0.3);
    assert_eq!(plates.protocol().ends(), [125.0, 400.0, 405.0]);
    assert_eq!(plates.path().len(), 8);
    // The phases are the path of their four corners.
    let phased = LoadedScene::load("reference", &[]).unwrap();
    let path = phased.scene.plates.as_ref().unwrap().path();
    assert_eq!(path, [[0.0, 0.0], [5.0, 0.3], [35.0, 0.3], [40.0, 0.0]]);
}
