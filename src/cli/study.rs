//! The CLI's side of a study (`traxer::run::run_study`): the scene loaded, a
//! progress bar, the stop message handed to the signal handler, warnings on
//! stderr. A study command parses its arguments into the study's settings,
//! calls [`run`] and prints the output.

use super::args::{OutputArgs, SceneArgs};
use super::{load_xray_scene, progress};
use std::path::PathBuf;
use traxer::embree::Device;
use traxer::output::StudyFiles;
use traxer::progress::Progress;
use traxer::run::{run_study, StudyControl, StudyPlace};
use traxer::scene::Scene;

struct CliStudy(progress::Bar, bool);

impl Progress for CliStudy {
    fn advance(&self, done: u64) {
        self.0.inc(done);
    }
}

impl StudyControl for CliStudy {
    fn warn(&self, warning: &str) {
        tell!("warning: {warning}");
    }

    fn stoppable(&self, message: &str) {
        super::signals::set_stop_message(message.to_string());
    }

    fn resumed(&self, message: &str) {
        if !self.1 {
            say!("{message}");
        }
    }

    fn point_finished(&self, description: &str) {
        if !self.1 {
            self.0.suspend(|| say!("{description}"));
        }
    }
}

/// Runs `kind` on the scene of `scene` into its results folder (--out, or
/// out/SCENE/NAME), resuming with `resume`; `note` may say something about
/// the scene before the study starts. Returns the output and the folder.
pub fn run<K: StudyFiles>(
    kind: &K,
    scene: &SceneArgs,
    output: &OutputArgs,
    resume: bool,
    note: impl FnOnce(&Scene),
) -> anyhow::Result<(K::Output, PathBuf)> {
    kind.check()?;
    let (device, loaded) = load_xray_scene(scene)?;
    note(&loaded);
    run_loaded(kind, (&device, &loaded), (scene, output), resume)
}

/// Runs `kind` on a scene the command has loaded already (to plan the study).
pub fn run_loaded<K: StudyFiles>(
    kind: &K,
    (device, loaded): (&Device, &Scene),
    (scene, output): (&SceneArgs, &OutputArgs),
    resume: bool,
) -> anyhow::Result<(K::Output, PathBuf)> {
    let out = output.scene_folder(scene, K::NAME);
    let quiet = output.quiet.quiet;
    let bar = progress::bar(kind.photons_total(loaded), "photons", quiet);
    let control = CliStudy(bar, quiet);
    let place = StudyPlace {
        out: Some(&out),
        resume,
    };
    let invocation = super::invocation();
    let result = run_study(
        kind,
        loaded,
        (device.info().version, &invocation),
        place,
        &control,
    );
    control.0.finish_and_clear();
    Ok((result?.0, out))
}
