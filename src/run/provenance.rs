//! Provenance built in one place, once per kind of result: a run of photons
//! ([`Provenance::of_run`]: trace, merge, resume, Python), a study's points
//! ([`Provenance::of_study`]: focus, compare, effective area, PSF, systematics,
//! the fit, the live window's save), a picture of a scene
//! ([`Provenance::of_picture`]) and a table or plot that reads no scene
//! ([`Provenance::of_table`]). Every front end (the CLI, the Python module, the
//! live window) gives its [`Invocation`] — what the user ran, as the front end
//! knows it (the library never reads `argv`). `output` writes the record; a
//! layout test keeps `Provenance::new` in this module.

use super::{Shard, StateHeader};
use crate::output::Provenance;
use crate::scene::Scene;
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

/// This build, as every record names it (provenance, run identities, study
/// records): the version and the commit it was built from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Build {
    pub version: &'static str,
    pub git_hash: &'static str,
}

/// The build this program is.
pub const BUILD: Build = Build {
    version: env!("CARGO_PKG_VERSION"),
    git_hash: env!("TRAXER_GIT_HASH"),
};

/// The commit the binary was built from.
pub fn git_hash() -> &'static str {
    BUILD.git_hash
}

impl Provenance {
    /// A run of photons: the scene, the run's parts as its run state records
    /// them (seed, photons, shards, time; a merge names `merged_from`), and the
    /// threads that traced it (`None` for a merge, which traces nothing).
    pub fn of_run(
        invocation: &Invocation,
        embree_version: String,
        scene: &Scene,
        header: &StateHeader,
        threads: Option<usize>,
        merged_from: &[PathBuf],
    ) -> Provenance {
        Provenance {
            threads,
            ..Provenance::new(invocation, Some(embree_version)).scene(scene)
        }
        .parts(header, merged_from)
    }

    /// A study's results: the scene (as its first load read it), `photons` per
    /// point from photon 0 with `seed`, on `threads`.
    pub fn of_study(
        invocation: &Invocation,
        embree_version: String,
        scene: &Scene,
        (photons, seed): (u64, u64),
        threads: usize,
    ) -> Provenance {
        Provenance {
            seed: Some(seed),
            photons: Some(photons),
            threads: Some(threads),
            first_photon: Some(0),
            ..Provenance::new(invocation, Some(embree_version)).scene(scene)
        }
    }

    /// A picture of the scene (a render): its sampling seed and threads, no
    /// photons.
    pub fn of_picture(
        invocation: &Invocation,
        embree_version: String,
        scene: &Scene,
        seed: u64,
        threads: usize,
    ) -> Provenance {
        Provenance {
            seed: Some(seed),
            threads: Some(threads),
            ..Provenance::new(invocation, Some(embree_version)).scene(scene)
        }
    }

    /// A table or plot that reads no scene and traces nothing (reflectivity,
    /// the solar flux, an EEF of a given image).
    pub fn of_table(invocation: &Invocation) -> Provenance {
        Provenance::new(invocation, None)
    }

    /// The same record with the count of points a resumed study took from its
    /// record (`None`: a study without a results folder).
    pub fn with_points_from_record(self, points: Option<usize>) -> Provenance {
        Provenance {
            points_from_record: points,
            ..self
        }
    }

    /// The same record with the threads that were used (a study knows them at
    /// its end).
    pub fn with_threads(self, threads: usize) -> Provenance {
        Provenance {
            threads: Some(threads),
            ..self
        }
    }

    /// This program, this command line, now; with the Embree version when Embree
    /// was used.
    fn new(invocation: &Invocation, embree_version: Option<String>) -> Provenance {
        Provenance {
            traxer_version: BUILD.version.into(),
            git_hash: BUILD.git_hash.into(),
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
            points_from_record: None,
            command_line: invocation.command_line.clone(),
            finished_unix_s: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_secs())
                .unwrap_or(0),
        }
    }

    /// With the scene that was traced or rendered.
    fn scene(self, scene: &Scene) -> Provenance {
        Provenance {
            scene_path: Some(scene.path.display().to_string()),
            scene_sha256: Some(scene.text_sha256.clone()),
            overrides: scene.overrides.clone(),
            variables: scene.vars.clone(),
            ..self
        }
    }

    /// With the run's parts, as recorded in its run state (a shard, a resumed run
    /// or a merge of `merged_from`); `photons` is then the photons these results
    /// hold.
    fn parts(self, header: &StateHeader, merged_from: &[PathBuf]) -> Provenance {
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
}
