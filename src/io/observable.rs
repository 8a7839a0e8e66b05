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
//! A time T is in seconds, or with a unit: `5s`, `2min`, `1h`. [`check`] tells a spec that cannot
//! apply to a scene's columns and run before anything runs (a typo, a time after the end); once
//! run, NaN where a spec does not apply: no such column, a time outside the run, no crossing. Every
//! spec holds a `:` or an `@`, which no override key, counter or other summary column does: a
//! reader of `summary.csv` tells the observable columns by that.

use std::collections::BTreeMap;
use std::path::Path;

/// The observables of `summary.csv` when the study names none: those of the plates experiment —
/// the peak force, F(35 s), the probe pressure p(X_U) at 5 and 30 s and its zero crossing, the
/// final height over width (empty where a scene has no such column).
pub(crate) const DEFAULT: [&str; 6] =
    ["max:force_total_mg", "force_total_mg@35", "probe_p@5", "probe_p@30", "zero:probe_p", "last:height/width"];

/// A history's columns by name.
pub(crate) type Columns = BTreeMap<String, Vec<f64>>;

/// `history.csv` (of a run directory) as columns; None without the file. A field that does not
/// parse reads as NaN.
pub(crate) fn read_history(dir: &Path) -> Option<Columns> {
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
pub(crate) fn observe(h: &Columns, spec: &str) -> f64 {
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
    match (col(c), time(when)) {
        (Some(v), Some(when)) => at(h, v, when),
        _ => nan,
    }
}

/// A time of a spec in seconds: a number, or a number with the unit `s`, `min` or `h`.
pub(crate) fn time(text: &str) -> Option<f64> {
    let t = text.trim();
    let (num, scale) = [("min", 60.0), ("h", 3600.0), ("s", 1.0)]
        .iter()
        .find_map(|(u, k)| t.strip_suffix(u).map(|n| (n.trim(), *k)))
        .unwrap_or((t, 1.0));
    num.parse::<f64>().ok().map(|v| v * scale).filter(|v| !v.is_nan())
}

/// The grammar, for messages.
const GRAMMAR: &str = "max:COL, min:COL, last:COL, last:A/B, zero:COL, COL@T, err:COL@T or maxerr:COL@T0:T1 \
                       (T in s, or with a unit: 5s, 2min, 1h)";

/// Ok if `spec` is an observable of a run whose history has `columns` and ends at `t_end` (s);
/// else what is wrong, with the nearest column name for a misspelt one.
pub(crate) fn check(spec: &str, columns: &[String], t_end: f64) -> Result<(), String> {
    let names = || columns.iter().map(String::as_str);
    let column = |c: &str| -> Result<(), String> {
        if columns.iter().any(|k| k == c) {
            return Ok(());
        }
        let hint = crate::spelling::suggestion(c, names());
        Err(format!("`{spec}`: no column `{c}` in this scene's history{hint} (`poroplast columns SCENE` lists them)"))
    };
    let when = |t: &str| -> Result<f64, String> {
        let v = time(t).ok_or_else(|| format!("`{spec}`: `{t}` is not a time (seconds, or 5s, 2min, 1h)"))?;
        if v < 0.0 || v > t_end * (1.0 + 1e-12) {
            return Err(format!("`{spec}`: t = {v} s is outside the run, [0, {t_end}] s (time.t_end)"));
        }
        Ok(v)
    };
    let bad = || Err(format!("`{spec}` is not an observable: expected {GRAMMAR}"));
    if let Some((kind, rest)) = spec.split_once(':') {
        return match kind {
            "max" | "min" | "zero" => column(rest),
            "last" => match rest.split_once('/') {
                Some((a, b)) => column(a).and(column(b)),
                None => column(rest),
            },
            "err" | "maxerr" => {
                let Some((c, span)) = rest.split_once('@') else { return bad() };
                column(c)?;
                column(&format!("{c}_exact"))
                    .map_err(|_| format!("`{spec}`: column `{c}` has no exact solution `{c}_exact` to compare with"))?;
                if kind == "err" {
                    return when(span).map(drop);
                }
                let Some((t0, t1)) = span.split_once(':') else { return bad() };
                if t1.trim() != "inf" {
                    when(t1)?;
                }
                when(t0).map(drop)
            }
            _ => Err(format!(
                "`{spec}`: unknown kind `{kind}:`{} (expected {GRAMMAR})",
                crate::spelling::suggestion(kind, ["max", "min", "last", "zero", "err", "maxerr"])
            )),
        };
    }
    match spec.split_once('@') {
        Some((c, t)) => column(c).and(when(t).map(drop)),
        None => bad(),
    }
}

/// Column `col` interpolated linearly at time `when` (NaN without the column or outside the run).
pub(crate) fn at_time(h: &Columns, col: &str, when: f64) -> f64 {
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
        return match time(when) {
            Some(when) => (at(h, v, when) - at(h, exact, when)).abs(),
            None => nan,
        };
    }
    let end = |b: &str| if b.trim() == "inf" { Some(f64::INFINITY) } else { time(b) };
    let Some((Some(t0), Some(t1))) = when.split_once(':').map(|(a, b)| (time(a), end(b))) else {
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
    fn times_with_units() {
        assert_eq!(time("35"), Some(35.0));
        assert_eq!(time("0.5s"), Some(0.5));
        assert_eq!(time(" 2min"), Some(120.0));
        assert_eq!(time("1.5 h"), Some(5400.0));
        assert_eq!(time("5ms"), None);
        assert_eq!(time("s"), None);
        let h = history(&[("time", &[0.0, 60.0, 120.0]), ("f", &[0.0, 6.0, 12.0])]);
        assert_eq!(observe(&h, "f@1min"), 6.0);
        assert_eq!(observe(&h, "f@90s"), 9.0);
    }

    #[test]
    fn specs_checked_against_a_scenes_columns() {
        let cols: Vec<String> = ["time", "force_total_mg", "sigma_app", "p", "p_exact", "height", "width"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        for ok in [
            "max:force_total_mg",
            "force_total_mg@0.5s",
            "sigma_app@605",
            "last:height/width",
            "zero:p",
            "err:p@1",
            "maxerr:p@0:inf",
            "force_total_mg@10min",
        ] {
            assert_eq!(check(ok, &cols, 605.0), Ok(()), "{ok}");
        }
        let err = |spec: &str| check(spec, &cols, 605.0).unwrap_err();
        assert!(err("max:force_totl_mg").contains("did you mean `force_total_mg`"), "{}", err("max:force_totl_mg"));
        assert!(err("sigma_ap@2").contains("did you mean `sigma_app`"));
        assert!(err("maxx:force_total_mg").contains("unknown kind `maxx:` (did you mean `max`?)"));
        assert!(err("force_total_mg@700").contains("outside the run, [0, 605] s"));
        assert!(err("force_total_mg@5ms").contains("`5ms` is not a time"));
        assert!(err("err:height@1").contains("no exact solution `height_exact`"));
        assert!(err("force_total_mg").contains("is not an observable"));
        assert!(err("last:height/widht").contains("did you mean `width`"));
    }

    #[test]
    fn every_spec_is_told_apart_from_other_columns() {
        for spec in DEFAULT {
            assert!(spec.contains([':', '@']), "{spec}");
        }
    }
}
