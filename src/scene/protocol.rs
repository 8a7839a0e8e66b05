//! A tool's protocol as scene rows: `{ t, displacement = µm }`, `{ t, displacement = "held" }`
//! or `{ t, force = µN }` (the row syntax of a `[[tools]]` protocol, used today by
//! `plates.upper`), and the checks on a list of them. Linear between consecutive rows of one
//! control, held after the last; a change of control is two rows at one time (a switch).

use serde::{Deserialize, Serialize};

/// One row of a protocol (exactly one of `displacement` and `force`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ProtocolRow {
    /// Time, s.
    pub(crate) t: f64,
    /// The tool's displacement along its axis (µm, towards the body), or `"held"`: where the
    /// tool is at this time (after force control).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) displacement: Option<Displacement>,
    /// The force the tool presses on the body with, µN (full body).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) force: Option<f64>,
}

/// A displacement row's value: µm, or the position reached (`"held"`).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(untagged)]
pub(crate) enum Displacement {
    Value(f64),
    Held(HeldWord),
}

/// The word `"held"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum HeldWord {
    Held,
}

/// The control of a row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Control {
    /// µm along the axis (None: held where the tool is).
    Displacement(Option<f64>),
    /// µN.
    Force(f64),
}

impl ProtocolRow {
    /// The row's control, or an error naming the row (`key` row `i`, 1-based).
    pub(crate) fn control(&self, key: &str, i: usize) -> Result<Control, String> {
        match (self.displacement, self.force) {
            (Some(Displacement::Value(d)), None) => Ok(Control::Displacement(Some(d))),
            (Some(Displacement::Held(_)), None) => Ok(Control::Displacement(None)),
            (None, Some(f)) => Ok(Control::Force(f)),
            _ => Err(format!(
                "{key} row {i}: give exactly one of displacement (µm, or \"held\") and force (µN), as {{ t = {}, \
                 force = 0.5 }}",
                self.t
            )),
        }
    }
}

/// The checks on a protocol's rows, errors naming the row (1-based): times finite, from 0 and
/// in order; a change of control only as two rows at one time (and not two rows at one time
/// with the same control); no `"held"` first row; no force ≤ 0 (a plate or a tool cannot pull).
pub(crate) fn check(key: &str, rows: &[ProtocolRow]) -> Result<(), String> {
    if rows.is_empty() {
        return Err(format!("{key}: no rows; give at least one, as [{{ t = 0, displacement = 0.0 }}]"));
    }
    let mut prev: Option<(f64, Control)> = None;
    for (i, row) in rows.iter().enumerate().map(|(i, r)| (i + 1, r)) {
        let c = row.control(key, i)?;
        if !(row.t.is_finite() && row.t >= 0.0) {
            return Err(format!("{key} row {i}: time {} s must be finite and ≥ 0", row.t));
        }
        match c {
            Control::Force(f) if !(f.is_finite() && f > 0.0) => {
                let who = if key.starts_with("plates") { "a plate" } else { "a tool" };
                return Err(format!(
                    "{key} row {i}: force = {f} µN: {who} cannot pull (forces are compressive, > 0); use a \
                     displacement row to lift it"
                ));
            }
            Control::Displacement(Some(d)) if !d.is_finite() => {
                return Err(format!("{key} row {i}: displacement = {d} must be finite (µm)"))
            }
            Control::Displacement(None) if prev.is_none() => {
                return Err(format!(
                    "{key} row 1: displacement = \"held\" holds the position reached under force control; the \
                     first row gives a value (µm)"
                ))
            }
            _ => {}
        }
        if let Some((t0, c0)) = prev {
            let switch = std::mem::discriminant(&c0) != std::mem::discriminant(&c);
            if row.t < t0 {
                return Err(format!(
                    "{key} row {i}: time {} s comes before row {}'s {t0} s (rows in increasing time)",
                    row.t,
                    i - 1
                ));
            }
            if row.t == t0 && !switch {
                return Err(format!(
                    "{key} rows {} and {i}: two rows at {t0} s with the same control (a switch is two rows at one \
                     time with different controls)",
                    i - 1
                ));
            }
            if row.t > t0 && switch {
                return Err(format!(
                    "{key} row {i}: the control changes between {t0} s and {} s; a switch is two rows at one time \
                     (add a row at {t0} s or at {} s)",
                    row.t, row.t
                ));
            }
            if matches!(c, Control::Displacement(None)) && !switch {
                return Err(format!(
                    "{key} row {i}: displacement = \"held\" only right after force control, at the switch's time"
                ));
            }
        }
        prev = Some((row.t, c));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(text: &str) -> Vec<ProtocolRow> {
        #[derive(Deserialize)]
        struct W {
            p: Vec<ProtocolRow>,
        }
        toml::from_str::<W>(&format!("p = {text}")).unwrap().p
    }

    #[test]
    fn a_ramp_then_a_force_hold_passes() {
        let r = rows("[{t = 0, displacement = 0.0}, {t = 5, displacement = 20.0}, {t = 5, force = 0.5}, {t = 60, force = 0.5}, {t = 60, displacement = \"held\"}]");
        assert_eq!(check("plates.upper", &r), Ok(()));
        assert_eq!(r[4].control("k", 5), Ok(Control::Displacement(None)));
    }

    #[test]
    fn bad_rows_are_named() {
        let cases = [
            ("[{t = 0, force = -1.0}]", "row 1: force = -1 µN: a plate cannot pull"),
            ("[{t = 0, force = 0.0}]", "cannot pull"),
            (
                "[{t = 0, displacement = 0.0}, {t = 5, displacement = 1.0}, {t = 3, displacement = 2.0}]",
                "row 3: time 3 s comes before row 2's 5 s",
            ),
            ("[{t = 0, displacement = 0.0}, {t = 5, force = 1.0}]", "row 2: the control changes between 0 s and 5 s"),
            ("[{t = 0, displacement = 0.0}, {t = 0, displacement = 1.0}]", "rows 1 and 2: two rows at 0 s"),
            ("[{t = 0, displacement = \"held\"}]", "row 1: displacement = \"held\""),
            ("[{t = 0, displacement = 0.0, force = 1.0}]", "row 1: give exactly one"),
            ("[{t = 0}]", "row 1: give exactly one"),
            ("[]", "no rows"),
        ];
        for (text, want) in cases {
            let e = check("plates.upper", &rows(text)).unwrap_err();
            assert!(e.contains(want), "{text}: {e}");
        }
    }
}
