//! The declaration of a scene key: its dotted name, unit, default, valid range, further rules,
//! a one-line description and where it enters the model. Each section file declares its keys
//! next to its serde types and checks the ranges through them, so a range lives in one place;
//! [`super::reference`] writes every section's table as the scene reference
//! (`docs/scene-reference.md`), and [`super::explain`] annotates a scene with them.

use crate::range::Range;

/// One key of a scene file.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Key {
    /// Dotted path (`time.dt`, `material.remodelling.lambda_p`; `bc.group` for `[[bc]]` entries).
    pub(crate) name: &'static str,
    /// Unit ("" for dimensionless numbers, flags and names).
    pub(crate) unit: &'static str,
    /// What the key is when the scene leaves it out.
    pub(crate) default: Unset,
    /// The interval a number must lie in (None: not a number, or a rule below).
    pub(crate) range: Option<Range>,
    /// What else is checked: choices, rules between keys.
    pub(crate) rule: &'static str,
    /// What the key sets, in one line.
    pub(crate) doc: &'static str,
    /// Where it enters the model or the numerics, if more precise than its section's
    /// (`eq. (56)`, `numerics.md: Pressure stabilisation`).
    pub(crate) enters: &'static str,
}

/// What a key is when the scene leaves it out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Unset {
    /// The scene must give it.
    Required,
    /// Nothing: the words say what that means (may be empty).
    Absent(&'static str),
    /// This value, written as TOML (tested against serde's default).
    Value(&'static str),
}

impl Key {
    /// A key with no range or rule.
    pub(crate) const fn new(name: &'static str, unit: &'static str, default: Unset, doc: &'static str) -> Key {
        Key { name, unit, default, range: None, rule: "", doc, enters: "" }
    }

    /// The same key with a valid range.
    pub(crate) const fn range(self, range: Range) -> Key {
        Key { range: Some(range), ..self }
    }

    /// The same key with where it enters the model (more precisely than its section).
    pub(crate) const fn enters(self, enters: &'static str) -> Key {
        Key { enters, ..self }
    }

    /// The same key with a rule in words.
    pub(crate) const fn rule(self, rule: &'static str) -> Key {
        Key { rule, ..self }
    }

    /// Ok, or "name = v: what it must be" (a key without a range accepts anything).
    pub(crate) fn check(&self, v: f64) -> Result<(), String> {
        self.check_as(self.name, v)
    }

    /// As [`Key::check`] for a count, shown as an integer.
    pub(crate) fn check_count(&self, n: usize) -> Result<(), String> {
        self.range.map_or(Ok(()), |r| r.check_shown(self.name, n as f64, n))
    }

    /// As [`Key::check`], with the message naming `label` (an entry of a list, say).
    pub(crate) fn check_as(&self, label: &str, v: f64) -> Result<(), String> {
        self.range.map_or(Ok(()), |r| r.check(label, v))
    }
}

/// A section of the reference: its title, the doc section its keys enter (docs/…), a sentence,
/// its keys.
pub(crate) struct Section {
    pub(crate) title: &'static str,
    pub(crate) enters: &'static str,
    pub(crate) about: &'static str,
    pub(crate) keys: &'static [Key],
}
