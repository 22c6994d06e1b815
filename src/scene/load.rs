//! Reading a scene file, the one pipeline every command uses: bytes → hash →
//! variables substituted (`vars`) → serde into a [`SceneDesc`], with errors that
//! name the file and line.

use super::desc::SceneDesc;
use super::error::SceneError;
use super::vars;
use crate::files::sha256_hex;
use std::collections::BTreeMap;
use std::path::Path;

/// A parsed scene file, not yet built.
pub struct LoadedScene {
    /// The text after substitution: spans in `desc` point into it (lines are kept).
    pub text: String,
    /// The file as written.
    pub original: String,
    /// SHA-256 of the file's bytes as read.
    pub sha256: String,
    /// The `-D name=value` overrides applied.
    pub overrides: Vec<String>,
    /// Final variable values (file defaults with the overrides applied).
    pub vars: BTreeMap<String, toml::Value>,
    pub desc: SceneDesc,
}

/// Reads `path`, applies `overrides` to its `[vars]` and parses it.
pub fn read(path: &Path, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let original = std::fs::read_to_string(path)
        .map_err(|e| SceneError::new(path, None, format!("cannot read the scene file: {e}")))?;
    let (text, vars) = vars::substitute(path, &original, overrides)?;
    let desc: SceneDesc =
        toml::from_str(&text).map_err(|e| SceneError::from_toml(path, &text, &e))?;
    Ok(LoadedScene {
        sha256: sha256_hex(original.as_bytes()),
        original,
        overrides: overrides.to_vec(),
        text,
        vars,
        desc,
    })
}
