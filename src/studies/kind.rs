//! What a study is to the job that runs it (`run::study_job`): its settings,
//! which serialise into its identity (what a resumed study must share with the
//! stopped one) and begin with the [`Sampling`] block every study has; its
//! points, recorded one by one so that a stopped study resumes where it
//! stopped; and its output. The study computes; the job opens its folder,
//! records, stops, writes provenance and files (`output::StudyFiles`).
//!
//! A trait rather than an enum of the studies: each study's settings, points
//! and output are its own types, and the job is generic over them, so a new
//! study adds an impl beside its code instead of a variant to every match
//! (docs/layout.md argues it).

use super::StudyError;
use crate::progress::Progress;
use crate::scene::Scene;
use serde::{de::DeserializeOwned, Deserialize, Serialize};

/// Loads the study's scene with these variables set besides the front end's
/// (studies that trace the scene under other settings: systematics, focus).
pub type SceneLoader<'a> = &'a (dyn Fn(&[String]) -> Result<Scene, StudyError> + Sync);

/// Where a finished point came from: the record of a stopped study of the
/// same settings (taken as is), or a trace made now. The job counts the first
/// kind so that a resumed study says how many it did not trace again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointOrigin {
    Record,
    Traced,
}

/// How a study samples each of its points: the block every study shares.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Sampling {
    /// Photons per point.
    pub photons: u64,
    /// The seed of the photons' random streams.
    pub seed: u64,
    /// Worker threads (0 = one per core). Not part of a study's identity: the
    /// results do not depend on it.
    #[serde(skip)]
    pub threads: usize,
    /// The sensor the study reads (default: the scene's only one).
    pub sensor: Option<String>,
}

/// A study: settings that serialise, its points, its output.
pub trait StudyKind: Serialize + Sync {
    /// One finished point (an angle's areas, a PSF image), as its record keeps it.
    type Point: Serialize + DeserializeOwned + Clone;
    /// What the study returns.
    type Output;
    /// Its name: the record's file name and the default results folder.
    const NAME: &'static str;
    /// What its points are called when it stops ("angles", "points").
    const POINTS: &'static str;

    /// The sampling block of its settings.
    fn sampling(&self) -> &Sampling;

    /// Checks the settings (before the scene is loaded).
    fn check(&self) -> Result<(), StudyError>;

    /// The photons it traces in all (for a progress bar).
    fn photons_total(&self, scene: &Scene) -> u64;

    /// Runs the study: the points of `replay` (recorded before) are taken
    /// instead of traced; `on_point` is told of each point as it is done and
    /// whether it came from the record; the
    /// study returns [`StudyError::Stopped`] after a point when
    /// `progress.stop_requested()` and points remain.
    fn run(
        &self,
        scene: &Scene,
        replay: &[Self::Point],
        progress: &dyn Progress,
        on_point: &mut dyn FnMut(&Self::Point, PointOrigin),
    ) -> Result<Self::Output, StudyError>;

    /// The worker threads the output was computed with.
    fn threads_used(output: &Self::Output) -> usize;

    /// A line about a point just finished, for a front end to show (focus:
    /// each position's diameters); none by default.
    fn describe(&self, _point: &Self::Point) -> Option<String> {
        None
    }
}
