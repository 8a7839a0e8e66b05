//! `--set KEY=VALUE`: typed overrides of a scene's values from the command line (parameter
//! studies without editing TOML). KEY is a dotted path into the scene (`material.lambda_p`,
//! `mesh.params.h`, `plates.compression`; `bc.0.group` for the first `[[bc]]`); VALUE is a TOML
//! value (`0.5`, `true`, `[0.0, 0.0, -9.81]`, `"text"`), and a bare word is a string
//! (`material.model=holmes_mow`). The result is validated like the file itself.

/// Sets `spec` ("KEY=VALUE") in `root`; the message names the override and what is wrong.
pub(crate) fn apply(root: &mut toml::Table, spec: &str) -> Result<(), String> {
    let err = |m: String| format!("--set {spec}: {m}");
    let (key, text) = spec.split_once('=').ok_or_else(|| err("expected KEY=VALUE".into()))?;
    let path: Vec<&str> = key.trim().split('.').collect();
    if path.iter().any(|p| p.is_empty()) {
        return Err(err(format!("`{}` is not a dotted key like material.mu", key.trim())));
    }
    let value = parse_value(text.trim()).map_err(err)?;
    let Some((last, parents)) = path.split_last() else {
        return Err(err("expected KEY=VALUE".into()));
    };
    let mut here = Slot::Table(root);
    for (i, part) in parents.iter().enumerate() {
        let at = path[..=i].join(".");
        here = match here {
            Slot::Table(t) => match t.entry(part.to_string()).or_insert_with(|| toml::Table::new().into()) {
                toml::Value::Table(t) => Slot::Table(t),
                toml::Value::Array(a) => Slot::Array(a),
                _ => return Err(err(format!("`{at}` is a value, not a table"))),
            },
            Slot::Array(a) => {
                let n = a.len();
                let idx: usize = part.parse().map_err(|_| err(format!("`{at}`: an index into a list is a number")))?;
                match a.get_mut(idx) {
                    Some(toml::Value::Table(t)) => Slot::Table(t),
                    Some(toml::Value::Array(a)) => Slot::Array(a),
                    Some(_) => return Err(err(format!("`{at}` is a value, not a table"))),
                    None => return Err(err(format!("`{at}`: index out of range ({n} entries)"))),
                }
            }
        };
    }
    match here {
        Slot::Table(t) => {
            if parents == ["material"] && super::material::MODULI.contains(last) {
                // One modulus: the one given replaces the scene's.
                t.retain(|k, _| !super::material::MODULI.contains(&k));
            }
            if parents == ["plates"] && *last == "table" {
                // One protocol: a table replaces the scene's phases.
                t.retain(|k, _| !super::plates::PHASE_KEYS.contains(&k));
            }
            if parents == ["plates"] && super::plates::PHASE_KEYS.contains(last) && t.contains_key("table") {
                return Err(err(
                    "this scene's protocol is a plates.table, which the phases cannot change: override the \
                                table (--set 'plates.table=[[0, 0], [5, 0.2], [65, 0.2], [70, 0]]': rows [t (s), ũ]), \
                                which replaces it"
                        .into(),
                ));
            }
            t.insert(last.to_string(), value);
        }
        Slot::Array(a) => {
            let n = a.len();
            let idx: usize = last.parse().map_err(|_| err(format!("`{key}`: an index into a list is a number")))?;
            *a.get_mut(idx).ok_or_else(|| err(format!("`{key}`: index out of range ({n} entries)")))? = value;
        }
    }
    Ok(())
}

enum Slot<'a> {
    Table(&'a mut toml::Table),
    Array(&'a mut Vec<toml::Value>),
}

/// A TOML value; a bare word (not a number, boolean, array, table or quoted string) is a string.
fn parse_value(text: &str) -> Result<toml::Value, String> {
    if text.is_empty() {
        return Err("empty value".into());
    }
    match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(mut t) => t.remove("v").ok_or_else(|| format!("`{text}` is not a single TOML value")),
        Err(e) => {
            let word = text.chars().all(|c| c.is_alphanumeric() || "_-./".contains(c));
            let mut chars = text.chars();
            let numeric = match chars.next() {
                Some('+' | '-') | Some('0'..='9') => true,
                Some('.') => chars.next().is_some_and(|c| c.is_ascii_digit()),
                _ => false,
            };
            match (word, numeric) {
                (true, false) => Ok(toml::Value::String(text.into())),
                (true, true) => Err(format!("`{text}` is not a valid number")),
                _ => Err(format!("`{text}` is not a TOML value ({})", e.message().replace('\n', " "))),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::apply;

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn overrides_set_typed_values_at_dotted_paths() {
        let mut t = table("[material]\nmu = 20.0\n[mesh]\nparams = { h = 20.0 }\n[[bc]]\ngroup = \"a\"\n");
        apply(&mut t, "material.mu=3.5").unwrap();
        apply(&mut t, "material.lambda_p = 0.5").unwrap();
        apply(&mut t, "mesh.params.h=10").unwrap();
        apply(&mut t, "bc.0.group=surface").unwrap();
        apply(&mut t, "material.gravity=[0.0, 0.0, -9.81]").unwrap();
        apply(&mut t, "output.fields=false").unwrap();
        assert_eq!(t["material"]["mu"].as_float(), Some(3.5));
        assert_eq!(t["material"]["lambda_p"].as_float(), Some(0.5));
        assert_eq!(t["mesh"]["params"]["h"].as_integer(), Some(10));
        assert_eq!(t["bc"][0]["group"].as_str(), Some("surface"));
        assert_eq!(t["material"]["gravity"].as_array().map(|a| a.len()), Some(3));
        assert_eq!(t["output"]["fields"].as_bool(), Some(false));
    }

    #[test]
    fn a_modulus_replaces_the_scenes() {
        let mut t = table("[material]\nmu = 20.0\nnu = 0.2\n");
        apply(&mut t, "material.drained_shear_modulus=1.5").unwrap();
        assert!(t["material"].get("mu").is_none());
        assert_eq!(t["material"]["drained_shear_modulus"].as_float(), Some(1.5));
        apply(&mut t, "material.drained_youngs_modulus=3.6").unwrap();
        assert!(t["material"].get("drained_shear_modulus").is_none());
        apply(&mut t, "material.mu=2.5").unwrap();
        let keys: Vec<&String> = t["material"].as_table().unwrap().keys().collect();
        assert_eq!(keys, ["mu", "nu"]);
    }

    #[test]
    fn malformed_overrides_are_named() {
        let mut t = table("[material]\nmu = 20.0\n[[bc]]\ngroup = \"a\"\n");
        for (spec, want) in [
            ("material.mu", "expected KEY=VALUE"),
            ("material..mu=1", "not a dotted key"),
            ("material.mu=", "empty value"),
            ("material.mu=1.2.3", "not a valid number"),
            ("material.mu.x=1", "`material.mu` is a value"),
            ("bc.3.group=x", "index out of range (1 entries)"),
            ("bc.first.group=x", "an index into a list is a number"),
            ("material.mu=[1, ", "not a TOML value"),
        ] {
            let e = apply(&mut t, spec).unwrap_err();
            assert!(e.starts_with(&format!("--set {spec}:")) && e.contains(want), "{spec}: {e}");
        }
    }
}
