//! A case's outcome (`case.toml` in its run directory, written when it ends) and the sweep's
//! `summary.csv`: one row per case in case order — its overrides, status, wall time, dofs,
//! steps, step cuts, Newton and Krylov iterations, the observables, the error line and the
//! run directory.
//!
//! Observables are read from the case's `history.csv`, as `scripts/study.py` reads them:
//! `max:COL`, `min:COL`, `last:COL`, `last:A/B` (a ratio), `COL@T` (interpolated at time T),
//! `zero:COL` (the first time COL falls from positive to zero or below); empty where they do
//! not apply (no such column, a failed case).

use super::study::{Case, Study};
use crate::error::{Error, Result};
use crate::io::rundir;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The record of a case that ended (`case.toml`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CaseResult {
    /// "ok" or "failed".
    pub status: String,
    /// The error line of a failed case.
    #[serde(default)]
    pub error: String,
    /// The case's overrides (all of them, the study's first): a record of another case is not this one's.
    pub set: Vec<String>,
    /// The counters of timings.txt (`wall_s` its total), where it was written.
    #[serde(default)]
    pub counters: BTreeMap<String, f64>,
    #[serde(default)]
    pub observables: BTreeMap<String, f64>,
}

/// summary.csv column ← timings.txt key.
const COUNTERS: [(&str, &str); 6] = [
    ("wall_s", "total"),
    ("dofs", "dofs"),
    ("steps", "steps"),
    ("step_cuts", "step_cuts"),
    ("newton_its", "newton_its"),
    ("ksp_its", "ksp_its"),
];

pub const RECORD: &str = "case.toml";

impl CaseResult {
    /// The outcome of a case whose run ended in `dir` (`error`: its error, if it failed), with
    /// the counters and observables the run directory holds — of an ok case only: a failed run
    /// may have ended before writing them, and those in the directory would be an earlier run's.
    pub fn of(dir: &Path, set: Vec<String>, error: Option<String>, observe: &[String]) -> CaseResult {
        let timings = if error.is_none() { read_timings(&dir.join("timings.txt")) } else { BTreeMap::new() };
        let counters = COUNTERS.iter().filter_map(|(c, k)| timings.get(*k).map(|v| (c.to_string(), *v))).collect();
        let observables = match (&error, read_history(&dir.join("history.csv"))) {
            (None, Some(h)) => {
                observe.iter().map(|o| (o.clone(), observe_one(&h, o))).filter(|(_, v)| v.is_finite()).collect()
            }
            _ => BTreeMap::new(),
        };
        CaseResult {
            status: if error.is_some() { "failed".into() } else { "ok".into() },
            // One line: the first of the message.
            error: error.map(|e| e.lines().next().unwrap_or_default().to_string()).unwrap_or_default(),
            set,
            counters,
            observables,
        }
    }

    /// The record in `dir`, if there is one and it is of a case with these overrides.
    pub fn read(dir: &Path, set: &[String]) -> Option<CaseResult> {
        let text = std::fs::read_to_string(dir.join(RECORD)).ok()?;
        let r: CaseResult = toml::from_str(&text).ok()?;
        (r.set == set).then_some(r)
    }

    /// Writes the record into `dir` (atomically: a reader finds the whole record or none).
    pub fn write(&self, dir: &Path) -> Result<()> {
        let path = dir.join(RECORD);
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let text = toml::to_string(self).map_err(|e| Error::io(&path, e))?;
        rundir::write_text_atomically(&path, &format!("# the outcome of this case of a poroplast sweep\n{text}"))
    }

    pub fn ok(&self) -> bool {
        self.status == "ok"
    }
}

/// A case's state as the summary shows it.
pub enum State {
    Ended(CaseResult),
    /// Not ended: "running" (claimed in this session), "interrupted" (a run directory from an
    /// earlier session, to resume) or "pending".
    Open(&'static str),
}

/// Writes `summary.csv` in `root` from the states of all cases (in case order).
pub fn write(root: &Path, study: &Study, states: &[(Case, State, String)]) -> Result<()> {
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
    for (case, state, dir) in states {
        let pairs = case.pairs();
        let mut row: Vec<String> = vec![case.index.to_string()];
        if scenes {
            row.push(case.own_scene.clone().unwrap_or_else(|| case.scene.clone()));
        }
        for k in &keys {
            row.push(pairs.iter().rev().find(|(pk, _)| pk == k).map(|(_, v)| v.clone()).unwrap_or_default());
        }
        let num = |m: &BTreeMap<String, f64>, k: &str| m.get(k).map(|v| format!("{v}")).unwrap_or_default();
        match state {
            State::Ended(r) => {
                row.push(r.status.clone());
                row.extend(COUNTERS.iter().map(|(c, _)| num(&r.counters, c)));
                row.extend(study.observe.iter().map(|o| num(&r.observables, o)));
                row.push(r.error.clone());
            }
            State::Open(s) => {
                row.push(s.to_string());
                row.extend(std::iter::repeat_n(String::new(), COUNTERS.len() + study.observe.len() + 1));
            }
        }
        row.push(dir.clone());
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

/// `key = value` numbers of timings.txt.
fn read_timings(path: &Path) -> BTreeMap<String, f64> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    text.lines()
        .filter_map(|l| l.split_once(" = "))
        .filter_map(|(k, v)| v.trim().parse::<f64>().ok().map(|v| (k.trim().to_string(), v)))
        .collect()
}

/// history.csv as columns.
fn read_history(path: &Path) -> Option<BTreeMap<String, Vec<f64>>> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut lines = text.lines();
    let names: Vec<String> = lines.next()?.split(',').map(|s| s.trim().to_string()).collect();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for l in lines.filter(|l| !l.trim().is_empty()) {
        for (i, v) in l.split(',').enumerate().take(names.len()) {
            cols[i].push(v.trim().parse().unwrap_or(f64::NAN));
        }
    }
    Some(names.into_iter().zip(cols).collect())
}

/// The observable `spec` of a history (NaN where it does not apply).
fn observe_one(h: &BTreeMap<String, Vec<f64>>, spec: &str) -> f64 {
    let nan = f64::NAN;
    let col = |c: &str| h.get(c).filter(|v| !v.is_empty());
    if let Some((kind, c)) = spec.split_once(':') {
        if kind == "last" {
            if let Some((a, b)) = c.split_once('/') {
                return match (col(a), col(b)) {
                    (Some(a), Some(b)) if b[b.len() - 1] != 0.0 => a[a.len() - 1] / b[b.len() - 1],
                    _ => nan,
                };
            }
        }
        let Some(v) = col(c) else { return nan };
        return match kind {
            "max" => v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            "min" => v.iter().copied().fold(f64::INFINITY, f64::min),
            "last" => v[v.len() - 1],
            "zero" => {
                let Some(t) = col("time") else { return nan };
                (1..v.len())
                    .find(|&i| v[i - 1] > 0.0 && v[i] <= 0.0)
                    .map_or(nan, |i| t[i - 1] + (t[i] - t[i - 1]) * v[i - 1] / (v[i - 1] - v[i]))
            }
            _ => nan,
        };
    }
    let Some((c, when)) = spec.split_once('@') else { return nan };
    let (Some(v), Some(t), Ok(when)) = (col(c), col("time"), when.parse::<f64>()) else { return nan };
    (1..t.len().min(v.len())).find(|&i| t[i - 1] <= when && when <= t[i]).map_or(nan, |i| {
        let w = if t[i] > t[i - 1] { (when - t[i - 1]) / (t[i] - t[i - 1]) } else { 1.0 };
        v[i - 1] + w * (v[i] - v[i - 1])
    })
}

/// Wall times by case label from an earlier summary.csv (`estimate_from`), as cost estimates.
pub fn read_wall_times(path: &Path, study: &Study) -> Result<BTreeMap<Vec<(String, String)>, f64>> {
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
pub fn label_key(case: &Case, keys: &[String]) -> Vec<(String, String)> {
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
    use super::*;

    #[test]
    fn observables_of_a_history() {
        let mut h = BTreeMap::new();
        h.insert("time".to_string(), vec![0.0, 1.0, 2.0]);
        h.insert("f".to_string(), vec![1.0, 3.0, -1.0]);
        h.insert("g".to_string(), vec![2.0, 2.0, 4.0]);
        assert_eq!(observe_one(&h, "max:f"), 3.0);
        assert_eq!(observe_one(&h, "min:f"), -1.0);
        assert_eq!(observe_one(&h, "last:f/g"), -0.25);
        assert_eq!(observe_one(&h, "f@0.5"), 2.0);
        assert_eq!(observe_one(&h, "zero:f"), 1.75);
        assert!(observe_one(&h, "max:nope").is_nan());
        assert!(observe_one(&h, "f@5").is_nan());
        assert_eq!(csv_field("a,b"), "\"a,b\"");
    }

    #[test]
    fn csv_fields_read_back_what_csv_field_writes() {
        let row = ["1", "[5, 10]", "", "say \"hi\", twice", "x"];
        let line = row.iter().map(|f| csv_field(f)).collect::<Vec<_>>().join(",");
        assert_eq!(csv_fields(&line), row);
        assert_eq!(csv_fields(""), [""]);
        assert_eq!(csv_fields("a,,b"), ["a", "", "b"]);
    }

    #[test]
    fn wall_times_of_cases_with_array_values() {
        // An array value is quoted in summary.csv ("[5, 10]"): the columns after it must not shift.
        let study = Study::parse(
            Path::new("s.toml"),
            "scene = \"x\"\n[[case]]\nset = [\"output.fields_at=[5, 10]\", \"material.mu=15\"]\n\
             [[case]]\nset = [\"output.fields_at=[1, 2, 3]\", \"material.mu=25\"]\n",
        )
        .unwrap();
        let root = std::env::temp_dir().join(format!("poroplast-summary-{}", std::process::id()));
        std::fs::create_dir_all(&root).unwrap();
        let states: Vec<(Case, State, String)> = study
            .cases
            .iter()
            .zip([3.0, 9.0])
            .map(|(c, wall)| {
                let mut r = CaseResult::of(&root, study.overrides(c), None, &[]);
                r.counters.insert("wall_s".into(), wall);
                (c.clone(), State::Ended(r), format!("cases/{}", c.dir_name()))
            })
            .collect();
        write(&root, &study, &states).unwrap();
        let text = std::fs::read_to_string(root.join("summary.csv")).unwrap();
        assert!(text.contains("\"[5, 10]\""), "{text}");
        let walls = read_wall_times(&root.join("summary.csv"), &study).unwrap();
        let keys = study.label_keys();
        assert_eq!(walls.get(&label_key(&study.cases[0], &keys)), Some(&3.0), "{walls:?}");
        assert_eq!(walls.get(&label_key(&study.cases[1], &keys)), Some(&9.0), "{walls:?}");
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn a_failed_case_has_no_counters() {
        // A failed rerun must not show the timings.txt of the run before it.
        let dir = std::env::temp_dir().join(format!("poroplast-failed-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("timings.txt"), "total = 12.5\nsteps = 7\n").unwrap();
        let ok = CaseResult::of(&dir, vec![], None, &[]);
        assert_eq!(ok.counters.get("wall_s"), Some(&12.5));
        let failed = CaseResult::of(&dir, vec![], Some("diverged\nmore".into()), &[]);
        assert!(failed.counters.is_empty() && failed.error == "diverged" && !failed.ok());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
