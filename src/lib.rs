//! traxer: an X-ray raytracer for grazing-incidence telescopes, on Intel Embree.
//!
//! Data flow (the layout and its rules: docs/layout.md):
//! `scene` (file → description → built scene with Embree; `geometry`, `mesh`,
//! `xray`, `source` build its parts) → `trace` (the photon loop: `source` emits,
//! `raycast` finds hits, `material` decides) → `sensor` (exact images and their
//! tallies) → `analysis` (HPD, EEF) → `output` (files). Around a run, `run`
//! (provenance, results folder, checkpoints, shards, study records); above it,
//! `studies` (focus, effective area, PSF, fits, systematics), `render` (visible
//! light) and `bench`. Leaves used by all: `constants`, `colormap`, `files`,
//! `text`, `random`, `progress`.
#![deny(unsafe_code)]

/// Declares a typed error that carries its message: for checks whose whole
/// content is what to tell the user (the caller adds where: file, line, key).
macro_rules! message_error {
    ($(#[$meta:meta])* $name:ident) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
        #[error("{0}")]
        pub struct $name(pub String);

        impl From<String> for $name {
            fn from(message: String) -> Self {
                $name(message)
            }
        }

        impl From<&str> for $name {
            fn from(message: &str) -> Self {
                $name(message.to_string())
            }
        }
    };
}

pub mod analysis;
pub mod bench;
pub mod colormap;
pub mod constants;
pub mod embree;
pub mod environment;
pub mod files;
pub mod geometry;
pub mod history;
pub mod magnet;
pub mod material;
pub mod mesh;
pub mod output;
pub mod progress;
pub mod random;
pub mod raycast;
pub mod render;
pub mod run;
pub mod scene;
pub mod sensor;
pub mod source;
pub mod studies;
pub mod text;
pub mod trace;
pub mod xray;

/// Whether an error of the library is the user's input (a scene, a mesh, a data
/// file, an output location, a setting) rather than a failure of the machine:
/// the binary exits with code 2 for these, the Python module raises `InputError`.
pub fn is_bad_input(e: &(dyn std::error::Error + 'static)) -> bool {
    e.downcast_ref::<scene::SceneError>()
        .is_some_and(scene::SceneError::is_bad_input)
        || e.is::<mesh::MeshError>()
        || e.is::<output::NpyError>()
        || e.is::<files::OutputLocationError>()
        || e.is::<source::sun::SolarDataError>()
        || e.is::<run::RunStateError>()
        || e.is::<run::MergeError>()
        || e.is::<run::InputError>()
        || e.downcast_ref::<run::RunError>()
            .is_some_and(run::RunError::is_bad_input)
        || e.is::<xray::CoatingSpecError>()
        || e.downcast_ref::<studies::StudyError>()
            .is_some_and(studies::StudyError::is_bad_input)
}
