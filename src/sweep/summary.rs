//! The sweep's `summary.csv`: one row per case in case order — its overrides, status, wall
//! time, dofs, steps, step cuts, Newton and Krylov iterations (the counters of its record),
//! the observables of its history ([`crate::io::observable`]), the error line and the case's run
//! directory:
//!
//! `case, [scene,] KEYS..., status, wall_s, dofs, steps, step_cuts, newton_its, ksp_its,
//! OBSERVABLES..., error, dir`
//!
//! The observables are evaluated when the summary is written, not when a case ends, so that a
//! case another study ran (a shared store) has this study's; each history is read once per
//! session ([`Observations`]).

use super::counters::COUNTERS;
use super::store::CaseRecord;
use super::study::{Case, Study};
use crate::error::{Error, Result};
use crate::io::observable::{self, observe};
use crate::io::rundir;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The observables of the cases that ended ok, each history read once (a case's history does
/// not change once it has ended).
pub(crate) struct Observations {
    observe: Vec<String>,
    seen: RefCell<BTreeMap<PathBuf, Vec<f64>>>,
}

impl Observations {
    pub(crate) fn new(observe: &[String]) -> Observations {
        Observations { observe: observe.to_vec(), seen: RefCell::new(BTreeMap::new()) }
    }

    /// The observables of the case that ended ok in `dir` (NaN where one does not apply).
    fn of(&self, dir: &Path) -> Vec<f64> {
        if let Some(v) = self.seen.borrow().get(dir) {
            return v.clone();
        }
        let values: Vec<f64> = match observable::read_history(dir) {
            Some(h) => self.observe.iter().map(|o| observe(&h, o)).collect(),
            None => vec![f64::NAN; self.observe.len()],
        };
        self.seen.borrow_mut().insert(dir.to_path_buf(), values.clone());
        values
    }
}

/// A case's state as the summary shows it.
pub(crate) enum State {
    Ended(CaseRecord),
    /// Not ended: "running" (claimed in this session), "interrupted" (a run directory without
    /// an outcome, to resume) or "pending".
    Open(&'static str),
}

/// A case's row: the case, its state and its run directory.
pub(crate) struct Row {
    pub(crate) case: Case,
    pub(crate) state: State,
    pub(crate) dir: PathBuf,
}

/// Writes `summary.csv` in `root` from the rows of all cases (in case order); the `dir` column
/// is relative to `root` where the directory is in it.
pub(crate) fn write(root: &Path, study: &Study, rows: &[Row], observations: &Observations) -> Result<()> {
    let keys = study.keys();
    let mut out = String::new();
    let scenes = study.per_case_scenes();
    let mut header: Vec<String> = vec!["case".into()];
    if scenes {
        header.push("scene".into());
    }
    header.extend(keys.iter().cloned());
    header.push("status".into());
    header.extend(COUNTERS.iter().map(|(c, _)| c.to_string()));
    header.extend(study.observe.iter().cloned());
    header.extend(["error".into(), "dir".into()]);
    out.push_str(&header.iter().map(|h| csv_field(h)).collect::<Vec<_>>().join(","));
    out.push('\n');
    let num = |v: f64| if v.is_finite() { format!("{v}") } else { String::new() };
    for Row { case, state, dir } in rows {
        let pairs = case.pairs();
        let mut row: Vec<String> = vec![case.index.to_string()];
        if scenes {
            row.push(case.own_scene.clone().unwrap_or_else(|| case.scene.clone()));
        }
        for k in &keys {
            row.push(pairs.iter().rev().find(|(pk, _)| pk == k).map(|(_, v)| v.clone()).unwrap_or_default());
        }
        match state {
            State::Ended(r) => {
                row.push(r.status.clone());
                row.extend(COUNTERS.iter().map(|(c, _)| r.counters.get(*c).map_or(String::new(), |v| num(*v))));
                if r.ok() {
                    row.extend(observations.of(dir).into_iter().map(num));
                } else {
                    row.extend(std::iter::repeat_n(String::new(), study.observe.len()));
                }
                row.push(r.error.clone());
            }
            State::Open(s) => {
                row.push(s.to_string());
                row.extend(std::iter::repeat_n(String::new(), COUNTERS.len() + study.observe.len() + 1));
            }
        }
        row.push(dir.strip_prefix(root).unwrap_or(dir).display().to_string());
        out.push_str(&row.iter().map(|f| csv_field(f)).collect::<Vec<_>>().join(","));
        out.push('\n');
    }
    rundir::write_text_atomically(&root.join("summary.csv"), &out)
}

/// A CSV field, quoted when it holds a comma, quote or line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\"").replace(['\n', '\r'], " "))
    } else {
        s.to_string()
    }
}

/// The fields of a line of CSV as [`csv_field`] writes them: a field in double quotes may hold
/// commas, and `""` in it is one quote.
fn csv_fields(line: &str) -> Vec<String> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            '"' if quoted => quoted = false,
            '"' if field.is_empty() => quoted = true,
            ',' if !quoted => fields.push(std::mem::take(&mut field)),
            c => field.push(c),
        }
    }
    fields.push(field);
    fields
}

/// Wall times by case label from an earlier summary.csv (`estimate_from`), as cost estimates.
pub(crate) fn read_wall_times(path: &Path, study: &Study) -> Result<BTreeMap<Vec<(String, String)>, f64>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, format!("estimate_from: {e}")))?;
    let mut lines = text.lines();
    let header = csv_fields(lines.next().unwrap_or_default());
    let keys = study.label_keys();
    let wall = header.iter().position(|h| *h == "wall_s");
    let cols: Vec<Option<usize>> = keys.iter().map(|k| header.iter().position(|h| h == k)).collect();
    let Some(wall) = wall else {
        return Err(Error::io(path, "estimate_from: no wall_s column (not a sweep's summary.csv)"));
    };
    let mut out = BTreeMap::new();
    for l in lines {
        // Quoted fields too: an override value may hold commas (`"[5, 10]"`).
        let f = csv_fields(l);
        let Some(w) = f.get(wall).and_then(|w| w.parse::<f64>().ok()) else { continue };
        let label: Vec<(String, String)> = keys
            .iter()
            .zip(&cols)
            .filter_map(|(k, c)| c.and_then(|c| f.get(c)).filter(|v| !v.is_empty()).map(|v| (k.clone(), v.clone())))
            .collect();
        out.insert(label, w);
    }
    Ok(out)
}

/// A case's overrides in the form [`read_wall_times`] keys them (the last value of each key, by
/// key; `scene`: the case's scene as summary.csv shows it).
pub(crate) fn label_key(case: &Case, keys: &[String]) -> Vec<(String, String)> {
    let pairs = case.pairs();
    keys.iter()
        .filter_map(|k| match k.as_str() {
            "scene" => Some((k.clone(), case.own_scene.clone().unwrap_or_else(|| case.scene.clone()))),
            _ => pairs.iter().rev().find(|(pk, _)| pk == k).map(|(_, v)| (k.clone(), v.clone())),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::store::Signature;
    use super::*;

    #[test]
    fn csv_fields_read_back_what_csv_field_writes() {
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        let row = ["1", "[5, 10]", "", "say \"hi\", twice", "x"];
        let line = row.iter().map(|f| csv_field(f)).collect::<Vec<_>>().join(",");
        assert_eq!(csv_fields(&line), row);
        assert_eq!(csv_fields(""), [""]);
        assert_eq!(csv_fields("a,,b"), ["a", "", "b"]);
    }

    #[test]
    fn summary_rows_with_array_values_and_observables() {
        // An array value is quoted in summary.csv ("[5, 10]"): the columns after it must not
        // shift. The observables come from each ok case's history; a failed case has none.
        let study = Study::parse(
            Path::new("s.toml"),
            "scene = \"cryer\"\nobserve = [\"max:f\", \"f@0.5\"]\n\
             [[case]]\nset = [\"output.fields_at=[5, 10]\", \"material.mu=15\"]\n\
             [[case]]\nset = [\"output.fields_at=[1, 2, 3]\", \"material.mu=25\"]\n\
             [[case]]\nset = [\"material.mu=35\"]\n",
        )
        .unwrap();
        let root = std::env::temp_dir().join(format!("poroplast-summary-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let rows: Vec<Row> = study
            .cases
            .iter()
            .zip([3.0, 9.0, 1.0])
            .map(|(c, wall)| {
                let dir = root.join("cases").join(c.index.to_string());
                std::fs::create_dir_all(&dir).unwrap();
                std::fs::write(dir.join("history.csv"), format!("time,f\n0,{wall}\n1,0\n")).unwrap();
                let sig = Signature::of(&c.scene, study.overrides(c), vec![]).unwrap();
                let failed = (c.index == 2).then(|| "diverged".to_string());
                let mut r = CaseRecord::of(&dir, &sig, failed);
                r.counters.insert("wall_s".into(), wall);
                Row { case: c.clone(), state: State::Ended(r), dir }
            })
            .collect();
        write(&root, &study, &rows, &Observations::new(&study.observe)).unwrap();
        let text = std::fs::read_to_string(root.join("summary.csv")).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "case,output.fields_at,material.mu,status,wall_s,dofs,steps,step_cuts,newton_its,ksp_its,max:f,f@0.5,error,dir"
        );
        assert_eq!(lines[1], "0,\"[5, 10]\",15,ok,3,,,,,,3,1.5,,cases/0");
        assert_eq!(lines[3], "2,,35,failed,1,,,,,,,,diverged,cases/2");
        let walls = read_wall_times(&root.join("summary.csv"), &study).unwrap();
        let keys = study.label_keys();
        assert_eq!(walls.get(&label_key(&study.cases[0], &keys)), Some(&3.0), "{walls:?}");
        assert_eq!(walls.get(&label_key(&study.cases[1], &keys)), Some(&9.0), "{walls:?}");
        let _ = std::fs::remove_dir_all(&root);
    }
}
