//! Provenance recorded next to every output: which program, which scene, which
//! random numbers, which command.

/// Facts that make a run reproducible; serialised into every JSON sidecar.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Provenance {
    pub traxer_version: String,
    /// Git commit the binary was built from (with "-dirty" for local changes).
    pub git_hash: String,
    pub embree_version: String,
    pub scene_path: String,
    /// SHA-256 of the scene file's bytes.
    pub scene_sha256: String,
    /// `-D name=value` overrides applied to the scene.
    pub overrides: Vec<String>,
    pub seed: u64,
    pub photons: u64,
    pub threads: usize,
    /// Index of the first photon (non-zero for a shard of a larger run).
    pub first_photon: u64,
    pub command_line: Vec<String>,
    /// Seconds since the Unix epoch when the run finished.
    pub finished_unix_s: u64,
}

/// The commit the binary was built from.
pub fn git_hash() -> &'static str {
    env!("TRAXER_GIT_HASH")
}
