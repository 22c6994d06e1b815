//! Provenance built in one place: every front end (the CLI, the Python module,
//! the live window) starts from its [`Invocation`] — what the user ran, as the
//! front end knows it (the library never reads `argv`) — and adds the scene, the
//! run settings and the run's parts. `output` writes the record.

use super::{Shard, StateHeader};
use crate::output::Provenance;
use crate::scene::Scene;
use crate::trace::RunConfig;
use serde_json::json;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// How the user asked for the work: the command line of the CLI, or the Python
/// call (`["python", "traxer.Scene.trace", ...]`), as the front end says.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Invocation {
    pub command_line: Vec<String>,
}

impl Invocation {
    pub fn new(command_line: impl IntoIterator<Item = impl Into<String>>) -> Invocation {
        Invocation {
            command_line: command_line.into_iter().map(Into::into).collect(),
        }
    }
}

/// The commit the binary was built from.
pub fn git_hash() -> &'static str {
    env!("TRAXER_GIT_HASH")
}

impl Provenance {
    /// This program, this command line, now; with the Embree version when Embree
    /// was used.
    pub fn new(invocation: &Invocation, embree_version: Option<String>) -> Provenance {
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
            command_line: invocation.command_line.clone(),
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
                Shard {
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
