//! Scenes that scale with the body and keep running: the shipped scenes as written for the
//! previous version (tests/data/scenes_v1, copied verbatim) still load and resolve to what the
//! shipped scenes are now; `reference_axi` is `reference` on the meridian; a copy with only the
//! radius changed scales its plates and mesh; the aggregate's moduli; the plate protocol's
//! phases; implausible magnitudes. No MPI: `LoadedScene::load` as `run` and `check` call it.

use super::{LoadedScene, BUILTIN};
use std::path::PathBuf;

fn load(arg: &str, sets: &[&str]) -> Result<LoadedScene, String> {
    LoadedScene::load(arg, &sets.iter().map(|s| s.to_string()).collect::<Vec<_>>()).map_err(|e| e.to_string())
}

/// The resolved scene as a TOML table.
fn table(s: &LoadedScene) -> toml::Table {
    toml::from_str(&s.to_toml().unwrap()).unwrap()
}

fn v1(name: &str) -> String {
    let p: PathBuf =
        [env!("CARGO_MANIFEST_DIR"), "tests", "data", "scenes_v1", &format!("{name}.toml")].iter().collect();
    p.display().to_string()
}

#[test]
fn the_previous_versions_scenes_resolve_to_todays() {
    // The scenes shipped before the protocol tables; the TST scenes came with them, the creep
    // scene with force control, the indentation with the tools' drainage.
    let later = |n: &str| n.starts_with("tst_") || n == "creep_plates" || n == "indent_sphere";
    let before: Vec<&str> = BUILTIN.iter().map(|(n, _)| *n).filter(|n| !later(n)).collect();
    assert_eq!(before.len(), 12);
    for name in &before {
        let old = load(&v1(name), &[]).unwrap_or_else(|e| panic!("{name} as written before: {e}"));
        let new = load(name, &[]).unwrap();
        let (mut a, mut b) = (table(&old), table(&new));
        // Only the descriptions' words changed ("t_end = 40 s" named the release's end).
        a.remove("description");
        b.remove("description");
        if *name == "reference_axi" {
            // The one change the scenes made: reference_axi fades the stabilisation as reference does.
            assert!(a["fem"].get("stabilisation_fade").is_none());
            a["fem"]
                .as_table_mut()
                .unwrap()
                .insert("stabilisation_fade".into(), b["fem"]["stabilisation_fade"].clone());
        }
        assert_eq!(a, b, "{name}: the old file resolves to another scene");
        // Each moved key is named with what to write instead; today's scenes need no note.
        let plates = old.scene.plates.is_some();
        assert_eq!(old.notes.len(), usize::from(plates), "{name}: {:?}", old.notes);
        if plates {
            assert!(old.notes[0].starts_with("plates.t_ramp = 5 and plates.t_end = "), "{}", old.notes[0]);
            assert!(old.notes[0].contains("deprecated: write plates.ramp = 5, plates.hold = "), "{}", old.notes[0]);
        }
        assert!(new.notes.is_empty(), "{name}: {:?}", new.notes);
    }
}

#[test]
fn reference_axi_is_reference_on_the_meridian() {
    let (axi, quarter) = (table(&load("reference_axi", &[]).unwrap()), table(&load("reference", &[]).unwrap()));
    let physics = |mut t: toml::Table| {
        for k in ["name", "description", "mesh"] {
            t.remove(k);
        }
        // The conditions that act on the meridian (the quarter's symmetry rollers are 3-D only).
        let bc: Vec<toml::Value> = t["bc"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|b| b.get("geometry").and_then(|g| g.as_str()).is_none_or(|g| g == "axisymmetric"))
            .cloned()
            .collect();
        t.insert("bc".into(), bc.into());
        t
    };
    assert_eq!(physics(axi.clone()), physics(quarter.clone()));
    assert_eq!(axi["fem"]["stabilisation_fade"].as_float(), Some(0.03));
    assert_eq!(axi["mesh"]["geometry"].as_str(), Some("axisymmetric"));
}

#[test]
fn a_copy_with_only_the_radius_changed_scales() {
    for name in ["reference", "reference_axi", "remodel_40"] {
        let at = |r: f64| load(name, &[&format!("mesh.params.R={r}")]).unwrap().scene;
        let (s100, s150) = (at(100.0), at(150.0));
        for k in ["h", "h_pole", "r_pole"] {
            let (a, b) = (s100.mesh.params[k], s150.mesh.params[k]);
            assert!((b / a - 1.5).abs() < 1e-12, "{name}: {k} = {a} at R = 100, {b} at R = 150");
        }
        let p = s150.plates.as_ref().unwrap();
        assert_eq!(p.radius(), 150.0);
        assert_eq!(p.seal_gap, Some(1.5));
        assert_eq!(p.probe_point, Some([60.0, 0.0, 285.0]));
    }
    // A size in µm wins over the relative one (scripts set them so), and a radius given stays.
    let s = load("reference", &["mesh.params.h=10", "mesh.params.R=150"]).unwrap().scene;
    assert_eq!((s.mesh.params["h"], s.mesh.params["h_pole"]), (10.0, 4.5));
    let s = load(&v1("reference"), &["mesh.params.R=150", "plates.radius=150"]).unwrap().scene;
    assert_eq!(s.plates.unwrap().radius(), 150.0);
    let e = load("reference", &["mesh.relative_sizes.h=1.5"]).unwrap_err();
    assert!(e.ends_with("mesh.relative_sizes.h = 1.5: must lie in (0, 1] (a fraction of R)"), "{e}");
    let e = load("reference", &["mesh.params={ h = 20.0 }"]).unwrap_err();
    assert!(e.contains("mesh.relative_sizes are relative to the aggregate's radius: give mesh.params.R"), "{e}");
}

#[test]
fn implausible_magnitudes_name_the_unit_mistake() {
    let e = load("reference_axi", &["mesh.params.R=0.15"]).unwrap_err();
    assert!(
        e.ends_with(
            "mesh.params.R = 0.15: must lie in [1, 10000] µm: 0.15 looks like mm (0.15 mm = 150 µm); lengths are µm"
        ),
        "{e}"
    );
    let e = load("reference_axi", &["mesh.params.R=150000"]).unwrap_err();
    assert!(e.contains("150000 looks like nm (150000 nm = 150 µm)"), "{e}");
    // Sizes in µm against a radius in mm: the mesh would be a few cells.
    let e = load(&v1("reference_axi"), &["mesh.params.R=1.5", "plates.radius=1.5"]).unwrap_err();
    assert!(e.contains("mesh.params.h = 15 is larger than the radius R = 1.5"), "{e}");
    let e = load(&v1("reference_axi"), &["plates.radius=0.1"]).unwrap_err();
    assert!(e.contains("plates.radius = 0.1: must lie in [1, 10000] µm: 0.1 looks like mm"), "{e}");
}

/// µ and ν of the solid of scene `arg` (with overrides).
fn solid_of(arg: &str, sets: &[&str]) -> Result<(f64, f64), String> {
    match load(arg, sets)?.scene.material.mixture() {
        Some(m) => match m.solid()? {
            super::SolidSpec::MuNu { mu, nu } => Ok((mu, nu)),
            super::SolidSpec::Alpha(_) => Err("alpha".into()),
        },
        None => Err("linear".into()),
    }
}

#[test]
fn the_aggregates_moduli_give_the_solids() {
    assert_eq!(solid_of("reference_axi", &[]).unwrap(), (20.0, 0.2));
    // Φs = 0.6: G = Φs µ = 12 kPa and E = 2 G (1 + ν) = 28.8 kPa are the shipped solid's µ = 20 kPa.
    for (i, (key, value)) in [("drained_shear_modulus", "12.0"), ("drained_youngs_modulus", "28.8")].iter().enumerate()
    {
        let text = BUILTIN.iter().find(|(n, _)| *n == "reference_axi").unwrap().1;
        let p = std::env::temp_dir().join(format!("poroplast-moduli-{}-{i}.toml", std::process::id()));
        std::fs::write(&p, text.replacen("mu = 20.0 ", &format!("{key} = {value} "), 1)).unwrap();
        let f = p.display().to_string();
        let (mu, nu) = solid_of(&f, &[]).unwrap();
        assert!((mu - 20.0).abs() < 1e-12 && nu == 0.2, "{key}: µ = {mu}");
        // An override of another modulus replaces the file's; a file with two is refused.
        assert_eq!(solid_of(&f, &["material.mu=20"]).unwrap(), (20.0, 0.2));
        let both = std::env::temp_dir().join(format!("poroplast-moduli-both-{}-{i}.toml", std::process::id()));
        std::fs::write(&both, text.replacen("mu = 20.0 ", &format!("mu = 20.0\n{key} = {value} "), 1)).unwrap();
        let e = load(&both.display().to_string(), &[]).unwrap_err();
        assert!(e.contains("give `nu` and one modulus — `mu` (the solid's)"), "{e}");
        let e = load(&f, &[&format!("material.{key}=-1")]).unwrap_err();
        assert!(e.ends_with(&format!("material.{key} = -1: must be positive")), "{e}");
    }
}

#[test]
fn the_plate_protocol_names_its_phases() {
    let phases = |s: &LoadedScene| s.scene.plates.as_ref().unwrap().protocol().ends();
    let s = load("reference", &[]).unwrap();
    assert_eq!(phases(&s), [5.0, 35.0, 40.0]);
    let s = load("reference", &["plates.release=10", "plates.hold=60"]).unwrap();
    assert_eq!(phases(&s), [5.0, 65.0, 75.0]);
    assert!(s.notes.is_empty());
    // The old keys as overrides of today's scenes (studies set them): t_end moves the release.
    let s = load("reference", &["plates.t_end=155", "time.t_end=200"]).unwrap();
    assert_eq!(phases(&s), [5.0, 150.0, 155.0]);
    assert_eq!(
        s.notes,
        ["plates.t_end = 155 is deprecated: write plates.ramp = 5, plates.hold = 145, plates.release = 5 (the \
          durations of the protocol's phases, s)"]
    );
    let s = load("reference", &["plates.t_ramp=10"]).unwrap();
    assert_eq!(phases(&s), [10.0, 30.0, 40.0]);
    // A release after the run's end is allowed (short test runs), with a note.
    let s = load("reference", &["time.t_end=20"]).unwrap();
    assert_eq!(
        s.notes,
        ["the plates' release ends at 40 s (ramp 5 + hold 30 + release 5), after the run's end time.t_end = 20 s: \
          the run stops during the hold"]
    );
    let e = load("reference", &["plates.hold=-1"]).unwrap_err();
    assert!(e.ends_with("plates.hold = -1: must be >= 0"), "{e}");
    let e = load("reference", &["plates.release=0"]).unwrap_err();
    assert!(e.ends_with("plates.release = 0: must be positive"), "{e}");
    let p = std::env::temp_dir().join(format!("poroplast-phases-{}.toml", std::process::id()));
    let text = BUILTIN.iter().find(|(n, _)| *n == "reference_axi").unwrap().1.replace("hold = 30.0", "");
    std::fs::write(&p, text).unwrap();
    let e = load(&p.display().to_string(), &[]).unwrap_err();
    assert!(
        e.ends_with("[plates]: give the protocol's phases ramp, hold and release (s); plates.hold is missing"),
        "{e}"
    );
}

#[test]
fn the_resolved_scene_has_every_default() {
    let t = table(&load("reference_axi", &[]).unwrap());
    assert_eq!(t["fem"]["stabilisation"].as_float(), Some(crate::scene::numerics::DEFAULT_STABILISATION));
    assert_eq!(t["fem"]["quadrature_degree"].as_integer(), Some(3));
    assert_eq!(t["fem"]["element"].as_str(), Some("P2-P1"));
    assert_eq!(t["solver"]["preset"].as_str(), Some("auto"));
    assert_eq!(t["plates"]["radius"].as_float(), Some(100.0));
    assert_eq!(t["plates"]["seal_gap"].as_float(), Some(1.0));
    let t = table(&load("terzaghi", &[]).unwrap());
    assert_eq!(t["fem"]["quadrature_degree"].as_integer(), Some(2), "the linear model's");
    // The resolved scene loads again as itself.
    let s = load("reference", &[]).unwrap();
    let p = std::env::temp_dir().join(format!("poroplast-resolved-{}.toml", std::process::id()));
    std::fs::write(&p, s.to_toml().unwrap()).unwrap();
    let again = load(&p.display().to_string(), &[]).unwrap();
    assert_eq!(table(&again), table(&s));
}
