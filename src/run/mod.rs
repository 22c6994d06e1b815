//! The life of a run, for every front end (the CLI, the Python module, the live
//! window): provenance built once per kind of result from the front end's
//! [`Invocation`] ([`provenance`]); a run traced into its results folder or in
//! memory ([`TraceJob`]); the results folder prepared, staged and put in place
//! ([`finished`]); the identity of a run ([`RunIdentity`]: [`BUILD`], scene and
//! every file it reads, variables, seed, counts); its run-state file
//! ([`state_file`]: a finished run's `run_state.bin`, a stopped run's
//! `checkpoint.bin`); shards ([`Shard`]) and their [`merge`]; and studies
//! ([`Study`]: their point-by-point [`record`], resumed, and their files written
//! and put in place together).
//!
//! Data flow: `trace` accumulates a [`Tally`] (exact sums); this module saves it
//! with what identifies the run in a run-state file. `traxer merge` reads the
//! run-state files of shards, checks that they are disjoint parts of one run and
//! adds their tallies; `traxer trace --resume` reads a checkpoint and continues
//! the photon loop from it. Both then hand the tally to `output` as a normal run.
//! Because sums are exact and photon i's random stream depends only on (seed,
//! i), any split, order or interruption gives the bit-identical tally of one
//! uninterrupted run. `output` writes files and knows nothing of runs.
//!
//! The file: a first line `traxer run state 3` followed by the SHA-256 of the
//! second line, the header as JSON (readable with `head -2`), then the tally in
//! `postcard`'s compact binary encoding, whose SHA-256 the header records: every
//! byte of the file is covered by a checksum.

pub mod finished;
pub mod job;
pub mod merge;
mod merge_job;
pub mod provenance;
pub mod record;
mod shard;
pub mod state_file;
pub mod study;
mod study_job;

pub use finished::{
    results_file_names, results_folder, results_folder_reading, save_results, save_traced,
    write_results, write_results_folder,
};
pub use job::{
    open_finished, open_stopped, Finished, Found, InMemory, Resumable, RunControl, RunError,
    RunSettings, TraceJob,
};
pub use merge::{merge, MergeError, Merged};
pub use merge_job::{MergeJob, MergedRun};
pub use provenance::{git_hash, Build, Invocation, BUILD};
pub use shard::Shard;
pub use state_file::{read_header, read_state, state_bytes, write_state, RunStateError};
pub use study::Study;
pub use study_job::{run_study, save_study, StudyControl, StudyPlace};

use crate::scene::{input_difference, InputHashes, Scene};
use crate::trace::{RunConfig, Tally};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// About 100 bytes each in memory: a photon list is for looking at photons, not
/// all of them.
pub const MAX_PHOTON_LIST: usize = 20_000_000;

/// More worker threads than this is a typo, not a machine.
pub const MAX_THREADS: usize = 1024;

/// Which front end asks, so that a message names a setting as its user wrote
/// it: `--photon-list 5` on the command line, `photon_list=5` in Python.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FrontEnd {
    Cli,
    Python,
}

impl FrontEnd {
    /// Setting `python_name` (its CLI option is the same with dashes) = `value`.
    pub fn setting(self, python_name: &str, value: impl std::fmt::Display) -> String {
        match self {
            FrontEnd::Cli => format!("--{} {value}", python_name.replace('_', "-")),
            FrontEnd::Python => format!("{python_name}={value}"),
        }
    }
}

/// The one validated run configuration of every front end: at least one photon,
/// 0 (one per core) to [`MAX_THREADS`] threads, a photon list of at most
/// [`MAX_PHOTON_LIST`]. Messages name the setting as `front` spells it.
pub fn run_config(
    photons: u64,
    seed: u64,
    threads: usize,
    photon_list: usize,
    front: FrontEnd,
) -> Result<RunConfig, InputError> {
    if photons == 0 {
        return Err(InputError(format!(
            "{}: photons must be at least 1",
            front.setting("photons", photons)
        )));
    }
    check_threads(threads, front)?;
    Ok(RunConfig {
        threads,
        photon_list: check_photon_list(photon_list, front)?,
        ..RunConfig::new(photons, seed)
    })
}

/// A thread count checked: 0 (one per core) to [`MAX_THREADS`].
pub fn check_threads(threads: usize, front: FrontEnd) -> Result<usize, InputError> {
    if threads > MAX_THREADS {
        return Err(InputError(format!(
            "{}: expected 0 (one per core) to {MAX_THREADS} worker threads",
            front.setting("threads", threads)
        )));
    }
    Ok(threads)
}

/// The number of photons to list (`--photon-list`, `photon_list=`), checked.
pub fn check_photon_list(n: usize, front: FrontEnd) -> Result<usize, InputError> {
    if n > MAX_PHOTON_LIST {
        return Err(InputError(format!(
            "{}: at most {MAX_PHOTON_LIST} photons are listed",
            front.setting("photon_list", n)
        )));
    }
    Ok(n)
}

/// A problem with what the user asked of a run (a folder, a record, a
/// checkpoint): exit code 2 in the CLI, `InputError` in Python.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// A run stopped on request (a signal, a Python KeyboardInterrupt) after writing
/// its checkpoint; the message says how to continue (exit code 130).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Stopped(pub String);

/// Name of a finished run's (or shard's, or merge's) run-state file.
pub const RUN_STATE_FILE: &str = "run_state.bin";
/// Name of a run's checkpoint while it runs.
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";

/// What must be equal for two parts to belong to one run, and for a checkpoint
/// to be continued by this program.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunIdentity {
    pub traxer_version: String,
    pub git_hash: String,
    /// SHA-256 of the scene file's bytes.
    pub scene_sha256: String,
    /// Final values of the scene's variables.
    pub variables: BTreeMap<String, toml::Value>,
    /// SHA-256 of every other file the scene reads (meshes, data and emission
    /// tables), by name.
    #[serde(default)]
    pub inputs: InputHashes,
    pub seed: u64,
    /// Photons of the whole run (all shards).
    pub total_photons: u64,
    /// Into how many shards the run is cut (1: not cut).
    pub shards: u64,
    /// Photons listed (`--photon-list`).
    pub photon_list: usize,
}

impl RunIdentity {
    /// The identity of a run of `scene` with `total_photons` photons cut into
    /// `shards` shards.
    pub fn new(
        scene: &Scene,
        seed: u64,
        total_photons: u64,
        shards: u64,
        photon_list: usize,
    ) -> RunIdentity {
        RunIdentity {
            traxer_version: BUILD.version.into(),
            git_hash: BUILD.git_hash.into(),
            scene_sha256: scene.text_sha256.clone(),
            variables: scene.vars.clone(),
            inputs: scene.inputs.clone(),
            seed,
            total_photons,
            shards,
            photon_list,
        }
    }

    /// The first difference from `other`, said for a person ("seed 1, not 2").
    pub fn difference(&self, other: &RunIdentity) -> Option<String> {
        let d = |what: &str, a: &dyn std::fmt::Display, b: &dyn std::fmt::Display| {
            Some(format!("{what} {a}, not {b}"))
        };
        if self.traxer_version != other.traxer_version || self.git_hash != other.git_hash {
            return d(
                "traxer",
                &format!("{} ({})", self.traxer_version, self.git_hash),
                &format!("{} ({})", other.traxer_version, other.git_hash),
            );
        }
        if self.scene_sha256 != other.scene_sha256 {
            return d(
                "a scene file with SHA-256",
                &short(&self.scene_sha256),
                &short(&other.scene_sha256),
            );
        }
        if let Some(diff) = input_difference(&self.inputs, &other.inputs) {
            return Some(diff);
        }
        if self.variables != other.variables {
            let mut keys: Vec<&String> = self
                .variables
                .keys()
                .chain(other.variables.keys())
                .collect();
            keys.sort();
            keys.dedup();
            let show = |v: Option<&toml::Value>| v.map_or("(none)".into(), |v| v.to_string());
            for k in keys {
                let (a, b) = (self.variables.get(k), other.variables.get(k));
                if a != b {
                    return d(&format!("variable {k} ="), &show(a), &show(b));
                }
            }
        }
        if self.seed != other.seed {
            return d("seed", &self.seed, &other.seed);
        }
        if self.total_photons != other.total_photons {
            return d(
                "a run of",
                &format!("{} photons", self.total_photons),
                &other.total_photons,
            );
        }
        if self.shards != other.shards {
            return d(
                "cut into",
                &format!("{} shards", self.shards),
                &other.shards,
            );
        }
        if self.photon_list != other.photon_list {
            return d("--photon-list", &self.photon_list, &other.photon_list);
        }
        None
    }
}

fn short(hash: &str) -> String {
    hash.chars().take(12).collect()
}

/// The header of a run-state file: whose tally it is and how far it got.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StateHeader {
    pub identity: RunIdentity,
    /// Where the scene file was (absolute), and its `-D` overrides: how
    /// `--resume` loads it again.
    pub scene_path: PathBuf,
    pub overrides: Vec<String>,
    /// The shards (1..=shards) this tally holds.
    pub parts: Vec<u64>,
    /// Photons of those shards, and how many of them are traced.
    pub photons: u64,
    pub traced: u64,
    /// Tracing time so far (summed over shards and sittings).
    pub seconds: f64,
    /// Shards a partial merge left out (`traxer merge --partial`).
    pub missing: Vec<u64>,
    /// SHA-256 and length of the encoded tally that follows the header.
    pub tally_sha256: String,
    pub tally_bytes: u64,
}

impl StateHeader {
    /// Every photon of its parts is traced.
    pub fn complete(&self) -> bool {
        self.traced == self.photons
    }
}

/// A run's identity, parts and progress, before the tally is encoded.
pub struct RunPart {
    pub identity: RunIdentity,
    pub scene_path: PathBuf,
    pub overrides: Vec<String>,
    pub shard: Shard,
    pub seconds: f64,
}

impl RunPart {
    /// The part of `scene` that `cfg` traces, as shard `shard`.
    pub fn new(scene: &Scene, cfg: &RunConfig, shard: Shard) -> RunPart {
        RunPart {
            identity: RunIdentity::new(scene, cfg.seed, shard.total, shard.count, cfg.photon_list),
            scene_path: std::path::absolute(&scene.path).unwrap_or_else(|_| scene.path.clone()),
            overrides: scene.overrides.clone(),
            shard,
            seconds: 0.0,
        }
    }

    /// The header for `tally` (its encoding's hash and length are filled in when
    /// written).
    pub fn header(&self, tally: &Tally) -> StateHeader {
        StateHeader {
            identity: self.identity.clone(),
            scene_path: self.scene_path.clone(),
            overrides: self.overrides.clone(),
            parts: vec![self.shard.index],
            photons: self.shard.photons(),
            traced: tally.traced,
            seconds: self.seconds,
            missing: Vec::new(),
            tally_sha256: String::new(),
            tally_bytes: 0,
        }
    }
}
