//! The systematics study as the study job runs it ([`crate::studies::StudyKind`]):
//! its settings, the plan made from the nominal scene, and how to load the
//! scene with more variables set.

use super::{run, Outcome, Plan, Settings, Systematics};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::studies::{PointOrigin, Sampling, SceneLoader, StudyError, StudyKind};
use serde::Serialize;

/// The study: serialised, its identity (settings and variations).
#[derive(Serialize)]
pub struct SystematicsStudy<'a> {
    #[serde(flatten)]
    pub settings: Settings,
    #[serde(rename = "variations", serialize_with = "variations_only")]
    pub plan: &'a Plan,
    /// Loads the scene (the nominal one: with no variables more).
    #[serde(skip)]
    pub load: SceneLoader<'a>,
    /// The scene's name for people (the files' titles).
    #[serde(skip)]
    pub scene_name: String,
}

fn variations_only<S: serde::Serializer>(plan: &&Plan, s: S) -> Result<S::Ok, S::Error> {
    plan.variations.serialize(s)
}

impl StudyKind for SystematicsStudy<'_> {
    type Point = Outcome;
    type Output = Systematics;
    const NAME: &'static str = "systematics";
    const POINTS: &'static str = "variations";

    fn sampling(&self) -> &Sampling {
        &self.settings.sampling
    }

    fn check(&self) -> Result<(), StudyError> {
        super::check(&self.settings)
    }

    fn photons_total(&self, _scene: &Scene) -> u64 {
        let n = self.plan.variations.len() as u64;
        self.settings.sampling.photons.saturating_mul(n)
    }

    /// Traces the variations on a scene of its own (the figure draws change
    /// its mirrors in place), loaded as the front end's.
    fn run(
        &self,
        _scene: &Scene,
        replay: &[Outcome],
        progress: &dyn Progress,
        on_point: &mut dyn FnMut(&Outcome, PointOrigin),
    ) -> Result<Systematics, StudyError> {
        let mut nominal = (self.load)(&[])?;
        run(
            &mut nominal,
            self.load,
            self.plan,
            &self.settings,
            replay,
            progress,
            on_point,
        )
    }

    fn threads_used(output: &Systematics) -> usize {
        output.facts.threads
    }
}
