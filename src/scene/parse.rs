//! TOML text to a typed scene, with errors that name the key.

use super::{COMMON_KEYS, Common, overrides};
use crate::error::{Error, Result};

/// The shared keys, typed, and every other top-level table as given (for the model).
pub(super) fn parse(
    text: &str,
    label: &str,
    overrides: &[String],
) -> Result<(Common, toml::Table)> {
    let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        let line = e
            .span()
            .map(|s| text[..s.start.min(text.len())].lines().count().max(1));
        let at = line.map(|l| format!(" at line {l}")).unwrap_or_default();
        Error::input(
            label,
            format!("is not valid TOML{at}: {}", first_line(e.message())),
        )
    })?;
    for o in overrides {
        overrides::apply_override(&mut table, o).map_err(|m| Error::input(label, m))?;
    }
    let overridden: Vec<String> = overrides
        .iter()
        .filter_map(|o| o.split_once('=').map(|(k, _)| k.trim().to_string()))
        .collect();
    let (common, tables): (toml::Table, toml::Table) = table
        .into_iter()
        .partition(|(k, _)| COMMON_KEYS.contains(&k.as_str()));
    let common = serde_path_to_error::deserialize(toml::Value::Table(common)).map_err(|e| {
        let path = e.path().to_string();
        let message = e.inner().message().to_string();
        Error::input(label, describe(&path, &message, &overridden))
    })?;
    Ok((common, tables))
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or(s).trim_end_matches('.')
}

/// Turns a serde message at `path` into one sentence naming the key.
pub fn describe(path: &str, message: &str, overridden: &[String]) -> String {
    let message = first_line(message);
    // The path of an unknown field already ends with it; that of a missing one does not.
    let join = |field: &str| {
        if path.is_empty() || path == "." {
            field.to_string()
        } else if path == field || path.ends_with(&format!(".{field}")) {
            path.to_string()
        } else {
            format!("{path}.{field}")
        }
    };
    let via = |key: &str| {
        let under = |k: &String| k == key || k.starts_with(&format!("{key}."));
        if overridden.iter().any(under) {
            " (given with --set)"
        } else {
            ""
        }
    };
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let (field, tail) = rest.split_once('`').unwrap_or((rest, ""));
        let key = join(field);
        let allowed = allowed_list(tail);
        return format!("unknown key `{key}`{}; {allowed}", via(&key));
    }
    if let Some(rest) = message.strip_prefix("missing field `") {
        let field = rest.split('`').next().unwrap_or(rest);
        let key = join(field);
        return format!("the required key `{key}` is missing");
    }
    if let Some(rest) = message.strip_prefix("unknown variant `") {
        let (value, tail) = rest.split_once('`').unwrap_or((rest, ""));
        return format!(
            "`{path}` = \"{value}\"{} is not allowed; {}",
            via(path),
            allowed_list(tail).replace("allowed keys", "allowed values")
        );
    }
    if let Some(rest) = message.strip_prefix("invalid type: ") {
        if let Some((found, expected)) = rest.split_once(", expected ") {
            // A named choice given as a number or a boolean: the TOML reader reports it as a
            // "unit variant" where "string only" was expected, which said nothing to a user.
            if found == "unit variant" || expected == "string only" {
                return format!(
                    "`{path}`{} has the wrong type: expected a string (one of the key's named \
                     values, in quotes), found a value that is not a string",
                    via(path)
                );
            }
            return format!(
                "`{path}`{} has the wrong type: expected {}, found {found}",
                via(path),
                plain_type(expected)
            );
        }
    }
    if let Some(rest) = message.strip_prefix("invalid length ") {
        if let Some((n, expected)) = rest.split_once(", expected ") {
            return format!(
                "`{path}`{} has {n} elements; expected {}",
                via(path),
                plain_type(expected)
            );
        }
    }
    if let Some(rest) = message.strip_prefix("invalid value: ") {
        if let Some((found, expected)) = rest.split_once(", expected ") {
            return format!(
                "`{path}`{} = {found} is not allowed; expected {expected}",
                via(path)
            );
        }
    }
    format!("`{path}`{}: {message}", via(path))
}

/// "expected one of `a`, `b`" -> "allowed keys: a, b".
fn allowed_list(tail: &str) -> String {
    let names: Vec<&str> = tail
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|s| !s.is_empty())
        .collect();
    if names.is_empty() {
        "this table takes no keys".to_string()
    } else {
        format!("allowed keys: {}", names.join(", "))
    }
}

fn plain_type(expected: &str) -> String {
    match expected {
        "f64" => "a number".to_string(),
        "u64" | "usize" | "u32" | "i64" => "a non-negative integer".to_string(),
        "a string" | "string" => "a string".to_string(),
        "a boolean" => "true or false".to_string(),
        other => other.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_field_names_key_and_allowed() {
        let m = describe(
            "material.youngg",
            "unknown field `youngg`, expected one of `young`, `poisson`",
            &[],
        );
        assert_eq!(
            m,
            "unknown key `material.youngg`; allowed keys: young, poisson"
        );
    }

    #[test]
    fn wrong_type_names_key() {
        let m = describe(
            "material.young",
            "invalid type: string \"abc\", expected f64",
            &[],
        );
        assert_eq!(
            m,
            "`material.young` has the wrong type: expected a number, found string \"abc\""
        );
    }
}
