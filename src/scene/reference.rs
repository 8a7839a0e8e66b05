//! The scene reference: every section's key table (declared in the section files) as Markdown,
//! the text of `docs/scene-reference.md` and of `poroplast scenes --keys`.

use super::key::{Key, Section, Unset};
use super::{bc, material, mesh, numerics, observe, plates, time};

/// Every section, in the order of a scene file.
pub fn sections() -> Vec<Section> {
    vec![
        SECTION,
        mesh::SECTION,
        material::LINEAR_SECTION,
        material::HOLMES_MOW_SECTION,
        material::PENALTY_SECTION,
        material::REMODELLING_SECTION,
        bc::SECTION,
        time::TIME_SECTION,
        time::OUTPUT_SECTION,
        time::INITIAL_SECTION,
        observe::PROBE_SECTION,
        observe::VERIFICATION_SECTION,
        plates::SECTION,
        numerics::SOLVER_SECTION,
        numerics::FEM_SECTION,
        PETSC_SECTION,
        Section { title: "Units", about: UNITS, keys: &[] },
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
         docs/user-guide.md shows the keys in use.\n",
    );
    for s in sections() {
        out.push_str(&format!("\n## {}\n\n{}\n", s.title, s.about));
        if s.keys.is_empty() {
            continue;
        }
        out.push_str("\n| key | unit | default | valid | description |\n|---|---|---|---|---|\n");
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
                "| `{}` | {} | {} | {} | {} |\n",
                k.name,
                cell(k.unit),
                cell(&default),
                cell(&valid),
                cell(k.doc)
            ));
        }
    }
    out
}

/// The keys outside the sections.
const SECTION: Section = Section {
    title: "Top level",
    about: "A scene has the sections below; `[mesh]`, `[material]` and `[time]` are required.",
    keys: &[
        Key::new("name", "", Unset::Absent("the file stem"), "short name; names the run directory"),
        Key::new("description", "", Unset::Value("\"\""), "one line on what the scene is"),
    ],
};

const PETSC_SECTION: Section = Section {
    title: "[petsc]",
    about: "Any PETSc option without the leading dash: `ksp_rtol = 1e-10`, `ksp_monitor = true` (false: left \
            out). Options given on the command line after `--` come after these.",
    keys: &[Key::new("petsc.<option>", "", Unset::Absent(""), "a PETSc option and its value")
        .rule("a string, number or boolean")],
};
