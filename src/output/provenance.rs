//! Provenance recorded with every output: which program, which scene (and its
//! hash and variables), which random numbers, which command. One constructor,
//! [`Provenance::new`], and two additions ([`Provenance::scene`],
//! [`Provenance::run`]) give every command the same record; [`write_sidecar`]
//! puts it next to outputs that cannot hold it themselves (PNGs, CSVs).

use crate::runstate::StateHeader;
use crate::scene::Scene;
use crate::trace::RunConfig;
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
    pub command_line: Vec<String>,
    /// Seconds since the Unix epoch when the record was made (the run finished).
    pub finished_unix_s: u64,
}

/// The commit the binary was built from.
pub fn git_hash() -> &'static str {
    env!("TRAXER_GIT_HASH")
}

impl Provenance {
    /// This program, this command line, now; with the Embree version when Embree
    /// was used.
    pub fn new(embree_version: Option<String>) -> Provenance {
        Provenance {
            traxer_version: env!("CARGO_PKG_VERSION").into(),
            git_hash: git_hash().into(),
            embree_version,
            scene_path: None,
            scene_sha256: None,
            overrides: Vec::new(),
            variables: BTreeMap::new(),
            seed: None,
            photons: None,
            threads: None,
            first_photon: None,
            shards: None,
            trace_seconds: None,
            command_line: std::env::args().collect(),
            finished_unix_s: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_secs())
                .unwrap_or(0),
        }
    }

    /// With the scene that was traced or rendered.
    pub fn scene(self, scene: &Scene) -> Provenance {
        Provenance {
            scene_path: Some(scene.path.display().to_string()),
            scene_sha256: Some(scene.text_sha256.clone()),
            overrides: scene.overrides.clone(),
            variables: scene.vars.clone(),
            ..self
        }
    }

    /// With the run settings (`threads`: the number actually used).
    pub fn run(self, cfg: &RunConfig, threads: usize) -> Provenance {
        Provenance {
            seed: Some(cfg.seed),
            photons: Some(cfg.photons),
            threads: Some(threads),
            first_photon: Some(cfg.first_photon),
            ..self
        }
    }

    /// With the run's parts, as recorded in its run state (a shard, a resumed run
    /// or a merge of `merged_from`); `photons` is then the photons these results
    /// hold.
    pub fn parts(self, header: &StateHeader, merged_from: &[PathBuf]) -> Provenance {
        let id = &header.identity;
        let shards = (id.shards > 1).then(|| {
            json!({
                "total_photons": id.total_photons,
                "cut_into": id.shards,
                "parts": header.parts,
                "missing": header.missing,
                "partial": !header.missing.is_empty(),
                "merged_from": merged_from.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
            })
        });
        Provenance {
            seed: Some(id.seed),
            photons: Some(header.photons),
            shards,
            trace_seconds: Some(header.seconds),
            first_photon: (header.parts.len() == 1).then(|| {
                crate::runstate::Shard {
                    index: header.parts[0],
                    count: id.shards,
                    total: id.total_photons,
                }
                .range()
                .start
            }),
            ..self
        }
    }

    /// With a seed and threads but no photon count (renders).
    pub fn seeded(self, seed: u64, threads: usize) -> Provenance {
        Provenance {
            seed: Some(seed),
            threads: Some(threads),
            ..self
        }
    }
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
