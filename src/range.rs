//! The valid range of a scalar parameter, declared once and checked where the value is read:
//! a scene's key table (`scene`) and the law that takes the value (`material`) check the same
//! declaration, and the message names the parameter, its value and the range in words.

use std::fmt;

/// An interval of finite numbers (open or closed at either end), with the words an error says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Range {
    lo: f64,
    lo_closed: bool,
    hi: f64,
    hi_closed: bool,
    /// What a value outside must be, after "key = value: " ("must be positive").
    says: &'static str,
}

impl Range {
    /// Any finite number.
    pub(crate) const FINITE: Range = Range::new(f64::NEG_INFINITY, false, f64::INFINITY, false, "must be finite");
    /// (0, ∞).
    pub(crate) const POSITIVE: Range = Range::new(0.0, false, f64::INFINITY, false, "must be positive");
    /// [0, ∞).
    pub(crate) const NON_NEGATIVE: Range = Range::new(0.0, true, f64::INFINITY, false, "must be finite and >= 0");

    /// From `lo` to `hi`, each end included if `*_closed`; an infinite end is always open.
    pub(crate) const fn new(lo: f64, lo_closed: bool, hi: f64, hi_closed: bool, says: &'static str) -> Range {
        Range { lo, lo_closed, hi, hi_closed, says }
    }

    /// The same interval with other words.
    pub(crate) const fn says(self, says: &'static str) -> Range {
        Range { says, ..self }
    }

    /// Whether `v` is finite and inside.
    pub(crate) fn contains(&self, v: f64) -> bool {
        let above = if self.lo_closed { v >= self.lo } else { v > self.lo };
        let below = if self.hi_closed { v <= self.hi } else { v < self.hi };
        v.is_finite() && above && below
    }

    /// Ok, or "`name` = `v`: `says`".
    pub(crate) fn check(&self, name: &str, v: f64) -> Result<(), String> {
        self.check_shown(name, v, v)
    }

    /// As [`Range::check`], with the value shown as `shown` (an integer as given).
    pub(crate) fn check_shown(&self, name: &str, v: f64, shown: impl fmt::Display) -> Result<(), String> {
        if self.contains(v) {
            Ok(())
        } else {
            Err(format!("{name} = {shown}: {}", self.says))
        }
    }
}

impl fmt::Display for Range {
    /// Interval notation: "(0, 1]", "[1, ∞)"; "finite" for the whole line.
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let end =
            |v: f64| if v.is_infinite() { format!("{}∞", if v < 0.0 { "−" } else { "" }) } else { v.to_string() };
        if self.lo.is_infinite() && self.hi.is_infinite() {
            return f.write_str("finite");
        }
        let open = if self.lo_closed && self.lo.is_finite() { '[' } else { '(' };
        let close = if self.hi_closed && self.hi.is_finite() { ']' } else { ')' };
        write!(f, "{open}{}, {}{close}", end(self.lo), end(self.hi))
    }
}

#[cfg(test)]
mod tests {
    use super::Range;

    #[test]
    fn ends_and_words() {
        let unit = Range::new(0.0, true, 1.0, false, "must lie in [0, 1)");
        assert!(unit.contains(0.0) && unit.contains(0.5) && !unit.contains(1.0) && !unit.contains(f64::NAN));
        assert_eq!(unit.to_string(), "[0, 1)");
        assert_eq!(unit.check("plates.compression", 1.0).unwrap_err(), "plates.compression = 1: must lie in [0, 1)");
        assert_eq!(Range::POSITIVE.to_string(), "(0, ∞)");
        assert_eq!(Range::NON_NEGATIVE.to_string(), "[0, ∞)");
        assert_eq!(Range::FINITE.to_string(), "finite");
        assert!(!Range::POSITIVE.contains(0.0) && !Range::POSITIVE.contains(f64::INFINITY));
        assert!(!Range::FINITE.contains(f64::NEG_INFINITY) && Range::FINITE.contains(-1e300));
        assert_eq!(
            Range::FINITE.check("material.kappa", f64::NAN).unwrap_err(),
            "material.kappa = NaN: must be finite"
        );
        let degree = Range::new(1.0, true, 8.0, true, "use 1..8");
        assert_eq!(
            degree.check_shown("fem.quadrature_degree", 9.0, 9usize).unwrap_err(),
            "fem.quadrature_degree = 9: use 1..8"
        );
    }
}
