//! The program's own `-poroplast_*` options, read from PETSc's options database (so they are
//! given like PETSc's: `-- -poroplast_chord 0.5`). A value that does not parse is an error
//! naming the option, the value and what it expects.

use crate::error::{Error, Result};
use crate::petsc::options;

/// `-name V` parsed by `parse` (None: not what the option `expects`); `default` without it.
pub(crate) fn value<T>(name: &str, default: T, expects: &str, parse: impl Fn(&str) -> Option<T>) -> Result<T> {
    Ok(optional(name, None, expects, parse)?.unwrap_or(default))
}

/// `-name [V]`: None without it, `bare` when given without a value (if that is allowed), else
/// the value parsed by `parse`.
pub(crate) fn optional<T>(
    name: &str,
    bare: Option<T>,
    expects: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Option<T>> {
    let Some(v) = options::get_string(name)? else { return Ok(None) };
    let parsed = match bare {
        Some(b) if v.is_empty() => Some(b),
        _ => parse(&v),
    };
    parsed.map(Some).ok_or_else(|| Error::Options(format!("-{name} {v}: expected {expects}")))
}

/// `-name N`, a count (a non-negative integer); `default` without it.
pub(crate) fn count(name: &str, default: usize) -> Result<usize> {
    value(name, default, "a non-negative integer", |v| v.parse().ok())
}

/// `-name [1|0]` (also true/false, yes/no; on when given without a value); `default` without it.
pub(crate) fn switch(name: &str, default: bool, expects: &str) -> Result<bool> {
    Ok(optional(name, Some(true), expects, |v| match v {
        "1" | "true" | "yes" => Some(true),
        "0" | "false" | "no" => Some(false),
        _ => None,
    })?
    .unwrap_or(default))
}
