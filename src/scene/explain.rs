//! A scene explained: the resolved scene as TOML (every default written out) with each key's
//! meaning, unit, default and valid range from its declaration ([`super::key`]) as a comment
//! above it, and the keys left unset listed with what that means — `poroplast show --explain`
//! and the run directory's `scene.toml`.

use super::key::{Key, Unset};
use super::reference::sections;
use super::{LoadedScene, Material};
use crate::error::Result;

/// The resolved scene of `loaded`, each key with its declaration as a comment.
pub fn explain(loaded: &LoadedScene) -> Result<String> {
    // The material model's own keys (`material.mu` is the drained modulus of the linear model).
    let model = match loaded.scene.material {
        Material::Linear { .. } => "model = \"linear\"",
        Material::HolmesMow(_) => "model = \"holmes_mow\"",
    };
    let keys: Vec<Key> = sections()
        .iter()
        .filter(|s| !s.title.contains("model = ") || s.title.contains(model))
        .flat_map(|s| s.keys.iter().copied())
        .collect();
    let mut out = String::new();
    let mut table = String::new();
    // The keys of the current table written so far (None: its unset keys are listed).
    let mut seen = Some(Vec::new());
    for line in loaded.to_toml()?.lines() {
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('[') {
            if let Some(names) = seen.take() {
                out.push_str(&unset(&keys, &table, &names));
            }
        }
        if let Some(header) = trimmed.strip_prefix('[') {
            table = header.trim_matches(['[', ']']).to_string();
            seen = Some(Vec::new());
        } else if let Some((key, _)) = trimmed.split_once(" = ").filter(|_| !line.starts_with(' ')) {
            let name = if table.is_empty() { key.to_string() } else { format!("{table}.{key}") };
            seen.get_or_insert_with(Vec::new).push(name.clone());
            if let Some(k) = declaration(&keys, &name) {
                out.push_str(&comment(k));
            } else if keys.iter().any(|k| k.name.starts_with(&format!("{name}."))) {
                // An empty list of tables (`bc = []`): none given.
                out.push_str(&format!("# [[{name}]] entries: none (docs/scene-reference.md lists their keys)\n"));
            }
        }
        out.push_str(line);
        out.push('\n');
    }
    if let Some(names) = seen {
        out.push_str(&unset(&keys, &table, &names));
    }
    Ok(out)
}

/// The declared keys of `table` the scene leaves unset (not in `written`), as comments: what
/// leaving them out means. Not for lists of tables (`[[bc]]`), the `.geo`'s parameters, or the
/// deprecated keys.
fn unset(keys: &[Key], table: &str, written: &[String]) -> String {
    if ["bc", "probe", "mesh.params", "petsc"].contains(&table) {
        return String::new();
    }
    let prefix = if table.is_empty() { String::new() } else { format!("{table}.") };
    keys.iter()
        .filter(|k| {
            k.name.strip_prefix(&prefix).is_some_and(|rest| !rest.contains('.'))
                && !written.iter().any(|w| w == k.name)
                && !k.doc.starts_with("deprecated")
        })
        .map(|k| format!("# ({} is not set){}", k.name.rsplit('.').next().unwrap_or(k.name), &comment(k)[1..]))
        .collect()
}

/// The key `name` is declared as: itself, or the table it belongs to (`mesh.params.W`,
/// `petsc.ksp_rtol`).
fn declaration<'k>(keys: &'k [Key], name: &str) -> Option<&'k Key> {
    let found = |n: &str| keys.iter().find(|k| k.name == n);
    found(name).or_else(|| {
        let (table, _) = name.rsplit_once('.')?;
        found(table).or_else(|| found(&format!("{table}.<option>")))
    })
}

/// "# meaning [unit; default ...; valid ...]".
fn comment(k: &Key) -> String {
    let mut facts = Vec::new();
    if !k.unit.is_empty() {
        facts.push(k.unit.to_string());
    }
    match k.default {
        Unset::Required => facts.push("required".into()),
        Unset::Value(v) => facts.push(format!("default {v}")),
        Unset::Absent("") => {}
        Unset::Absent(words) => facts.push(format!("default: {words}")),
    }
    match (k.range, k.rule) {
        (Some(r), "") => facts.push(format!("valid {r}")),
        (Some(r), rule) => facts.push(format!("valid {r}; {rule}")),
        (None, "") => {}
        (None, rule) => facts.push(rule.to_string()),
    }
    let facts = if facts.is_empty() { String::new() } else { format!(" [{}]", facts.join("; ")) };
    format!("# {}{facts}\n", k.doc)
}

#[cfg(test)]
mod tests {
    use super::super::LoadedScene;
    use super::explain;

    #[test]
    fn every_key_line_is_explained_and_the_text_is_the_scene() {
        let s = LoadedScene::load("reference_axi", &[]).unwrap();
        let text = explain(&s).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let above = |key_line: &str| {
            let i = lines.iter().position(|l| *l == key_line).unwrap_or_else(|| panic!("no `{key_line}` in\n{text}"));
            lines[i - 1]
        };
        assert_eq!(
            above("R = 100.0"),
            "# the aggregate's radius (sphere `.geo` files); plates.radius follows it [µm; valid [1, 10000]]"
        );
        assert!(above("u0 = 1000.0").starts_with("# its modulus U0 [kPa; required"), "{}", above("u0 = 1000.0"));
        assert!(
            above("stabilisation = 4.0").contains("[default: 4; valid [0, ∞)]"),
            "{}",
            above("stabilisation = 4.0")
        );
        assert!(above("mu = 20.0").starts_with("# the solid's shear modulus µ"), "{}", above("mu = 20.0"));
        // The keys left unset say what that means.
        assert!(text.contains("\n# (dt_min is not set) a step cut below this by failed solves ends the run with an error [s; default: 1e-6 dt;"), "{text}");
        assert!(text.contains("# (remodelling is not set) the visco-plastic remodelling of B_p: a table, below [default: none: B_p = I]"), "{text}");
        let hold = above("hold = 30.0");
        assert!(
            hold.starts_with("# duration of the hold at u_max [s;") && hold.contains("required unless plates.table"),
            "{hold}"
        );
        // Every `key = value` line has its comment, and the comments change nothing.
        for (i, l) in lines.iter().enumerate().skip(1) {
            if l.contains(" = ") && !l.starts_with(['#', ' ']) {
                assert!(lines[i - 1].starts_with("# "), "`{l}` has no comment");
            }
        }
        let a: toml::Table = toml::from_str(&text).unwrap();
        let b: toml::Table = toml::from_str(&s.to_toml().unwrap()).unwrap();
        assert_eq!(a, b);
    }
}
