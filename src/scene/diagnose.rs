//! Messages for scene files that TOML or serde reject: the line and key of the error (serde
//! loses the key inside tagged enums such as `[material]`, so it is found by removing values
//! until the error changes), serde's Rust type names in words, and the `--set` override to blame.

use super::overrides;
use super::sections::Scene;

/// The scene of a TOML table (the file with `--set` overrides applied).
pub(super) fn from_table(table: &toml::Table) -> std::result::Result<Scene, toml::de::Error> {
    toml::Value::Table(table.clone()).try_into()
}

/// The message of a scene that cannot be read once its overrides are applied: "--set SPEC:
/// message" for the override without which the error goes away or changes (the last such), else
/// the scene file's own error (`toml_message`).
pub(super) fn override_message(text: &str, file: &toml::Table, specs: &[String], e: &toml::de::Error) -> String {
    let msg = plain(e.message().trim());
    for skip in (0..specs.len()).rev() {
        let mut t = file.clone();
        for (_, spec) in specs.iter().enumerate().filter(|(i, _)| *i != skip) {
            // An override that no longer applies without the skipped one changes the error too.
            if overrides::apply(&mut t, spec).is_err() {
                return format!("--set {}: {msg}", specs[skip]);
            }
        }
        let same = matches!(from_table(&t), Err(e2) if plain(e2.message().trim()) == msg);
        if !same {
            return format!("--set {}: {msg}", specs[skip]);
        }
    }
    match toml::from_str::<Scene>(text) {
        Err(fe) => toml_message(text, &fe),
        Ok(_) => format!("with the overrides --set {}: {msg}", specs.join(" --set ")),
    }
}

/// The dotted key of the value a serde type error ("invalid type: sequence, expected a number")
/// or unknown choice ("unknown variant `40c`, expected one of `40b`, `40a`, `40b_tau`") is about — serde loses
/// it inside tagged enums such as `[material]`: of the values of that kind (or that string),
/// the one whose removal changes the error (the innermost, if a table and its value both do).
/// None unless exactly one.
fn culprit_key(table: &toml::Table, msg: &str) -> Option<String> {
    // The values the error can be about: of the kind it names, or the string it names.
    let suspect: Box<dyn Fn(&toml::Value) -> bool> = if let Some(kind) = msg.strip_prefix("invalid type: ") {
        Box::new(move |v| kind.starts_with(serde_kind(v)))
    } else {
        let variant = unknown_variant(msg)?;
        Box::new(move |v| v.as_str() == Some(variant))
    };
    let base = plain(from_table(table).err()?.message().trim());
    fn collect(
        v: &toml::Value,
        path: &mut Vec<String>,
        suspect: &dyn Fn(&toml::Value) -> bool,
        out: &mut Vec<Vec<String>>,
    ) {
        let children: Vec<(String, &toml::Value)> = match v {
            toml::Value::Table(t) => t.iter().map(|(k, v)| (k.clone(), v)).collect(),
            toml::Value::Array(a) => a.iter().enumerate().map(|(i, v)| (i.to_string(), v)).collect(),
            _ => return,
        };
        for (k, child) in children {
            path.push(k);
            if suspect(child) {
                out.push(path.clone());
            }
            collect(child, path, suspect, out);
            path.pop();
        }
    }
    fn remove(v: &mut toml::Value, path: &[String]) {
        let Some((first, rest)) = path.split_first() else { return };
        let child = match v {
            toml::Value::Table(t) if rest.is_empty() => {
                t.remove(first);
                return;
            }
            toml::Value::Array(a) if rest.is_empty() => {
                if let Ok(i) = first.parse::<usize>() {
                    if i < a.len() {
                        a.remove(i);
                    }
                }
                return;
            }
            toml::Value::Table(t) => t.get_mut(first),
            toml::Value::Array(a) => first.parse::<usize>().ok().and_then(|i| a.get_mut(i)),
            _ => None,
        };
        if let Some(c) = child {
            remove(c, rest);
        }
    }
    let mut candidates = Vec::new();
    collect(&toml::Value::Table(table.clone()), &mut Vec::new(), suspect.as_ref(), &mut candidates);
    let culprits: Vec<Vec<String>> = candidates
        .into_iter()
        .filter(|p| {
            let mut v = toml::Value::Table(table.clone());
            remove(&mut v, p);
            let toml::Value::Table(t) = v else { return false };
            !matches!(from_table(&t), Err(e) if plain(e.message().trim()) == base)
        })
        .collect();
    let innermost: Vec<&Vec<String>> =
        culprits.iter().filter(|p| !culprits.iter().any(|q| q.len() > p.len() && q.starts_with(p))).collect();
    match innermost[..] {
        [p] => Some(p.join(".")),
        _ => None,
    }
}

/// The field a "missing field `X`" error names.
fn missing_field(msg: &str) -> Option<&str> {
    msg.strip_prefix("missing field `")?.split_once('`').map(|(f, _)| f)
}

/// The choice an "unknown variant `X`, expected ..." error names.
fn unknown_variant(msg: &str) -> Option<&str> {
    msg.strip_prefix("unknown variant `")?.split_once('`').map(|(v, _)| v)
}

/// serde's name of the kind of a TOML value (as in "invalid type: <kind>").
fn serde_kind(v: &toml::Value) -> &'static str {
    match v {
        toml::Value::String(_) => "string",
        toml::Value::Integer(_) => "integer",
        toml::Value::Float(_) => "floating point",
        toml::Value::Boolean(_) => "boolean",
        toml::Value::Datetime(_) => "datetime",
        toml::Value::Array(_) => "sequence",
        toml::Value::Table(_) => "map",
    }
}

/// A TOML error on one line: "line N (`text`): message" (the parser's own text spans lines).
/// A type error or an unknown choice names its key: "line N (`text`): material.phi_s: message"
/// — serde loses the key inside tagged enums such as `[material]`, and reports the whole table;
/// then the key is found by [`culprit_key`] and the line is its `key = value` line in the table
/// (or, failing that, the one line of the table whose value has that type, or holds that
/// choice as a string).
pub(crate) fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let msg = plain(&e.message().replace('\n', " "));
    // A field missing at the top level has an empty span at the start, which is no line of it.
    if let (Some(field), Some(std::ops::Range { start: 0, end: 0 })) = (missing_field(&msg), e.span()) {
        return match field {
            "mesh" | "material" | "time" => {
                format!("missing section [{field}] (every scene has [mesh], [material] and [time])")
            }
            _ => format!("missing key `{field}` at the top level"),
        };
    }
    match e.span() {
        Some(span) => {
            let start = span.start.min(text.len());
            let mut line = text[..start].matches('\n').count() + 1;
            let region = &text[start..span.end.clamp(start, text.len())];
            let key = toml::from_str::<toml::Table>(text).ok().and_then(|t| culprit_key(&t, &msg));
            let name = key.as_deref().map(|k| k.rsplit('.').next().unwrap_or(k));
            let at = name.and_then(|n| {
                region.lines().position(|l| l.split_once('=').is_some_and(|(k, _)| k.trim().trim_matches('"') == n))
            });
            if let Some(i) = at {
                line += i;
            } else if let Some(kind) = msg.strip_prefix("invalid type: ") {
                let hits: Vec<usize> = region
                    .lines()
                    .enumerate()
                    .filter(|(_, l)| value_kind(l).is_some_and(|k| kind.starts_with(k)))
                    .map(|(i, _)| i)
                    .collect();
                if let [i] = hits[..] {
                    line += i;
                }
            } else if let Some(v) = unknown_variant(&msg) {
                let quoted = [format!("\"{v}\""), format!("'{v}'")];
                let hits: Vec<usize> = region
                    .lines()
                    .enumerate()
                    .filter(|(_, l)| quoted.iter().any(|q| l.contains(q.as_str())))
                    .map(|(i, _)| i)
                    .collect();
                if let [i] = hits[..] {
                    line += i;
                }
            }
            let what = text.lines().nth(line - 1).unwrap_or("").trim();
            match key {
                Some(k) => format!("line {line} (`{what}`): {k}: {msg}"),
                None => format!("line {line} (`{what}`): {msg}"),
            }
        }
        None => msg,
    }
}

/// serde's Rust type names in words: "expected usize" → "expected a non-negative integer".
fn plain(msg: &str) -> String {
    let mut m = msg.to_string();
    for (rust, words) in [
        ("expected usize", "expected a non-negative integer"),
        ("expected u64", "expected a non-negative integer"),
        ("expected u32", "expected a non-negative integer"),
        ("expected i64", "expected an integer"),
        ("expected i32", "expected an integer"),
        ("expected f64", "expected a number"),
    ] {
        if let Some(rest) = m.strip_suffix(rust) {
            m = format!("{rest}{words}");
        }
    }
    m
}

/// The serde name of the kind of value on a `key = value` line (None for other lines).
fn value_kind(line: &str) -> Option<&'static str> {
    let (key, value) = line.split_once('=')?;
    let (key, v) = (key.trim(), value.trim());
    if key.is_empty() || key.starts_with(['#', '[']) {
        return None;
    }
    Some(match v.chars().next()? {
        '[' => "sequence",
        '{' => "map",
        '"' | '\'' => "string",
        't' | 'f' if v.starts_with("true") || v.starts_with("false") => "boolean",
        _ if v.split(['#', ' ']).next().is_some_and(|n| n.parse::<i64>().is_ok()) => "integer",
        _ => "floating point",
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_type_error_in_a_tagged_table_names_its_line() {
        let text = "name = \"x\"\n[mesh]\ngeo = \"column.geo\"\n[material]\nmodel = \"linear\"\nmu = [1]\nnu = 0.2\n";
        let e = toml::from_str::<Scene>(text).expect_err("mu is not a number");
        let m = toml_message(text, &e);
        assert_eq!(m, "line 6 (`mu = [1]`): material.mu: invalid type: sequence, expected a number");
        // Two values of that kind in the table: the key is the one whose removal changes the error.
        let text = "[mesh]\ngeo = \"g\"\n[material]\nmodel = \"holmes_mow\"\nmu = 20.0\nnu = 0.2\n\
                    phi_s = [0.6]\nk0 = 1.0\nkappa = 1.0\nm0 = 0.1\ngravity = [0.0, 0.0, -9.81]\n";
        let e = toml::from_str::<Scene>(text).expect_err("phi_s is not a number");
        let m = toml_message(text, &e);
        assert_eq!(m, "line 7 (`phi_s = [0.6]`): material.phi_s: invalid type: sequence, expected a number");
        assert_eq!(value_kind("nu = 0.2  # comment"), Some("floating point"));
        assert_eq!(value_kind("n = 3"), Some("integer"));
        assert_eq!(value_kind("drained = true"), Some("boolean"));
        assert_eq!(value_kind("[material]"), None);
    }

    #[test]
    fn an_unknown_choice_names_its_key_line_and_the_choices() {
        let text = "[mesh]\ngeo = \"g\"\n[material]\nmodel = \"holmes_mow\"\nmu = 20.0\nnu = 0.2\nphi_s = 0.6\n\
                    k0 = 1.0\nkappa = 1.0\nm0 = 0.1\nremodelling = { lambda_p = 0.001, sigma_y = 2.0, form = \"40c\" }\n";
        let e = toml::from_str::<Scene>(text).expect_err("40c is no flow rule");
        assert_eq!(
            toml_message(text, &e),
            "line 11 (`remodelling = { lambda_p = 0.001, sigma_y = 2.0, form = \"40c\" }`): material.remodelling.form: \
             unknown variant `40c`, expected one of `40b`, `40a`, `40b_tau`"
        );
    }

    #[test]
    fn a_missing_section_is_named_without_a_line() {
        let text = "# My aggregate\n[mesh]\ngeo = \"g\"\n[time]\nt_end = 1.0\ndt = 0.1\n";
        let e = toml::from_str::<Scene>(text).expect_err("no [material]");
        assert_eq!(
            toml_message(text, &e),
            "missing section [material] (every scene has [mesh], [material] and [time])"
        );
        // A key missing in a table is at that table's line.
        let text = "# c\n[mesh]\ngeo = \"g\"\n[material]\nmodel = \"linear\"\nmu = 1.0\nnu = 0.2\n\
                    permeability = 1.0\n[time]\nt_end = 1.0\n";
        let e = toml::from_str::<Scene>(text).expect_err("no time.dt");
        assert_eq!(toml_message(text, &e), "line 9 (`[time]`): missing field `dt`");
    }
}
