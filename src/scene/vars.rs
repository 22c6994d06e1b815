//! Scene variables: a `[vars]` table of defaults, overridden with `-D name=value`
//! on the command line, and referenced in the file as a whole value `"$name"` or
//! inside a string as `"${name}"`.
//!
//! Substitution is textual and keeps every line where it was, so errors found
//! after substitution still point at the right line of the file.

use super::error::{line_of, SceneError};
use std::collections::BTreeMap;
use std::path::Path;

/// Applies `overrides` ("name=value") to the file's `[vars]` and substitutes every
/// reference. Returns the text to parse and the final variable values.
pub fn substitute(
    file: &Path,
    text: &str,
    overrides: &[String],
) -> Result<(String, BTreeMap<String, toml::Value>), SceneError> {
    let raw: toml::Table =
        toml::from_str(text).map_err(|e| SceneError::from_toml(file, text, &e))?;
    let mut vars: BTreeMap<String, toml::Value> = match raw.get("vars") {
        None => BTreeMap::new(),
        Some(toml::Value::Table(t)) => t.iter().map(|(k, v)| (k.clone(), v.clone())).collect(),
        Some(_) => {
            return Err(SceneError::new(
                file,
                None,
                "`vars` must be a table of name = value",
            ))
        }
    };
    for (k, o) in overrides.iter().enumerate() {
        let Some((name, value)) = o.split_once('=') else {
            return Err(SceneError::new(
                file,
                None,
                format!("variable override `{o}`: expected name=value"),
            ));
        };
        let name = name.trim();
        if let Some(first) = overrides[..k]
            .iter()
            .find(|p| override_name(p) == Some(name))
        {
            return Err(SceneError::new(
                file,
                None,
                format!(
                    "variable `{name}` is overridden twice (-D {} and -D {}): give it once",
                    crate::text::shorten(first, 80),
                    crate::text::shorten(o, 80)
                ),
            ));
        }
        if !vars.contains_key(name) {
            let known: Vec<&str> = vars.keys().map(|s| s.as_str()).collect();
            return Err(SceneError::new(
                file,
                None,
                format!(
                    "variable override `{o}`: the scene has no variable `{name}` (declare it in [vars]; known: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            ));
        }
        vars.insert(name.to_string(), parse_value(value.trim()));
    }

    let mut out = String::with_capacity(text.len());
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        out.push_str(&substitute_line(file, text, offset, line, &vars)?);
        offset += line.len();
    }
    Ok((out, vars))
}

/// The variable a `name=value` override sets.
fn override_name(o: &str) -> Option<&str> {
    o.split_once('=').map(|(n, _)| n.trim())
}

/// The overrides `base` with `extra` on top: an extra override replaces the
/// base's of the same variable (a study setting the variable it varies over
/// the user's `-D` of it), so that no variable is overridden twice.
pub fn merged_overrides(base: &[String], extra: &[String]) -> Vec<String> {
    let replaced = |o: &String| {
        extra
            .iter()
            .any(|e| override_name(e).is_some() && override_name(e) == override_name(o))
    };
    base.iter()
        .filter(|o| !replaced(o))
        .chain(extra)
        .cloned()
        .collect()
}

/// A -D value: TOML syntax if it parses (numbers, booleans, arrays, quoted
/// strings), otherwise the bare text as a string.
fn parse_value(s: &str) -> toml::Value {
    #[derive(serde::Deserialize)]
    struct V {
        v: toml::Value,
    }
    toml::from_str::<V>(&format!("v = {s}"))
        .map(|v| v.v)
        .unwrap_or_else(|_| toml::Value::String(s.to_string()))
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '-'
}

/// Substitutes one line, skipping comments; `offset` is the line's byte offset.
fn substitute_line(
    file: &Path,
    text: &str,
    offset: usize,
    line: &str,
    vars: &BTreeMap<String, toml::Value>,
) -> Result<String, SceneError> {
    let lookup = |name: &str, at: usize| {
        vars.get(name).ok_or_else(|| {
            SceneError::new(
                file,
                Some(line_of(text, offset + at)),
                format!("unknown variable `${name}` (declare it in [vars])"),
            )
        })
    };
    let b: Vec<char> = line.chars().collect();
    let mut out = String::with_capacity(line.len());
    let mut quote: Option<char> = None;
    let mut byte = 0; // byte offset of b[i] within the line
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        match quote {
            None if c == '#' => {
                out.extend(&b[i..]);
                break;
            }
            None if c == '"' || c == '\'' => {
                // A whole-value reference "$name" becomes the variable's TOML value.
                let mut j = i + 1;
                if j < b.len() && b[j] == '$' && j + 1 < b.len() && b[j + 1] != '{' {
                    j += 1;
                    while j < b.len() && is_ident(b[j]) {
                        j += 1;
                    }
                    if j < b.len() && b[j] == c && j > i + 2 {
                        let name: String = b[i + 2..j].iter().collect();
                        out.push_str(&lookup(&name, byte)?.to_string());
                        byte += b[i..=j].iter().map(|ch| ch.len_utf8()).sum::<usize>();
                        i = j + 1;
                        continue;
                    }
                }
                quote = Some(c);
                out.push(c);
            }
            Some(q) if c == '\\' && q == '"' && i + 1 < b.len() => {
                out.push(c);
                out.push(b[i + 1]);
                byte += c.len_utf8() + b[i + 1].len_utf8();
                i += 2;
                continue;
            }
            Some(q) if c == q => {
                quote = None;
                out.push(c);
            }
            Some(_) if c == '$' && i + 1 < b.len() && b[i + 1] == '{' => {
                let start = i + 2;
                let mut j = start;
                while j < b.len() && b[j] != '}' {
                    j += 1;
                }
                if j == b.len() {
                    return Err(SceneError::new(
                        file,
                        Some(line_of(text, offset + byte)),
                        "unterminated ${...} reference",
                    ));
                }
                let name: String = b[start..j].iter().collect();
                match lookup(&name, byte)? {
                    toml::Value::String(s) => out.push_str(s),
                    v => out.push_str(&v.to_string()),
                }
                byte += b[i..=j].iter().map(|ch| ch.len_utf8()).sum::<usize>();
                i = j + 1;
                continue;
            }
            _ => out.push(c),
        }
        byte += c.len_utf8();
        i += 1;
    }
    Ok(out)
}
