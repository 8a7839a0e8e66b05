//! The observables of a case: scalars read from its `history.csv`, named by a small grammar —
//! the one grammar of the project (the study scripts read these values from `summary.csv`
//! instead of evaluating histories themselves).
//!
//! - `max:COL`, `min:COL`, `last:COL`: the largest, smallest, last value of column COL;
//! - `last:A/B`: the ratio of the last values (`last:height/width`);
//! - `COL@T`: COL interpolated linearly at time T;
//! - `zero:COL`: the first time COL falls from positive to zero or below (interpolated);
//! - against an exact solution (a column `COL_exact` beside COL): `err:COL@T`, |COL − COL_exact|
//!   at T, and `maxerr:COL@T0:T1`, the largest |COL − COL_exact| over the rows with T0 ≤ t ≤ T1
//!   (`inf` allowed).
//!
//! NaN where a spec does not apply: no such column, a time outside the run, no crossing. Every
//! spec holds a `:` or an `@`, which no override key, counter or other summary column does: a
//! reader of `summary.csv` tells the observable columns by that.

use std::collections::BTreeMap;
use std::path::Path;

/// The observables of `summary.csv` when the study names none: those of the plates experiment —
/// the peak force, F(35 s), the probe pressure p(X_U) at 5 and 30 s and its zero crossing, the
/// final height over width (empty where a scene has no such column).
pub const DEFAULT: [&str; 6] =
    ["max:force_total_mg", "force_total_mg@35", "probe_p@5", "probe_p@30", "zero:probe_p", "last:height/width"];

/// A history's columns by name.
pub type Columns = BTreeMap<String, Vec<f64>>;

/// `history.csv` (of a run directory) as columns; None without the file. A field that does not
/// parse reads as NaN.
pub fn read_history(dir: &Path) -> Option<Columns> {
    let text = std::fs::read_to_string(dir.join("history.csv")).ok()?;
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
pub fn observe(h: &Columns, spec: &str) -> f64 {
    let nan = f64::NAN;
    let col = |c: &str| h.get(c).filter(|v| !v.is_empty());
    if let Some((kind, rest)) = spec.split_once(':') {
        match kind {
            "err" | "maxerr" => return error(h, kind, rest),
            "last" if rest.contains('/') => {
                let (a, b) = rest.split_once('/').unwrap_or_default();
                return match (col(a), col(b)) {
                    (Some(a), Some(b)) if b[b.len() - 1] != 0.0 => a[a.len() - 1] / b[b.len() - 1],
                    _ => nan,
                };
            }
            _ => {}
        }
        let Some(v) = col(rest) else { return nan };
        return match kind {
            "max" => v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            "min" => v.iter().copied().fold(f64::INFINITY, f64::min),
            "last" => v[v.len() - 1],
            "zero" => {
                let Some(t) = col("time") else { return nan };
                (1..v.len().min(t.len()))
                    .find(|&i| v[i - 1] > 0.0 && v[i] <= 0.0)
                    .map_or(nan, |i| t[i - 1] + (t[i] - t[i - 1]) * v[i - 1] / (v[i - 1] - v[i]))
            }
            _ => nan,
        };
    }
    let Some((c, when)) = spec.split_once('@') else { return nan };
    match (col(c), when.parse::<f64>()) {
        (Some(v), Ok(when)) => at(h, v, when),
        _ => nan,
    }
}

/// Column `col` interpolated linearly at time `when` (NaN without the column or outside the run).
pub fn at_time(h: &Columns, col: &str, when: f64) -> f64 {
    h.get(col).map_or(f64::NAN, |v| at(h, v, when))
}

/// Column values `v` interpolated linearly at time `when` (NaN outside the run).
fn at(h: &Columns, v: &[f64], when: f64) -> f64 {
    let Some(t) = h.get("time") else { return f64::NAN };
    (1..t.len().min(v.len())).find(|&i| t[i - 1] <= when && when <= t[i]).map_or(f64::NAN, |i| {
        let w = if t[i] > t[i - 1] { (when - t[i - 1]) / (t[i] - t[i - 1]) } else { 1.0 };
        v[i - 1] + w * (v[i] - v[i - 1])
    })
}

/// `err:COL@T` and `maxerr:COL@T0:T1` (`rest` is what follows the `:`).
fn error(h: &Columns, kind: &str, rest: &str) -> f64 {
    let nan = f64::NAN;
    let Some((c, when)) = rest.split_once('@') else { return nan };
    let (Some(v), Some(exact), Some(t)) = (h.get(c), h.get(&format!("{c}_exact")), h.get("time")) else {
        return nan;
    };
    if kind == "err" {
        return match when.parse::<f64>() {
            Ok(when) => (at(h, v, when) - at(h, exact, when)).abs(),
            Err(_) => nan,
        };
    }
    let Some((Ok(t0), Ok(t1))) = when.split_once(':').map(|(a, b)| (a.parse::<f64>(), b.parse::<f64>())) else {
        return nan;
    };
    let errors: Vec<f64> = t
        .iter()
        .zip(v.iter().zip(exact))
        .filter(|(s, _)| t0 <= **s && **s <= t1)
        .map(|(_, (a, b))| (a - b).abs())
        .collect();
    if errors.is_empty() {
        nan
    } else {
        errors.into_iter().fold(f64::NEG_INFINITY, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn history(cols: &[(&str, &[f64])]) -> Columns {
        cols.iter().map(|(k, v)| (k.to_string(), v.to_vec())).collect()
    }

    #[test]
    fn observables_of_a_history() {
        let h = history(&[("time", &[0.0, 1.0, 2.0]), ("f", &[1.0, 3.0, -1.0]), ("g", &[2.0, 2.0, 4.0])]);
        assert_eq!(observe(&h, "max:f"), 3.0);
        assert_eq!(observe(&h, "min:f"), -1.0);
        assert_eq!(observe(&h, "last:f"), -1.0);
        assert_eq!(observe(&h, "last:f/g"), -0.25);
        assert_eq!(observe(&h, "f@0.5"), 2.0);
        assert_eq!(observe(&h, "zero:f"), 1.75);
        assert!(observe(&h, "max:nope").is_nan());
        assert!(observe(&h, "f@5").is_nan());
        assert!(observe(&h, "zero:g").is_nan());
        assert!(observe(&h, "bogus:f").is_nan() && observe(&h, "f").is_nan());
    }

    #[test]
    fn a_pressure_falling_through_zero() {
        // p falls through zero between t = 2 (p = 1) and t = 3 (p = -3): at t = 2.25.
        let h = history(&[
            ("time", &[0.0, 1.0, 2.0, 3.0]),
            ("p", &[0.0, 2.0, 1.0, -3.0]),
            ("height", &[2.0, 1.0, 1.0, 1.5]),
            ("width", &[2.0, 2.0, 2.5, 3.0]),
        ]);
        assert_eq!(observe(&h, "max:p"), 2.0);
        assert_eq!(observe(&h, "last:p"), -3.0);
        assert!((observe(&h, "p@1.5") - 1.5).abs() < 1e-15);
        assert!((observe(&h, "zero:p") - 2.25).abs() < 1e-15);
        assert_eq!(observe(&h, "last:height/width"), 0.5);
        assert!(observe(&h, "p@7").is_nan() && observe(&h, "max:q").is_nan());
    }

    #[test]
    fn errors_against_an_exact_column() {
        // p − p_exact = 0, −0.5, 1.5 at t = 0, 1, 2.
        let h = history(&[("time", &[0.0, 1.0, 2.0]), ("p", &[1.0, 1.5, 4.0]), ("p_exact", &[1.0, 2.0, 2.5])]);
        assert_eq!(observe(&h, "err:p@1"), 0.5);
        assert_eq!(observe(&h, "err:p@1.5"), 0.5); // 2.75 against 2.25
        assert_eq!(observe(&h, "maxerr:p@0:1"), 0.5);
        assert_eq!(observe(&h, "maxerr:p@1:inf"), 1.5);
        assert!(observe(&h, "maxerr:p@3:4").is_nan());
        assert!(observe(&h, "err:q@1").is_nan() && observe(&h, "err:p").is_nan());
        assert!(observe(&h, "maxerr:p@1").is_nan());
    }

    #[test]
    fn every_spec_is_told_apart_from_other_columns() {
        for spec in DEFAULT {
            assert!(spec.contains([':', '@']), "{spec}");
        }
    }
}
