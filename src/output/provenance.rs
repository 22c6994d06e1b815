//! Provenance recorded with every output: which program, which scene (and its
//! hash and variables), which random numbers, which command. This is the record
//! as written; it is built in one place, `run::provenance` (from the front end's
//! invocation, the scene, the run settings and its parts). [`write_sidecar`]
//! puts it next to outputs that cannot hold it themselves (PNGs, CSVs).

use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Facts that make a result reproducible; serialised into every JSON output and
/// sidecar. Fields that do not apply to a command (no scene, no photons) are null.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Provenance {
    pub traxer_version: String,
    /// Git commit the binary was built from (with "-dirty" for local changes).
    pub git_hash: String,
    pub embree_version: Option<String>,
    pub scene_path: Option<String>,
    /// SHA-256 of the scene file's bytes.
    pub scene_sha256: Option<String>,
    /// `-D name=value` overrides applied to the scene.
    pub overrides: Vec<String>,
    /// Final values of the scene's variables (defaults with the overrides).
    pub variables: BTreeMap<String, toml::Value>,
    pub seed: Option<u64>,
    pub photons: Option<u64>,
    /// Worker threads used (results do not depend on it).
    pub threads: Option<usize>,
    /// Index of the first photon (non-zero for a shard of a larger run).
    pub first_photon: Option<u64>,
    /// For a run cut into shards: the whole run's photons, the number of shards,
    /// the shards these results hold, those a partial merge left out, and the
    /// folders merged; null for a run in one piece.
    pub shards: Option<Value>,
    /// Tracing time summed over the shards and over the sittings of a resumed run.
    pub trace_seconds: Option<f64>,
    /// For a study with a results folder: how many of its points were taken
    /// from the record of the stopped study it resumed (0 for a fresh one).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub points_from_record: Option<usize>,
    pub command_line: Vec<String>,
    /// Seconds since the Unix epoch when the record was made (the run finished).
    pub finished_unix_s: u64,
}

/// Where the sidecar of `output` goes: the same name with `.json`
/// (`render.png` → `render.json`), or `NAME.provenance.json` if that is the
/// output itself.
pub fn sidecar_path(output: &Path) -> PathBuf {
    let p = output.with_extension("json");
    if p == output {
        output.with_extension("provenance.json")
    } else {
        p
    }
}

/// Writes the sidecar of `output`: the provenance and `details` (settings that
/// are not in the provenance, the files it covers).
pub fn write_sidecar(
    output: &Path,
    provenance: &Provenance,
    details: Value,
) -> std::io::Result<PathBuf> {
    let path = sidecar_path(output);
    let name = output
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    super::write_json(
        &path,
        &json!({ "provenance": provenance, "file": name, "details": details }),
    )?;
    Ok(path)
}
