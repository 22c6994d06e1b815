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
        let line = line_of(text, span.start);
        let quoted = text.lines().nth(line - 1).unwrap_or("").trim_end();
        SceneError::new(
            file,
            Some(line),
            format!("{}\n    | {quoted}", e.message().trim_end()),
        )
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
