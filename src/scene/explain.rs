//! A scene explained: the resolved scene as TOML (every default written out) with each key's
//! meaning, unit, default and valid range from its declaration (`super::key`) as a comment
//! above it, and the keys left unset listed with what that means — `poroplast show --explain`
//! and the run directory's `scene.toml`. Values are written on their key's line, except a table
//! of numbers (`plates.table`), which is written a row a line with its columns aligned.

use super::key::{Key, Unset};
use super::reference::sections;
use super::LoadedScene;
use crate::error::Result;

/// The resolved scene of `loaded`, each key with its declaration as a comment.
pub fn explain(loaded: &LoadedScene) -> Result<String> {
    let keys = declared(loaded);
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
        match rows(line) {
            Some(table) => out.push_str(&table),
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    if let Some(names) = seen {
        out.push_str(&unset(&keys, &table, &names));
    }
    Ok(out)
}

/// The keys a scene can have: its material model's own (`material.mu` is the drained modulus
/// of the linear model) and every other section's.
fn declared(loaded: &LoadedScene) -> Vec<Key> {
    let model = format!("model = \"{}\"", loaded.scene.material.model().0);
    sections()
        .iter()
        .filter(|s| !s.title.contains("model = ") || s.title.contains(&model))
        .flat_map(|s| s.keys.iter().copied())
        .collect()
}

/// `key = [[a, b], [c, d], ...]`, an array of rows of numbers, as a table: a row a line, each
/// column right-aligned; None for any other line.
fn rows(line: &str) -> Option<String> {
    let (key, _) = line.split_once(" = ")?;
    let parsed: toml::Table = toml::from_str(line).ok()?;
    let cells: Vec<Vec<String>> = parsed
        .get(key)?
        .as_array()?
        .iter()
        .map(|row| {
            let row = row.as_array().filter(|r| !r.is_empty() && r.iter().all(|v| v.is_float() || v.is_integer()))?;
            Some(row.iter().map(|v| v.to_string()).collect())
        })
        .collect::<Option<_>>()?;
    if cells.is_empty() {
        return None;
    }
    let columns = cells.iter().map(Vec::len).max().unwrap_or(0);
    let width: Vec<usize> =
        (0..columns).map(|c| cells.iter().filter_map(|r| r.get(c)).map(|v| v.len()).max().unwrap_or(0)).collect();
    let mut out = format!("{key} = [\n");
    for row in &cells {
        let padded: Vec<String> = row.iter().zip(&width).map(|(v, &w)| format!("{v:>w$}")).collect();
        out.push_str(&format!("    [{}],\n", padded.join(", ")));
    }
    out.push_str("]\n");
    Some(out)
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
    use super::{comment, declaration, declared, explain};

    fn parsed(text: &str) -> toml::Table {
        toml::from_str(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
    }

    /// The model name `declared` selects the key sections by is the scene's own `model = ".."`
    /// (what serde writes), for each model.
    #[test]
    fn the_model_name_is_the_scenes() {
        for scene in ["cryer", "reference"] {
            let material = &LoadedScene::load(scene, &[]).unwrap().scene.material;
            let written = toml::Table::try_from(material).unwrap();
            assert_eq!(written["model"].as_str(), Some(material.model().0), "{scene}");
        }
    }

    /// `tst_two_compressions`' table is printed a row a line, aligned, with nothing between its
    /// rows; every key has its own declaration's comment right above it; the text parses back to
    /// the same table and loads as the same scene.
    #[test]
    fn a_table_is_printed_as_rows_and_each_comment_is_above_its_key() {
        let s = LoadedScene::load("tst_two_compressions", &[]).unwrap();
        let text = explain(&s).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let at = lines.iter().position(|l| *l == "table = [").unwrap_or_else(|| panic!("no table in\n{text}"));
        let rows: Vec<&str> = lines[at + 1..].iter().take_while(|l| l.starts_with("    [")).copied().collect();
        assert_eq!(
            rows,
            [
                "    [   0.0,  0.0],",
                "    [   5.0, 0.15],",
                "    [1005.0, 0.15],",
                "    [1010.0,  0.0],",
                "    [1300.0,  0.0],",
                "    [1305.0,  0.3],",
                "    [2305.0,  0.3],",
                "    [2310.0,  0.0],",
            ]
        );
        assert_eq!(lines[at + 1 + rows.len()], "]");
        let table = parsed(&lines[at..at + rows.len() + 2].join("\n"));
        let want = s.scene.plates.as_ref().unwrap().table.clone().unwrap();
        let got: Vec<[f64; 2]> = table["table"].clone().try_into().unwrap();
        assert_eq!(got, want);
        // Each key line's comment is its own declaration's, on the line above.
        let keys = declared(&s);
        let mut section = String::new();
        let mut checked = 0;
        for (i, l) in lines.iter().enumerate() {
            if let Some(h) = l.strip_prefix('[') {
                section = h.trim_matches(['[', ']']).to_string();
            } else if let Some((key, _)) = l.split_once(" = ").filter(|_| !l.starts_with(['#', ' '])) {
                let name = if section.is_empty() { key.to_string() } else { format!("{section}.{key}") };
                if let Some(k) = declaration(&keys, &name) {
                    assert_eq!(format!("{}\n", lines[i - 1]), comment(k), "above `{l}` ({name})");
                    checked += 1;
                }
            }
        }
        assert!(checked > 40, "{checked} keys checked in\n{text}");
        // Loaded again, the printed scene is the same scene.
        let dir = std::env::temp_dir().join(format!("poroplast-explain-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("explained.toml");
        std::fs::write(&path, &text).unwrap();
        let again = LoadedScene::load(path.to_str().unwrap(), &[]).unwrap();
        assert_eq!(parsed(&again.to_toml().unwrap()), parsed(&s.to_toml().unwrap()));
        std::fs::remove_dir_all(&dir).unwrap();
    }

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
