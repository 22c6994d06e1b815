//! How the command line watches a run (`traxer::run`): a progress bar, signals
//! that stop a checkpointing run gracefully, the report when it is done; and
//! `traxer trace --resume DIR`.

use super::progress::Bar;
use super::signals::{checkpoint_on_signals, stop_requested};
use std::path::Path;
use traxer::run::{open_stopped, Finished, Found, RunControl, RunSettings};
use traxer::scene::Scene;

/// A run's progress bar and the process's signals.
pub struct CliControl {
    bar: Bar,
}

impl CliControl {
    /// A bar over `photons` (hidden when `quiet` or not on a terminal).
    pub fn new(photons: u64, quiet: bool) -> CliControl {
        CliControl {
            bar: super::progress::bar(photons, "photons", quiet),
        }
    }
}

impl RunControl for CliControl {
    fn advance(&self, photons: u64) {
        self.bar.inc(photons);
    }

    fn stop_requested(&self) -> bool {
        stop_requested()
    }

    fn checkpointing(&self, on: bool) {
        checkpoint_on_signals(on);
    }
}

/// The end of a run on stdout: its report and where its files are.
pub fn finish(scene: &Scene, finished: Finished, control: &CliControl, quiet: bool) {
    control.bar.finish_and_clear();
    super::report::warn_about_sensors(scene, &finished.result);
    if !quiet {
        super::report::report(scene, &finished.result);
        say!(
            "wrote {} files to {}",
            finished.files,
            finished.out.display()
        );
    }
}

/// `traxer trace [SCENE] --resume DIR`: SCENE if the scene moved since.
pub fn resume(
    dir: &Path,
    moved_scene: Option<&Path>,
    settings: &RunSettings,
    quiet: bool,
) -> anyhow::Result<()> {
    let mut run = match open_stopped(dir, moved_scene)? {
        Found::Finished(photons) => {
            say!(
                "{}: the run is finished ({photons} photons); nothing to resume",
                dir.display()
            );
            return Ok(());
        }
        Found::Stopped(run) => run,
    };
    super::Warnings::default().show(&run.scene);
    let (traced, photons) = run.progress();
    if !quiet {
        say!(
            "resuming {} after {traced} of {photons} photons",
            dir.display()
        );
    }
    let control = CliControl::new(photons, quiet);
    control.bar.set_position(traced);
    let finished = run.run(settings, &super::invocation(), &control)?;
    finish(&run.scene, finished, &control, quiet);
    Ok(())
}
