//! Errors in scene files, always naming the file and, where known, the line.

use std::path::{Path, PathBuf};

/// A problem with a scene file or its command-line overrides (exit code 2),
/// or, marked [`SceneError::of_machine`], the machine's failure to build a
/// scene that is fine (Embree out of memory: exit code 1).
#[derive(Debug, thiserror::Error)]
#[error("{}{}: {message}", file.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct SceneError {
    pub file: PathBuf,
    /// 1-based line number, when the problem has a place in the file.
    pub line: Option<usize>,
    pub message: String,
    /// The dotted key of the value at fault (`objects[2].shape.radius`), when
    /// the problem is located at a value of the file (the message names it too).
    pub key: Option<String>,
    /// The machine failed, not the scene.
    pub machine: bool,
}

/// The longest word (a run without spaces: a value, a path) a message quotes
/// whole.
const MAX_WORD: usize = 300;

impl SceneError {
    pub fn new(file: &Path, line: Option<usize>, message: impl Into<String>) -> SceneError {
        SceneError {
            file: file.to_path_buf(),
            line,
            // A value of 100 000 characters (a -D, a string in the file) is
            // quoted shortened, not whole.
            message: crate::text::shorten_words(&message.into(), MAX_WORD),
            key: None,
            machine: false,
        }
    }

    /// The same error, as the machine's failure (Embree could not build the
    /// scene), not the scene's.
    pub fn of_machine(self) -> SceneError {
        SceneError {
            machine: true,
            ..self
        }
    }

    /// Whether the scene (the user's input) is at fault.
    pub fn is_bad_input(&self) -> bool {
        !self.machine
    }

    /// The same error, about the value at `key`.
    fn keyed(self, key: Option<String>) -> SceneError {
        SceneError { key, ..self }
    }

    /// An error at byte offset `offset` of `text`.
    pub fn at(file: &Path, text: &str, offset: usize, message: impl Into<String>) -> SceneError {
        SceneError::new(file, Some(line_of(text, offset)), message)
            .keyed(key_at(text, offset..offset))
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
        let (offset, message, key) = match locate_bad_value(text, span.clone(), message) {
            Some((offset, key)) => {
                let said = plain_value_message(message, &key, text, offset);
                let said = with_flattened_keys(said, &key);
                (offset, format!("`{key}`: {said}"), Some(key))
            }
            None => {
                // An unclosed multi-line string is reported where the file
                // ends: point at the line that opened it.
                let opened = [r#"""""#, "'''"]
                    .iter()
                    .filter(|_| message.contains("invalid multiline"))
                    .filter_map(|q| text[..span.start.min(text.len())].rfind(q))
                    .max();
                let offset = opened.unwrap_or(span.start);
                (
                    offset,
                    plain_syntax_message(message),
                    key_at(text, offset..offset),
                )
            }
        };
        let line = line_of(text, offset);
        let quoted = excerpt(text, offset);
        SceneError::new(file, Some(line), format!("{message}\n    | {quoted}")).keyed(key)
    }
}

/// serde's "unknown field `k`" in a table that flattens a mirror surface in
/// names no keys: the keys that table takes are added.
fn with_flattened_keys(said: String, key: &str) -> String {
    let table = key.rsplit_once('.').map_or("", |(t, _)| t);
    match super::mirror_surface::keys_of_table_with_surface(table) {
        Some(keys) if said.starts_with("unknown field `") && !said.contains("expected") => {
            let keys: Vec<String> = keys.iter().map(|k| format!("`{k}`")).collect();
            format!("{said}, expected one of {}", keys.join(", "))
        }
        _ => said,
    }
}

/// The text a scene was parsed from, to turn byte spans into located errors.
#[derive(Clone, Copy)]
pub(crate) struct SceneText<'a> {
    pub path: &'a Path,
    pub text: &'a str,
    /// The file as written (before variables were substituted) and the `-D`
    /// overrides, so that an error on a line that uses an overridden variable
    /// says where its value came from.
    pub original: &'a str,
    pub overrides: &'a [String],
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
            return SceneError::new(self.path, None, message);
        }
        let line = line_of(self.text, span.start);
        let last = line_of(self.text, span.end.max(span.start));
        let message = match self.override_used(line, last, &message) {
            Some(d) => format!("{message} (from the variable override {d})"),
            None => message,
        };
        SceneError::new(self.path, Some(line), message).keyed(key_at(self.text, span))
    }

    /// The `-D` override of a variable that lines `first..=last` (1-based) of the
    /// file use, if any (substitution keeps lines where they were). Where the
    /// lines use several (a whole table), the one given to a key the message
    /// names (`g_agamma = "$g_agamma"` for "g_agamma = 1e10: ..."); with none
    /// named, the first.
    fn override_used(&self, first: usize, last: usize, message: &str) -> Option<&str> {
        let lines: Vec<&str> = self
            .original
            .lines()
            .skip(first.checked_sub(1)?)
            .take(last + 1 - first)
            .collect();
        let written = lines.join("\n");
        let uses = |name: &str, text: &str| {
            text.contains(&format!("\"${name}\"")) || text.contains(&format!("${{{name}}}"))
        };
        let used: Vec<&str> = self
            .overrides
            .iter()
            .map(String::as_str)
            .filter(|d| {
                d.split_once('=')
                    .is_some_and(|(name, _)| uses(name.trim(), &written))
            })
            .collect();
        // The key a variable is given to: the word before `=` in front of
        // its use (`temperature_k = "$helium_k"`).
        let key_of = |name: &str| -> Option<String> {
            let at = written
                .find(&format!("\"${name}\""))
                .or_else(|| written.find(&format!("${{{name}}}")))?;
            let before = written[..at].trim_end().strip_suffix('=')?.trim_end();
            let key: String = before
                .chars()
                .rev()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect();
            (!key.is_empty()).then_some(key)
        };
        let named = used.iter().copied().find(|d| {
            let name = d.split_once('=').map_or("", |(n, _)| n.trim());
            key_of(name).is_some_and(|k| {
                message.contains(&format!("{k} =")) || message.contains(&format!("{k}:"))
            })
        });
        named.or(used.first().copied())
    }

    /// An error about the whole file (no line).
    pub fn whole(&self, message: impl std::fmt::Display) -> SceneError {
        SceneError::new(self.path, None, message.to_string())
    }
}

/// serde's words for a value of the wrong kind, in a physicist's: a transform
/// step or energy with two keys, a date where a number belongs.
fn plain_value_message(message: &str, key: &str, text: &str, offset: usize) -> String {
    if message.starts_with("wanted exactly 1 element")
        || message.contains("expected map with a single key")
    {
        return if key.contains("transform") {
            "a transform step has exactly one key (translate, rotate or scale): write each as its own step, e.g. transform = [ { translate = [0, 0, 10] }, { rotate = { axis = [0, 0, 1], angle = 30 } } ] (applied in order)".into()
        } else if key.ends_with("energy") {
            "energy has exactly one key: line = KEV, or band = [MIN, MAX]".into()
        } else {
            format!("exactly one key is allowed here ({message})")
        };
    }
    if let Some(expected) = message
        .strip_prefix("invalid type: map, expected ")
        .filter(|_| is_datetime_at(text, offset))
    {
        return format!(
            "`{}` is a date or time to TOML, where {expected} belongs: write a number (or quote it as a string)",
            token_at(text, offset)
        );
    }
    message.to_string()
}

/// The value written at `offset` of `text` (up to a space, comma or bracket).
fn token_at(text: &str, offset: usize) -> String {
    text[offset.min(text.len())..]
        .chars()
        .take_while(|c| !c.is_whitespace() && !",]}".contains(*c))
        .collect()
}

/// Whether a TOML date or time starts at `offset` of `text`.
fn is_datetime_at(text: &str, offset: usize) -> bool {
    token_at(text, offset)
        .parse::<toml_edit::Datetime>()
        .is_ok()
}

/// toml's syntax errors, with what to do about the common ones.
fn plain_syntax_message(message: &str) -> String {
    let hint = if message.contains("invalid multiline basic string") {
        r#": a string opened with """ on this line is never closed; close it with """ (or write a one-line "..." string)"#
    } else if message.contains("invalid multiline literal string") {
        ": a string opened with ''' on this line is never closed; close it with '''"
    } else if message.contains("invalid basic string") {
        r#": a string opened with " on this line is not closed on the same line; close it with " (strings over several lines use """)"#
    } else {
        ""
    };
    format!("{message}{hint}")
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
    // What identifies the value: its description, (unknown field) its key, an
    // array's wrong length, or a table of one-key choices with several keys.
    let mut described = None;
    let mut unknown_key = None;
    let mut length = None;
    let mut one_key_table = false;
    if let Some(rest) = message.strip_prefix("unknown field `") {
        unknown_key = Some(rest.split_once('`')?.0);
    } else if let Some(rest) = message.strip_prefix("invalid length ") {
        length = rest.split(',').next()?.trim().parse::<usize>().ok();
    } else if message.contains("expected map with a single key")
        || message.starts_with("wanted exactly 1 element")
    {
        one_key_table = true;
    } else {
        let rest = message
            .strip_prefix("invalid type: ")
            .or_else(|| message.strip_prefix("invalid value: "))?;
        described = Some(rest.rsplit_once(", expected ")?.0);
    }
    let doc = toml_edit::ImDocument::parse(text).ok()?;
    let mut found = Vec::new();
    visit_table(doc.as_table(), "", &mut |key, value| {
        let inside = value
            .span()
            .is_some_and(|s| s.start >= span.start && s.end <= span.end);
        let matches = if let Some(d) = described {
            describes(d, value)
        } else if let Some(k) = unknown_key {
            key.rsplit('.').next() == Some(k)
        } else if let Some(n) = length {
            value.as_array().is_some_and(|a| a.len() == n)
        } else {
            one_key_table && is_one_key_choice(value)
        };
        if inside && matches {
            found.push((
                value.span().map_or(span.start, |s| s.start),
                key.to_string(),
            ));
        }
    });
    // A date read as a table (serde's "map") wins over the tables around it.
    if described == Some("map") {
        let dates: Vec<&(usize, String)> = found
            .iter()
            .filter(|(o, _)| is_datetime_at(text, *o))
            .collect();
        if let [one] = dates.as_slice() {
            return Some((*one).clone());
        }
    }
    match found.as_slice() {
        [one] => Some(one.clone()),
        // Several elements of one array (`pixels = [10.0, 10.0]`): the array.
        [first, rest @ ..] => {
            let parent = |k: &str| k.rsplit_once('[').map(|(p, _)| p.to_string());
            let p = parent(&first.1)?;
            let same = rest
                .iter()
                .all(|r| parent(&r.1).as_deref() == Some(p.as_str()));
            same.then_some((first.0, p))
        }
        [] => None,
    }
}

/// The dotted key of the innermost value or table of `text` whose text holds
/// `span`.
fn key_at(text: &str, span: std::ops::Range<usize>) -> Option<String> {
    let doc = toml_edit::ImDocument::parse(text).ok()?;
    let mut best: Option<(usize, String)> = None;
    let mut consider = |key: &str, s: Option<std::ops::Range<usize>>| {
        let Some(s) = s else { return };
        let holds = s.start <= span.start && span.end <= s.end;
        // Children come after their parents: an equal span is the deeper one.
        if holds && best.as_ref().is_none_or(|(len, _)| s.len() <= *len) {
            best = Some((s.len(), key.to_string()));
        }
    };
    visit_subtables(doc.as_table(), "", &mut |key, t| consider(key, t.span()));
    visit_table(doc.as_table(), "", &mut |key, v| consider(key, v.span()));
    best.map(|(_, key)| key)
}

/// Calls `f(dotted key, table)` for every table under `table` (`[a.b]`, and
/// each `[[a]]` as `a[i]`), depth first.
fn visit_subtables(
    table: &toml_edit::Table,
    prefix: &str,
    f: &mut dyn FnMut(&str, &toml_edit::Table),
) {
    for (key, item) in table.iter() {
        let path = dotted(prefix, key);
        let tables: Vec<(String, &toml_edit::Table)> = match item {
            toml_edit::Item::Table(t) => vec![(path, t)],
            toml_edit::Item::ArrayOfTables(a) => a
                .iter()
                .enumerate()
                .map(|(i, t)| (format!("{path}[{i}]"), t))
                .collect(),
            _ => Vec::new(),
        };
        for (path, t) in tables {
            f(&path, t);
            visit_subtables(t, &path, f);
        }
    }
}

/// Tables in which exactly one of a few keys is written (an energy: `line` or
/// `band`; a transform step: `translate`, `rotate` or `scale`), written with
/// more than one of them.
fn is_one_key_choice(value: &toml_edit::Value) -> bool {
    const CHOICES: [&str; 5] = ["line", "band", "translate", "rotate", "scale"];
    value
        .as_inline_table()
        .is_some_and(|t| t.len() > 1 && t.iter().all(|(k, _)| CHOICES.contains(&k)))
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
        V::Datetime(_) => described == "map",
    }
}

/// serde prints strings with Rust's Debug escapes; compare like for like.
fn unescape(s: &str) -> String {
    let debug = format!("{s:?}");
    debug[1..debug.len() - 1].to_string()
}

/// `key` under `prefix` ("a.b" + "c" = "a.b.c").
fn dotted(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

/// Calls `f(dotted key, value)` for every value under `table`, depth first.
fn visit_table(table: &toml_edit::Table, prefix: &str, f: &mut dyn FnMut(&str, &toml_edit::Value)) {
    for (key, item) in table.iter() {
        let path = dotted(prefix, key);
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

/// The line holding byte `offset`, cut to at most [`EXCERPT`] characters around
/// that offset (a generated file may have a line of megabytes).
fn excerpt(text: &str, offset: usize) -> String {
    let offset = offset.min(text.len());
    let start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let end = text[offset..].find('\n').map_or(text.len(), |i| offset + i);
    let line = text[start..end].trim_end();
    if line.chars().count() <= EXCERPT {
        return line.to_string();
    }
    // A window around the offset, on character boundaries.
    let at = text[start..offset].chars().count();
    let from = at.saturating_sub(EXCERPT / 2);
    let window: String = line.chars().skip(from).take(EXCERPT).collect();
    let before = if from > 0 { "…" } else { "" };
    let after = if from + EXCERPT < line.chars().count() {
        "…"
    } else {
        ""
    };
    format!("{before}{window}{after}")
}

/// The longest excerpt of a scene line an error quotes (characters).
const EXCERPT: usize = 160;

/// 1-based line number of a byte offset.
pub fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}
