//! `--set KEY=VALUE`: overrides any scene key by its dotted path.
//!
//! The value is read as a TOML value (`70e9`, `[1, 2, 3]`, `"text"`, `true`); a bare word that
//! is not valid TOML (such as `auto`) is taken as a string. Whether the key exists is decided
//! when the overridden table is read into a [`super::Scene`], so an unknown path is an error
//! there, with the allowed keys listed.

/// Applies one `KEY=VALUE` override to a scene table. The error is a sentence without the
/// file name.
pub fn apply_override(table: &mut toml::Table, assignment: &str) -> Result<(), String> {
    let Some((key, value)) = assignment.split_once('=') else {
        return Err(format!(
            "--set {assignment}: expected KEY=VALUE, for example --set material.young=70e9"
        ));
    };
    let key = key.trim();
    let value = parse_value(value.trim());
    let parts: Vec<&str> = key.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(format!(
            "--set {assignment}: `{key}` is not a dotted key path such as material.young"
        ));
    }
    let (last, parents) = parts.split_last().expect("split gives at least one part");
    let mut node = table;
    let mut walked = String::new();
    for p in parents {
        if !walked.is_empty() {
            walked.push('.');
        }
        walked.push_str(p);
        let entry = node
            .entry(p.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        node = match entry {
            toml::Value::Table(t) => t,
            _ => {
                return Err(format!(
                    "--set {key}: `{walked}` is a value, not a table, so it has no key `{}`",
                    &key[walked.len() + 1..]
                ));
            }
        };
    }
    node.insert(last.to_string(), value);
    Ok(())
}

fn parse_value(text: &str) -> toml::Value {
    let doc = format!("v = {text}");
    match doc.parse::<toml::Table>() {
        Ok(mut t) => t
            .remove("v")
            .unwrap_or_else(|| toml::Value::String(text.into())),
        Err(_) => toml::Value::String(text.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_nested_number_and_creates_tables() {
        let mut t: toml::Table = "[material]\nyoung = 1.0\n".parse().unwrap();
        apply_override(&mut t, "material.young=70e9").unwrap();
        apply_override(&mut t, "gravity.acceleration=[0, 0, -1]").unwrap();
        apply_override(&mut t, "time.dt=auto").unwrap();
        assert_eq!(t["material"]["young"].as_float(), Some(70e9));
        assert_eq!(t["gravity"]["acceleration"].as_array().unwrap().len(), 3);
        assert_eq!(t["time"]["dt"].as_str(), Some("auto"));
    }

    #[test]
    fn rejects_missing_equals_and_value_as_table() {
        let mut t: toml::Table = "name = \"x\"\n".parse().unwrap();
        assert!(apply_override(&mut t, "material.young").is_err());
        assert!(apply_override(&mut t, "name.first=1").is_err());
    }
}
