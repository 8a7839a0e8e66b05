//! The study file (STUDY.toml) and its cases.
//!
//! ```toml
//! name = "mu_h"                    # optional (default: the file's stem); names the sweep directory
//! scene = "reference_axi"          # base scene: a shipped scene's name or a file (relative to STUDY.toml)
//! set = ["time.t_end=10"]          # --set overrides of every case (optional)
//! petsc = ["-ksp_rtol", "1e-8"]    # PETSc options of every case (optional)
//! observe = ["max:force_total_mg"] # summary.csv observables (optional, see `observable`)
//! estimate_from = "old/summary.csv" # wall times of an earlier sweep: run the longest cases first (optional)
//!
//! [[grid]]                         # an axis: every combination of the axes is a case
//! key = "material.mu"              # (the first axis varies slowest)
//! values = [10, 20]
//!
//! [[grid]]                         # a linked axis: its keys change together
//! keys = ["mesh.params.h", "mesh.params.h_pole"]
//! values = [[20, 4], [15, 2]]
//! ```
//!
//! or, instead of `[[grid]]`, a list of cases, each with its own overrides and, optionally, its
//! own scene (then the study's `scene` may be left out if every case names one):
//!
//! ```toml
//! [[case]]
//! set = ["material.mu=10", "material.nu=0.3"]
//! [[case]]
//! scene = "remodel_40"             # this case's scene instead of the study's (as `scene` above)
//! set = ["time.t_end=20"]
//! ```
//!
//! A value is the text after `=` of a `--set`: a string is taken as it is (`"[5, 10]"`), a
//! number, boolean or array is written as TOML. The semantics of the axes are those of
//! `scripts/study.py --grid` (`KEY=V1,V2` and `K1,K2=A1:A2,B1:B2`).

use crate::error::{Error, Result};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A study file, as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct StudyFile {
    name: Option<String>,
    scene: Option<String>,
    #[serde(default, deserialize_with = "one_or_list")]
    set: Vec<String>,
    #[serde(default)]
    petsc: Vec<String>,
    observe: Option<Vec<String>>,
    estimate_from: Option<String>,
    #[serde(default)]
    grid: Vec<Axis>,
    #[serde(default)]
    case: Vec<CaseEntry>,
}

/// One `[[grid]]` axis: `key` and a list of values, or `keys` and a list of value lists.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct Axis {
    key: Option<String>,
    keys: Option<Vec<String>>,
    values: Vec<toml::Value>,
}

/// One `[[case]]`: its overrides (`KEY=VALUE`) and its own scene, if it has one.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseEntry {
    scene: Option<String>,
    #[serde(default, deserialize_with = "one_or_list")]
    set: Vec<String>,
}

/// `set = "KEY=VALUE"` (one override) or `set = ["KEY=VALUE", ...]`: a lone string is one override,
/// not a list of its characters.
fn one_or_list<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Vec<String>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum OneOrList {
        One(String),
        List(Vec<String>),
    }
    match OneOrList::deserialize(d) {
        Ok(OneOrList::One(s)) => Ok(vec![s]),
        Ok(OneOrList::List(v)) => Ok(v),
        Err(_) => Err(serde::de::Error::custom("`set` is an override \"KEY=VALUE\" or a list of them")),
    }
}

/// A study: the base scene and settings, and its cases in order.
#[derive(Debug, Clone)]
pub(crate) struct Study {
    pub(crate) name: String,
    /// Overrides of every case (before the case's own).
    pub(crate) set: Vec<String>,
    pub(crate) petsc: Vec<String>,
    pub(crate) observe: Vec<String>,
    /// Whether the study file names its observables (else they are [`crate::io::observable::DEFAULT`],
    /// empty where a scene has no such column).
    pub(crate) observe_given: bool,
    /// An earlier summary.csv whose wall times estimate the cases' costs.
    pub(crate) estimate_from: Option<PathBuf>,
    pub(crate) cases: Vec<Case>,
}

/// One case: its index in the study, its scene and its own overrides.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Case {
    pub(crate) index: usize,
    /// The scene argument of the case (the study's, or its own): a shipped scene's name, or a
    /// file's absolute path.
    pub(crate) scene: String,
    /// Its own scene as the study file names it (`[[case]] scene`), if it has one.
    pub(crate) own_scene: Option<String>,
    /// `KEY=VALUE` overrides of this case (after the study's `set`).
    pub(crate) set: Vec<String>,
}

impl Case {
    /// The case's overrides as (key, value).
    pub(crate) fn pairs(&self) -> Vec<(String, String)> {
        self.set
            .iter()
            .map(|s| match s.split_once('=') {
                Some((k, v)) => (k.trim().to_string(), v.trim().to_string()),
                None => (s.trim().to_string(), String::new()),
            })
            .collect()
    }

    /// How the case is named in progress lines: its own scene, if any, and its overrides; a
    /// list value of more than 4 items shown by its first and last (`time.steps=[0.05, …(36), 10.0]`).
    pub(crate) fn label(&self) -> String {
        let mut parts: Vec<String> = self.own_scene.iter().map(|s| format!("scene={s}")).collect();
        parts.extend(self.set.iter().map(|s| short_list(s)));
        if parts.is_empty() {
            "(base scene)".into()
        } else {
            parts.join(" ")
        }
    }
}

/// `key=[a,b,...,z]` with more than 4 items as `key=[a, …(n), z]`; anything else as it is.
fn short_list(set: &str) -> String {
    match set.split_once('=') {
        Some((k, v)) if v.trim().starts_with('[') && v.trim().ends_with(']') => {
            let items: Vec<&str> = v.trim()[1..v.trim().len() - 1].split(',').map(str::trim).collect();
            if items.len() > 4 {
                format!("{k}=[{}, …({}), {}]", items[0], items.len(), items[items.len() - 1])
            } else {
                set.to_string()
            }
        }
        _ => set.to_string(),
    }
}

impl Study {
    /// Parses the text of the study file `path` (read by the caller); relative paths in it are
    /// relative to the file's directory.
    pub(crate) fn parse(path: &Path, text: &str) -> Result<Study> {
        let err = |msg: String| Error::Sweep(format!("study {}: {msg}", path.display()));
        let file: StudyFile = toml::from_str(text).map_err(|e| err(crate::scene::toml_message(text, &e)))?;
        let base = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        // A scene argument: a file relative to the study file, else as written (a shipped scene).
        let resolve = |scene: &str| -> Result<String> {
            let local = base.join(scene);
            Ok(if local.is_file() {
                std::fs::canonicalize(&local).map_err(|e| Error::io(&local, e))?.display().to_string()
            } else {
                scene.to_string()
            })
        };
        let scene = file.scene.as_deref().map(resolve).transpose()?;
        let estimate_from = file.estimate_from.as_ref().map(|e| base.join(e));
        if !file.grid.is_empty() && !file.case.is_empty() {
            return Err(err("give the cases as [[grid]] axes or as a [[case]] list, not both".into()));
        }
        // (own scene, overrides) of each case.
        let cases: Vec<(Option<String>, Vec<String>)> = if !file.case.is_empty() {
            file.case.iter().map(|c| (c.scene.clone(), c.set.clone())).collect()
        } else if !file.grid.is_empty() {
            expand(&file.grid).map_err(err)?.into_iter().map(|set| (None, set)).collect()
        } else {
            return Err(err("no cases: give [[grid]] axes (key, values) or [[case]] entries (set)".into()));
        };
        let mut resolved = Vec::with_capacity(cases.len());
        for (index, (own, set)) in cases.into_iter().enumerate() {
            let scene = match (&own, &scene) {
                (Some(s), _) => resolve(s)?,
                (None, Some(s)) => s.clone(),
                (None, None) => {
                    return Err(err(format!(
                        "missing field `scene`: give the study's base scene, or a `scene` in every [[case]] \
                         (case {index} has none)"
                    )))
                }
            };
            resolved.push(Case { index, scene, own_scene: own, set });
        }
        let name = match &file.name {
            Some(n) if !n.trim().is_empty() => n.trim().to_string(),
            _ => path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "study".into()),
        };
        Ok(Study {
            name,
            set: file.set,
            petsc: file.petsc,
            observe_given: file.observe.is_some(),
            observe: file
                .observe
                .unwrap_or_else(|| crate::io::observable::DEFAULT.iter().map(|s| s.to_string()).collect()),
            estimate_from,
            cases: resolved,
        })
    }

    /// The scenes of the cases, each once, in order of first appearance.
    pub(crate) fn scenes(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for c in &self.cases {
            if !out.contains(&c.scene.as_str()) {
                out.push(&c.scene);
            }
        }
        out
    }

    /// The columns of summary.csv that tell cases apart: `scene` when cases have their own
    /// scenes, then the override keys.
    pub(crate) fn label_keys(&self) -> Vec<String> {
        let scene = self.per_case_scenes().then(|| "scene".to_string());
        scene.into_iter().chain(self.keys()).collect()
    }

    /// Whether some case has its own scene (summary.csv then has a `scene` column).
    pub(crate) fn per_case_scenes(&self) -> bool {
        self.cases.iter().any(|c| c.own_scene.is_some())
    }

    /// Every override of a case: the study's, then the case's own.
    pub(crate) fn overrides(&self, case: &Case) -> Vec<String> {
        self.set.iter().chain(&case.set).cloned().collect()
    }

    /// The override keys of the cases, in order of first appearance (summary.csv's first columns).
    pub(crate) fn keys(&self) -> Vec<String> {
        let mut keys: Vec<String> = Vec::new();
        for c in &self.cases {
            for (k, _) in c.pairs() {
                if !keys.contains(&k) {
                    keys.push(k);
                }
            }
        }
        keys
    }
}

/// The cases of a grid: every combination of the axes' points, the first axis slowest.
fn expand(axes: &[Axis]) -> std::result::Result<Vec<Vec<String>>, String> {
    let mut points: Vec<Vec<Vec<String>>> = Vec::new();
    for (i, axis) in axes.iter().enumerate() {
        let keys = match (&axis.key, &axis.keys) {
            (Some(k), None) => vec![k.clone()],
            (None, Some(ks)) if !ks.is_empty() => ks.clone(),
            _ => return Err(format!("[[grid]] axis {}: give `key` (one) or `keys` (linked), not both", i + 1)),
        };
        if keys.iter().any(|k| k.trim().is_empty() || k.contains('=')) {
            return Err(format!("[[grid]] axis {}: a key is empty or contains '='", i + 1));
        }
        if axis.values.is_empty() {
            return Err(format!("[[grid]] axis {} ({}): no values", i + 1, keys.join(", ")));
        }
        let mut axis_points = Vec::new();
        for v in &axis.values {
            let parts: Vec<&toml::Value> = if keys.len() == 1 {
                vec![v]
            } else {
                match v {
                    toml::Value::Array(a) if a.len() == keys.len() => a.iter().collect(),
                    _ => {
                        return Err(format!(
                            "[[grid]] axis {} ({}): every value must be a list of {} values, one per key; got {v}",
                            i + 1,
                            keys.join(", "),
                            keys.len()
                        ))
                    }
                }
            };
            axis_points.push(keys.iter().zip(parts).map(|(k, v)| format!("{}={}", k.trim(), value_text(v))).collect());
        }
        points.push(axis_points);
    }
    let mut cases: Vec<Vec<String>> = vec![Vec::new()];
    for axis in points {
        cases = cases
            .into_iter()
            .flat_map(|c| {
                axis.iter().map(move |p| {
                    let mut c = c.clone();
                    c.extend(p.iter().cloned());
                    c
                })
            })
            .collect();
    }
    Ok(cases)
}

/// A value as the text after `=` of a `--set`.
fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Study> {
        Study::parse(Path::new("/nonexistent/s.toml"), text)
    }

    #[test]
    fn grid_with_a_linked_axis() {
        let s = parse(
            "scene = \"reference_axi\"\nset = [\"time.t_end=5\"]\n[[grid]]\nkey = \"material.mu\"\nvalues = [10, 20.5]\n\
             [[grid]]\nkeys = [\"mesh.params.h\", \"mesh.params.h_pole\"]\nvalues = [[20, 4], [\"15\", 2]]\n",
        )
        .unwrap();
        assert_eq!(s.name, "s");
        assert_eq!(s.cases.len(), 4);
        assert_eq!(s.cases[0].set, ["material.mu=10", "mesh.params.h=20", "mesh.params.h_pole=4"]);
        assert_eq!(s.cases[1].set, ["material.mu=10", "mesh.params.h=15", "mesh.params.h_pole=2"]);
        assert_eq!(s.cases[3].set, ["material.mu=20.5", "mesh.params.h=15", "mesh.params.h_pole=2"]);
        assert_eq!(s.overrides(&s.cases[0])[0], "time.t_end=5");
        assert_eq!(s.keys(), ["material.mu", "mesh.params.h", "mesh.params.h_pole"]);
    }

    #[test]
    fn case_list_and_bad_files() {
        let s = parse("scene = \"x\"\n[[case]]\nset = [\"a=1\"]\n[[case]]\nset = []\n").unwrap();
        assert_eq!(s.cases.len(), 2);
        assert_eq!(s.cases[1].label(), "(base scene)");
        assert_eq!(s.observe, crate::io::observable::DEFAULT);
        let msg = |t: &str| parse(t).unwrap_err().to_string();
        assert!(msg("scene = \"x\"\n").contains("no cases"));
        assert!(msg("scene = \"x\"\nbogus = 1\n[[case]]\nset=[]\n").contains("bogus"));
        assert!(msg("[[case]]\nset=[]\n").contains("missing field `scene`"));
        assert!(msg("scene = \"x\"\n[[grid]]\nkey = \"a\"\nvalues = []\n").contains("no values"));
        assert!(msg("scene = \"x\"\n[[grid]]\nkeys = [\"a\", \"b\"]\nvalues = [[1]]\n").contains("list of 2"));
        assert!(msg("scene = \"x\"\n[[grid]]\nkey = \"a\"\nvalues = [1]\n[[case]]\nset=[]\n").contains("not both"));
        // A lone string is one override, in the study's `set` and a case's; a number is neither.
        let s = parse("scene = \"x\"\nset = \"time.t_end=2\"\n[[case]]\nset = \"a=1\"\n").unwrap();
        assert_eq!(
            (s.set.as_slice(), s.cases[0].set.as_slice()),
            (&["time.t_end=2".to_string()][..], &["a=1".to_string()][..])
        );
        let e = msg("scene = \"x\"\nset = 2\n[[case]]\nset = []\n");
        assert!(e.contains("line 2") && e.contains("`set` is an override \"KEY=VALUE\" or a list of them"), "{e}");
    }

    #[test]
    fn cases_with_their_own_scenes() {
        // Without a base scene every case names one; with one, a case may replace it.
        let s =
            parse("[[case]]\nscene = \"remodel_40\"\nset = [\"a=1\"]\n[[case]]\nscene = \"dir/my.toml\"\n").unwrap();
        assert_eq!((s.cases[0].scene.as_str(), s.cases[1].scene.as_str()), ("remodel_40", "dir/my.toml"));
        assert_eq!(s.cases[0].label(), "scene=remodel_40 a=1");
        assert_eq!(short_list("time.steps=[0.5,1,1.5,2,3]"), "time.steps=[0.5, …(5), 3]");
        assert_eq!(short_list("time.land_on=[1.0, 2.0]"), "time.land_on=[1.0, 2.0]");
        assert_eq!(short_list("a=1"), "a=1");
        assert_eq!(s.scenes(), ["remodel_40", "dir/my.toml"]);
        assert!(s.per_case_scenes());
        let s =
            parse("scene = \"x\"\n[[case]]\nset = []\n[[case]]\nscene = \"y\"\nset = []\n[[case]]\nscene = \"x\"\n")
                .unwrap();
        assert_eq!(s.scenes(), ["x", "y"]);
        assert_eq!(s.cases[0].own_scene.as_deref(), None);
        let g = parse("scene = \"x\"\n[[grid]]\nkey = \"a\"\nvalues = [1]\n").unwrap();
        assert!(!g.per_case_scenes() && g.cases[0].scene == "x");
        let e = parse("[[case]]\nscene = \"x\"\n[[case]]\nset = []\n").unwrap_err().to_string();
        assert!(e.contains("case 1 has none"), "{e}");
    }
}
