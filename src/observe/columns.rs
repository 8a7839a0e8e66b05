//! The `history.csv` column reference: every column a run can write, in the order a run writes
//! them, with its unit and meaning, read from the columns' declarations (the step's own in
//! `io::recorder`, the observers' here) — the table of docs/reference-run-directory.md, which
//! `poroplast columns --table` prints and a test keeps equal.

use super::{aspiration, experiment, force_control, probe, remodelling_summary, tools, verification};
use crate::io::recorder::{ColumnDoc, ITERATIONS, STEP};

/// Every column a run can write, in order: the step's, the experiment's (with its Laplace
/// analysis), the upper plate's under force control, the tools' (patterns), the medium's, the remodelling summary's, the probes' (a pattern), the exact solutions', and the
/// step's iterations and wall time. A scene's run writes those that apply, in this order.
pub(crate) fn reference() -> Vec<ColumnDoc> {
    let mut docs: Vec<ColumnDoc> = STEP.iter().map(|c| c.doc).collect();
    docs.extend(experiment::columns().map(|(doc, _)| *doc));
    docs.extend(force_control::COLUMNS.iter().map(|c| c.doc));
    docs.extend(tools::COLUMNS);
    docs.extend(aspiration::LENGTH.iter().map(|c| c.doc).chain(aspiration::DRAG.iter().map(|c| c.doc)));
    docs.extend(remodelling_summary::COLUMNS.iter().map(|c| c.doc));
    docs.push(probe::COLUMN);
    docs.extend(verification::COLUMNS.iter().map(|&d| *d));
    docs.extend(ITERATIONS.iter().map(|c| c.doc));
    docs
}

/// [`reference`] as a Markdown table (column, unit, meaning): the text of the `history.csv`
/// table of docs/reference-run-directory.md.
pub fn reference_table() -> String {
    let mut out = String::from("| column | unit | meaning |\n|---|---|---|\n");
    for d in reference() {
        let name = if d.pattern { d.name.to_string() } else { format!("`{}`", d.name) };
        out.push_str(&format!("| {name} | {} | {} |\n", d.unit, d.meaning.replace('|', "\\|")));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observe::observers::history_column_names;
    use crate::scene::{LoadedScene, BUILTIN};

    /// The first Markdown table after the heading `## \`history.csv\` columns` of `page`, and
    /// its byte range.
    fn history_table(page: &str) -> (String, std::ops::Range<usize>) {
        let section = page.find("## `history.csv` columns").expect("the history.csv section");
        let start = section + page[section..].find("\n|").expect("a table in the history.csv section") + 1;
        let len = page[start..].find("\n\n").unwrap_or(page.len() - start) + 1;
        (page[start..start + len].to_string(), start..start + len)
    }

    #[test]
    fn docs_history_table_is_the_declared_one() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/reference-run-directory.md");
        let page = std::fs::read_to_string(path).unwrap();
        let (committed, range) = history_table(&page);
        let declared = reference_table();
        if committed != declared {
            if std::env::var_os("POROPLAST_WRITE_REFERENCE").is_some() {
                let mut page = page.clone();
                page.replace_range(range, &declared);
                std::fs::write(path, page).unwrap();
            }
            let first = committed.lines().zip(declared.lines()).find(|(a, b)| a != b);
            panic!(
                "docs/reference-run-directory.md's history.csv table differs from the column declarations \
                 (first differing row: {first:?}): paste `poroplast columns --table` over it (or run this test \
                 with POROPLAST_WRITE_REFERENCE=1)"
            );
        }
    }

    /// The table's reader finds the rows of the page, and an altered meaning is a difference.
    #[test]
    fn a_changed_row_is_a_difference() {
        let page = format!("# x\n\n## `history.csv` columns\n\nIn order:\n\n{}\nAfter.\n", reference_table());
        assert_eq!(history_table(&page).0, reference_table());
        let altered = page.replace("the step's size", "the step's length");
        assert_ne!(history_table(&altered).0, reference_table());
    }

    /// Every column of every shipped scene's `history.csv`, with a probe added (so that the
    /// probes meet each other observer), is in the reference, in its order (a probe's under the
    /// probes' pattern): a column written but not declared there, or written elsewhere in the
    /// row, fails.
    #[test]
    fn every_shipped_scene_writes_referenced_columns_in_order() {
        let docs = reference();
        let dir = std::env::temp_dir().join(format!("poroplast-columns-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, text) in BUILTIN {
            let path = dir.join(format!("{name}.toml"));
            let probe = "\n[[probe]]\nname = \"added\"\nfield = \"p\"\npoint = [0.0, 0.0, 1.0]\n";
            std::fs::write(&path, format!("{text}{probe}")).unwrap();
            let scene = LoadedScene::load(path.to_str().unwrap(), &[]).unwrap();
            let mut at = 0;
            for col in history_column_names(&scene).unwrap() {
                // A tool's columns, one block per tool, are the tools' patterns (in any order).
                let tool = scene.scene.tools.iter().find(|t| col.starts_with(&format!("{}_", t.name)));
                if let Some(t) = tool {
                    let generic = col.replacen(&t.name, "*tool*", 1);
                    assert!(docs.iter().any(|d| d.pattern && d.name == generic), "{name}: column {col} ({generic})");
                    continue;
                }
                let is_probe = scene.scene.probe.iter().any(|p| p.name == col);
                let found =
                    docs[at..].iter().position(|d| if is_probe { d.pattern } else { !d.pattern && d.name == col });
                let found = found
                    .unwrap_or_else(|| panic!("{name}: column {col} is not in the reference (or not in its order)"));
                at += found;
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
