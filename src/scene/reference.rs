//! The scene reference: every section's key table (declared in the section files) as Markdown,
//! the text of `docs/scene-reference.md` and of `poroplast scenes --keys`.

use super::bc;
use super::drainage;
use super::key::{Key, Section, Unset};
use super::material;
use super::medium;
use super::mesh;
use super::numerics;
use super::observe;
use super::plates;
use super::surface;
use super::time;
use super::tools;

/// Every section, in the order of a scene file.
pub(crate) fn sections() -> Vec<Section> {
    vec![
        SECTION,
        mesh::SECTION,
        material::LINEAR_SECTION,
        material::HOLMES_MOW_SECTION,
        material::NEO_HOOKEAN_SECTION,
        material::PENALTY_SECTION,
        material::REMODELLING_SECTION,
        bc::SECTION,
        time::TIME_SECTION,
        time::OUTPUT_SECTION,
        time::INITIAL_SECTION,
        observe::PROBE_SECTION,
        observe::VERIFICATION_SECTION,
        plates::SECTION,
        tools::SECTION,
        surface::SECTION,
        medium::SECTION,
        drainage::SECTION,
        numerics::SOLVER_SECTION,
        numerics::FEM_SECTION,
        PETSC_SECTION,
        Section { title: "Units", enters: "model.md", about: UNITS, keys: &[] },
    ]
}

const UNITS: &str = "Lengths in µm, stresses and pressures in kPa, times in s, so forces are in nN and \
                     conductivities in µm⁴/(nN s) (1 mm⁴/(N s) = 1000).";

/// The scene reference as Markdown: one table per section.
pub fn reference() -> String {
    let mut out = String::from(
        "# Scene reference\n\n\
         Every key of a scene file, generated from the declarations in `src/scene/` (`poroplast scenes \
         --keys` prints the same text; a test keeps this file equal to it). A scene is TOML; unknown \
         keys are errors. A range is an interval the value must lie in; values are also finite. \
         docs/reference-scene-files.md shows the keys in use.\n",
    );
    for s in sections() {
        out.push_str(&format!("\n## {}\n\n{}\n", s.title, s.about));
        if s.keys.is_empty() {
            continue;
        }
        if !s.enters.is_empty() {
            out.push_str(&format!("\nThe keys enter docs/{} (the column \"enters\": more precisely).\n", s.enters));
        }
        out.push_str("\n| key | unit | default | valid | description | enters |\n|---|---|---|---|---|---|\n");
        for k in s.keys {
            let default = match k.default {
                Unset::Required => "required".to_string(),
                Unset::Absent("") => "—".to_string(),
                Unset::Absent(words) => words.to_string(),
                Unset::Value(v) => format!("`{v}`"),
            };
            let valid = match (k.range, k.rule) {
                (Some(r), "") => r.to_string(),
                (Some(r), rule) => format!("{r}; {rule}"),
                (None, rule) => rule.to_string(),
            };
            let cell = |s: &str| s.replace('|', "\\|");
            out.push_str(&format!(
                "| `{}` | {} | {} | {} | {} | {} |\n",
                k.name,
                cell(k.unit),
                cell(&default),
                cell(&valid),
                cell(k.doc),
                cell(k.enters)
            ));
        }
    }
    out
}

/// The keys outside the sections.
const SECTION: Section = Section {
    title: "Top level",
    enters: "",
    about: "A scene has the sections below; `[mesh]`, `[material]` and `[time]` are required.",
    keys: &[
        Key::new("name", "", Unset::Absent("the file stem"), "short name; names the run directory"),
        Key::new("description", "", Unset::Value("\"\""), "one line on what the scene is"),
    ],
};

const PETSC_SECTION: Section = Section {
    title: "[petsc]",
    enters: "reference-options.md: PETSc options worth knowing",
    about: "Any PETSc option without the leading dash: `ksp_rtol = 1e-10`, `ksp_monitor = true` (false: left \
            out). Options given on the command line after `--` come after these.",
    keys: &[Key::new("petsc.<option>", "", Unset::Absent(""), "a PETSc option and its value")
        .rule("a string, number or boolean")],
};

#[cfg(test)]
mod tests {
    use super::super::{LoadedScene, Material, Scene};
    use super::*;
    use std::collections::BTreeSet;

    /// Every declared key name.
    fn declared() -> BTreeSet<&'static str> {
        sections().iter().flat_map(|s| s.keys.iter().map(|k| k.name)).collect()
    }

    /// The fields serde knows in the table at `path` of builtin `scene`, from its message for an
    /// unknown key there ("expected one of `a`, `b`").
    fn serde_fields(scene: &str, path: &str) -> Vec<String> {
        let set = if path.is_empty() { "zz_unknown=1".to_string() } else { format!("{path}.zz_unknown=1") };
        let e = LoadedScene::load(scene, &[set]).err().map(|e| e.to_string()).unwrap_or_default();
        let expected = e.split_once("expected").map(|(_, rest)| rest).unwrap_or_else(|| panic!("{scene} {path}: {e}"));
        expected.split('`').skip(1).step_by(2).map(|s| s.to_string()).collect()
    }

    #[test]
    fn every_serde_field_is_declared() {
        let keys = declared();
        // (builtin scene, the table's path in the scene, its keys' prefix in the reference)
        for (scene, path, prefix) in [
            ("reference", "", ""),
            ("reference", "mesh", "mesh."),
            ("terzaghi", "material", "material."),
            ("reference", "material", "material."),
            ("reference", "material.penalty", "material.penalty."),
            ("remodel_40", "material.remodelling", "material.remodelling."),
            ("terzaghi", "bc.0", "bc."),
            ("terzaghi", "time", "time."),
            ("reference", "output", "output."),
            ("cryer", "probe.0", "probe."),
            ("terzaghi", "verification", "verification."),
            ("cryer", "verification", "verification."),
            ("reference", "plates", "plates."),
            ("reference", "solver", "solver."),
            ("reference", "fem", "fem."),
        ] {
            let fields = serde_fields(scene, path);
            assert!(!fields.is_empty(), "{scene} {path}: {e:?}", e = fields);
            for f in fields {
                // a key, or a table whose keys are declared
                let name = format!("{prefix}{f}");
                let table = format!("{name}.");
                assert!(
                    keys.contains(name.as_str()) || keys.iter().any(|k| k.starts_with(&table)),
                    "{name} (in {scene}'s [{path}]) has no declaration"
                );
            }
        }
        // Tables the shipped scenes do not have, and the tags of the tagged tables.
        let traction = serde_fields("terzaghi", "bc.0");
        assert!(traction.contains(&"traction".to_string()));
        for name in ["bc.traction.normal", "bc.traction.vector", "initial.displacement_gradient", "material.model"] {
            assert!(keys.contains(name), "{name}");
        }
        let initial = toml::from_str::<super::super::time::InitialSpec>("zz_unknown = 1").unwrap_err().to_string();
        assert!(initial.contains("`displacement_gradient`"), "{initial}");
    }

    #[test]
    fn the_declared_defaults_are_serdes() {
        // The smallest scene of each model: every key with a default takes it.
        let scene = |material: &str| -> toml::Table {
            let text = format!(
                "[mesh]\ngeo = \"g\"\n[material]\n{material}\n[time]\nt_end = 1.0\ndt = 0.1\n\
                 [plates]\nradius = 1.0\ncompression = 0.1\nt_ramp = 1.0\nt_end = 2.0\n\
                 [[probe]]\nname = \"p\"\nfield = \"p\"\ngroup = \"g\"\n\
                 [[bc]]\ngroup = \"g\"\nroller = true\n[surface]\ntension = 1.0\n[medium]\n\
                 [[tools]]\nname = \"t\"\nkind = \"plane\"\norigin = [0.0, 0.0, 0.0]\naxis = [0.0, 0.0, 1.0]\n\
                 [drainage]\nseal_gap = 1.0\n"
            );
            let scene: Scene = toml::from_str(&text).unwrap();
            toml::Table::try_from(&scene).unwrap()
        };
        let holmes_mow = "model = \"holmes_mow\"\nmu = 1.0\nnu = 0.2\nphi_s = 0.5\nk0 = 1.0\nkappa = 1.0\nm0 = 0.0\n\
                          remodelling = { lambda_p = 1.0, sigma_y = 1.0 }";
        let tables = [scene(holmes_mow), scene("model = \"linear\"\nmu = 1.0\nnu = 0.2\npermeability = 1.0")];
        assert!(matches!(
            toml::from_str::<Scene>(&toml::to_string(&tables[0]).unwrap()).unwrap().material,
            Material::HolmesMow(_)
        ));
        let lookup = |t: &toml::Table, name: &str| -> Option<toml::Value> {
            let mut here = toml::Value::Table(t.clone());
            for part in name.split('.') {
                here = match here {
                    toml::Value::Array(a) => a.first()?.get(part)?.clone(),
                    v => v.get(part)?.clone(),
                };
            }
            Some(here)
        };
        let as_number = |v: &toml::Value| v.as_float().or(v.as_integer().map(|i| i as f64));
        let mut checked = 0;
        for s in sections() {
            for k in s.keys {
                let Unset::Value(text) = k.default else { continue };
                let want: toml::Value = toml::from_str::<toml::Table>(&format!("v = {text}")).unwrap()["v"].clone();
                // The key's section is in one of the two scenes (the model's keys in one only).
                let got = tables.iter().filter_map(|t| lookup(t, k.name)).next();
                let got = got.unwrap_or_else(|| panic!("{}: no default in the serialised scene", k.name));
                let same = match (as_number(&want), as_number(&got)) {
                    (Some(a), Some(b)) => a == b,
                    _ => want == got,
                };
                assert!(same, "{}: declared default {text}, serde's {got}", k.name);
                checked += 1;
            }
        }
        assert!(checked >= 20, "{checked} defaults checked");
        // A key declared absent by default is not in the serialised scene.
        for name in ["time.dt_max", "plates.seal_gap", "fem.element", "material.permeability_c"] {
            assert!(tables.iter().all(|t| lookup(t, name).is_none()), "{name}");
        }
    }

    #[test]
    fn docs_scene_reference_is_the_generated_one() {
        let committed = include_str!("../../docs/scene-reference.md");
        if committed != reference() {
            let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/scene-reference.md");
            if std::env::var_os("POROPLAST_WRITE_REFERENCE").is_some() {
                std::fs::write(path, reference()).unwrap();
            }
            panic!(
                "docs/scene-reference.md differs from the key declarations: regenerate it with \
                 `poroplast scenes --keys > docs/scene-reference.md` (or run this test with \
                 POROPLAST_WRITE_REFERENCE=1)"
            );
        }
    }
}
