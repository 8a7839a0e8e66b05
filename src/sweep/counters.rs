//! A case's counters: its wall time, dofs, steps, step cuts, Newton and Krylov iterations, read
//! from the `timings.txt` of its run directory. The store keeps them in `case.toml` and the
//! summary shows them, in this order.

use std::collections::BTreeMap;
use std::path::Path;

/// summary.csv column ← timings.txt key.
pub(crate) const COUNTERS: [(&str, &str); 6] = [
    ("wall_s", "total"),
    ("dofs", "dofs"),
    ("steps", "steps"),
    ("step_cuts", "step_cuts"),
    ("newton_its", "newton_its"),
    ("ksp_its", "ksp_its"),
];

/// The counters of the timings.txt in a run directory (summary.csv's names).
pub(crate) fn counters(dir: &Path) -> BTreeMap<String, f64> {
    let timings = read_timings(&dir.join("timings.txt"));
    COUNTERS.iter().filter_map(|(c, k)| timings.get(*k).map(|v| (c.to_string(), *v))).collect()
}

/// `key = value` numbers of timings.txt.
fn read_timings(path: &Path) -> BTreeMap<String, f64> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    text.lines()
        .filter_map(|l| l.split_once(" = "))
        .filter_map(|(k, v)| v.trim().parse::<f64>().ok().map(|v| (k.trim().to_string(), v)))
        .collect()
}
