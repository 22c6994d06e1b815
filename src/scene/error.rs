//! Errors in scene files, always naming the file and, where known, the line.

use std::path::{Path, PathBuf};

/// A problem with a scene file or its command-line overrides (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct SceneError {
    pub file: PathBuf,
    /// 1-based line number, when the problem has a place in the file.
    pub line: Option<usize>,
    pub message: String,
}

impl SceneError {
    pub fn new(file: &Path, line: Option<usize>, message: impl Into<String>) -> SceneError {
        SceneError {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    /// An error at byte offset `offset` of `text`.
    pub fn at(file: &Path, text: &str, offset: usize, message: impl Into<String>) -> SceneError {
        SceneError::new(file, Some(line_of(text, offset)), message)
    }

    /// Converts a TOML syntax or type error into a located error with the
    /// offending line quoted.
    pub fn from_toml(file: &Path, text: &str, e: &toml::de::Error) -> SceneError {
        let Some(span) = e.span() else {
            return SceneError::new(file, None, e.message().to_string());
        };
        let message = e.message().trim_end();
        // Inside tables read through `type = ...` (materials, sources, shapes) serde
        // reports the whole table: find the offending value in it.
        let (offset, message) = match locate_bad_value(text, span.clone(), message) {
            Some((offset, key)) => (offset, format!("`{key}`: {message}")),
            None => (span.start, message.to_string()),
        };
        let line = line_of(text, offset);
        let quoted = text.lines().nth(line - 1).unwrap_or("").trim_end();
        SceneError::new(file, Some(line), format!("{message}\n    | {quoted}"))
    }
}

/// The text a scene was parsed from, to turn byte spans into located errors.
#[derive(Clone, Copy)]
pub(crate) struct SceneText<'a> {
    pub path: &'a Path,
    pub text: &'a str,
}

impl SceneText<'_> {
    /// An error at `span`; the empty span at 0 (things the file does not
    /// contain, such as built-in materials) names no line.
    pub fn error(
        &self,
        span: std::ops::Range<usize>,
        message: impl std::fmt::Display,
    ) -> SceneError {
        let message = message.to_string();
        if span.is_empty() && span.start == 0 {
            SceneError::new(self.path, None, message)
        } else {
            SceneError::at(self.path, self.text, span.start, message)
        }
    }

    /// An error about the whole file (no line).
    pub fn whole(&self, message: impl std::fmt::Display) -> SceneError {
        SceneError::new(self.path, None, message.to_string())
    }
}

/// For serde's "invalid type: string \"ten\", expected u32" (or "invalid value:
/// ...", or "unknown field `side`") reported over a whole table, the byte offset
/// and dotted key of the one value inside `span` that the message describes.
/// `None` when the message names no value, or when no value or several match.
fn locate_bad_value(
    text: &str,
    span: std::ops::Range<usize>,
    message: &str,
) -> Option<(usize, String)> {
    // What identifies the value: its description, or (unknown field) its key.
    let (described, unknown_key) = match message.strip_prefix("unknown field `") {
        Some(rest) => (None, Some(rest.split_once('`')?.0)),
        None => {
            let rest = message
                .strip_prefix("invalid type: ")
                .or_else(|| message.strip_prefix("invalid value: "))?;
            (Some(rest.rsplit_once(", expected ")?.0), None)
        }
    };
    let doc = toml_edit::ImDocument::parse(text).ok()?;
    let mut found = Vec::new();
    visit_table(doc.as_table(), "", &mut |key, value| {
        let inside = value
            .span()
            .is_some_and(|s| s.start >= span.start && s.end <= span.end);
        let matches = match (described, unknown_key) {
            (Some(d), _) => describes(d, value),
            (None, Some(k)) => key.rsplit('.').next() == Some(k),
            _ => false,
        };
        if inside && matches {
            found.push((
                value.span().map_or(span.start, |s| s.start),
                key.to_string(),
            ));
        }
    });
    match found.as_slice() {
        [one] => Some(one.clone()),
        _ => None,
    }
}

/// Whether serde's description of an unexpected value ("string \"ten\"",
/// "integer `5`", "floating point `1.5`", "boolean `true`", "sequence", "map")
/// fits a TOML value.
fn describes(described: &str, value: &toml_edit::Value) -> bool {
    use toml_edit::Value as V;
    let quoted = |prefix: &str, open: char, close: char| -> Option<String> {
        let inner = described.strip_prefix(prefix)?;
        let inner = inner.strip_prefix(open)?.strip_suffix(close)?;
        Some(inner.to_string())
    };
    match value {
        V::String(s) => quoted("string ", '"', '"').is_some_and(|x| x == unescape(s.value())),
        V::Integer(i) => quoted("integer ", '`', '`').is_some_and(|x| x.parse() == Ok(*i.value())),
        V::Float(f) => quoted("floating point ", '`', '`')
            .and_then(|x| x.parse::<f64>().ok())
            .is_some_and(|x| x == *f.value() || (x.is_nan() && f.value().is_nan())),
        V::Boolean(b) => quoted("boolean ", '`', '`').is_some_and(|x| x == b.value().to_string()),
        V::Array(_) => described == "sequence",
        V::InlineTable(_) => described == "map",
        V::Datetime(_) => false,
    }
}

/// serde prints strings with Rust's Debug escapes; compare like for like.
fn unescape(s: &str) -> String {
    let debug = format!("{s:?}");
    debug[1..debug.len() - 1].to_string()
}

/// Calls `f(dotted key, value)` for every value under `table`, depth first.
fn visit_table(table: &toml_edit::Table, prefix: &str, f: &mut dyn FnMut(&str, &toml_edit::Value)) {
    for (key, item) in table.iter() {
        let path = if prefix.is_empty() {
            key.to_string()
        } else {
            format!("{prefix}.{key}")
        };
        match item {
            toml_edit::Item::Value(v) => visit_value(v, &path, f),
            toml_edit::Item::Table(t) => visit_table(t, &path, f),
            toml_edit::Item::ArrayOfTables(a) => {
                for (i, t) in a.iter().enumerate() {
                    visit_table(t, &format!("{path}[{i}]"), f);
                }
            }
            toml_edit::Item::None => {}
        }
    }
}

fn visit_value(value: &toml_edit::Value, path: &str, f: &mut dyn FnMut(&str, &toml_edit::Value)) {
    f(path, value);
    match value {
        toml_edit::Value::Array(a) => {
            for (i, v) in a.iter().enumerate() {
                visit_value(v, &format!("{path}[{i}]"), f);
            }
        }
        toml_edit::Value::InlineTable(t) => {
            for (k, v) in t.iter() {
                visit_value(v, &format!("{path}.{k}"), f);
            }
        }
        _ => {}
    }
}

/// 1-based line number of a byte offset.
pub fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}
