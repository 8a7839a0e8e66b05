//! Line and token cursors over an MSH text, with 1-based line numbers for error messages.

use std::path::Path;
use std::str::{FromStr, SplitAsciiWhitespace};

use crate::error::{Error, Result};

/// Line cursor with 1-based line numbers for error messages.
pub(super) struct Lines<'a> {
    pub(super) it: std::str::Split<'a, char>,
    pub(super) no: usize,
    pub(super) path: &'a Path,
}

impl<'a> Lines<'a> {
    pub(super) fn new(path: &'a Path, text: &'a str) -> Self {
        // A final newline ends the last line rather than starting an empty one.
        let text = text.strip_suffix('\n').unwrap_or(text);
        Lines { it: text.split('\n'), no: 0, path }
    }

    /// Next line, trimmed, or `None` at end of file.
    pub(super) fn next_opt(&mut self) -> Option<&'a str> {
        let l = self.it.next()?;
        self.no += 1;
        Some(l.trim())
    }

    /// Next line; end of file is an error mentioning what was expected.
    pub(super) fn next(&mut self, what: &str) -> Result<&'a str> {
        self.next_opt()
            .ok_or_else(|| self.err(format!("unexpected end of file while reading {what} (truncated file?)")))
    }

    pub(super) fn err(&self, msg: impl std::fmt::Display) -> Error {
        Error::mesh(self.path, format!("line {}: {msg}", self.no))
    }

    /// Parse exactly `N` integers from the next line.
    pub(super) fn ints<T: FromStr + Copy + Default, const N: usize>(&mut self, what: &str) -> Result<[T; N]> {
        let line = self.next(what)?;
        let mut out = [T::default(); N];
        let mut toks = line.split_ascii_whitespace();
        let mut n = 0;
        for tok in toks.by_ref() {
            if n == N {
                n += 1;
                break;
            }
            out[n] = tok.parse().map_err(|_| self.expected(N, "integers", what, line))?;
            n += 1;
        }
        if n != N {
            return Err(self.expected(N, "integers", what, line));
        }
        Ok(out)
    }

    pub(super) fn expected(&self, n: usize, kind: &str, what: &str, line: &str) -> Error {
        self.err(format!("expected {n} {kind} ({what}), got \"{}\"", shorten(line)))
    }

    /// Consume the `$End...` line closing a section.
    pub(super) fn end(&mut self, tag: &str) -> Result<()> {
        let l = self.next(tag)?;
        if l != tag {
            return Err(
                self.err(format!("expected {tag}, got \"{}\" (count in the section header too small?)", shorten(l)))
            );
        }
        Ok(())
    }
}

/// Tokens of one line, parsed on demand with errors pointing at the line.
pub(super) struct Toks<'a> {
    pub(super) it: SplitAsciiWhitespace<'a>,
    line: &'a str,
}

impl<'a> Toks<'a> {
    pub(super) fn new(line: &'a str) -> Self {
        Toks { it: line.split_ascii_whitespace(), line }
    }

    pub(super) fn get<T: FromStr>(&mut self, lines: &Lines, what: &str) -> Result<T> {
        let tok = self.it.next();
        tok.and_then(|t| t.parse().ok()).ok_or_else(|| {
            lines.err(format!(
                "expected {what}, got {} in \"{}\"",
                tok.map_or("end of line".to_string(), |t| format!("\"{}\"", shorten(t))),
                shorten(self.line)
            ))
        })
    }

    /// Fails if anything is left on the line.
    pub(super) fn finish(&mut self, lines: &Lines, what: &str) -> Result<()> {
        match self.it.next() {
            None => Ok(()),
            Some(t) => {
                Err(lines.err(format!("unexpected \"{}\" after {what} in \"{}\"", shorten(t), shorten(self.line))))
            }
        }
    }
}

pub(super) fn shorten(s: &str) -> String {
    const MAX: usize = 80;
    if s.len() <= MAX {
        s.to_string()
    } else {
        let mut end = MAX;
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        format!("{}...", &s[..end])
    }
}
