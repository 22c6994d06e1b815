//! Python's side of a run's life (`traxer::run`): `Scene.trace(..., out=DIR,
//! checkpoint_every=S)` traces into a results folder as `traxer trace` does,
//! keeping a checkpoint there, and `traxer.resume(DIR)` continues a stopped run
//! (from Python or the CLI) to the same files. Ctrl-C (KeyboardInterrupt) stops
//! a checkpointing run after its current batch, with the checkpoint written.

use crate::convert::{progress_bar, threads};
use crate::errors::lib;
use crate::result::TraceResult;
use crate::scene::Loaded;
use crate::units::Unit;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Duration;
use traxer::output::Provenance;
use traxer::run::{
    open_finished, open_stopped, read_state, Found, Invocation, Resumable, RunControl, RunError,
    RunSettings, StateHeader, RUN_STATE_FILE,
};
use traxer::trace::Tally;

/// A progress bar, and Python's signals checked between batches.
pub struct PyControl {
    pub bar: indicatif::ProgressBar,
    interrupted: Mutex<Option<PyErr>>,
}

impl PyControl {
    pub fn new(photons: u64, progress: bool) -> PyControl {
        PyControl {
            bar: progress_bar(photons, progress),
            interrupted: Mutex::new(None),
        }
    }

    /// The run's error as Python sees it: a KeyboardInterrupt (with a note on the
    /// checkpoint) if Ctrl-C stopped it.
    pub fn error(&self, e: RunError) -> PyErr {
        let interrupt = self.interrupted.lock().ok().and_then(|mut i| i.take());
        match (interrupt, &e) {
            (Some(interrupt), RunError::Stopped(s)) => {
                Python::attach(|py| {
                    // Python 3.11+: the note says how to continue.
                    let _ = interrupt.value(py).call_method1("add_note", (s.0.clone(),));
                });
                interrupt
            }
            _ => lib(e),
        }
    }
}

impl RunControl for PyControl {
    fn advance(&self, photons: u64) {
        self.bar.inc(photons);
    }

    fn stop_requested(&self) -> bool {
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => false,
            Err(e) => {
                if let Ok(mut i) = self.interrupted.lock() {
                    i.get_or_insert(e);
                }
                true
            }
        }
    }
}

/// A study (`traxer::run::run_study`) reports its photons to the bar and asks
/// between its points whether Ctrl-C was pressed.
impl traxer::progress::Progress for PyControl {
    fn advance(&self, done: u64) {
        self.bar.inc(done);
    }

    fn stop_requested(&self) -> bool {
        RunControl::stop_requested(self)
    }
}

impl traxer::run::StudyControl for PyControl {
    fn warn(&self, warning: &str) {
        Python::attach(|py| {
            let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
            // A warning that cannot be shown is not worth failing the study.
            let _ = PyErr::warn(
                py,
                &category,
                &std::ffi::CString::new(warning).unwrap_or_default(),
                1,
            );
        });
    }
}

/// Runs study `kind` on `loaded`'s scene with the GIL released: into the
/// results folder `out` (resuming with `resume`) when given, as the CLI does;
/// Ctrl-C stops it between points with a KeyboardInterrupt whose note says how
/// to continue. Returns its output and provenance.
pub fn run_study<K: traxer::output::StudyFiles + Send>(
    py: Python<'_>,
    loaded: &Loaded,
    (kind, method): (&K, &str),
    (out, resume): (Option<PathBuf>, bool),
    progress: bool,
) -> PyResult<(K::Output, Provenance)>
where
    K::Output: Send,
{
    if resume && out.is_none() {
        return Err(crate::errors::input(
            "resume=True needs out=: the folder of the stopped study".to_string(),
        ));
    }
    kind.check().map_err(lib)?;
    let scene = &loaded.scene;
    // The call and the study's settings (the provenance's command).
    let invocation = Invocation::new([
        "python".into(),
        format!(
            "traxer.Scene({:?}, defines={:?}).{method}(…) with settings {}",
            scene.path.display().to_string(),
            scene.overrides,
            serde_json::to_string(kind).unwrap_or_default()
        ),
    ]);
    let control = PyControl::new(kind.photons_total(scene), progress);
    let place = traxer::run::StudyPlace {
        out: out.as_deref(),
        resume,
    };
    let version = loaded.device.info().version;
    let result =
        py.detach(|| traxer::run::run_study(kind, scene, (version, &invocation), place, &control));
    control.bar.finish_and_clear();
    result.map_err(|e| control.error(e))
}

/// `checkpoint_every` (seconds) checked.
pub fn checkpoint_interval(seconds: Option<f64>) -> PyResult<Option<Duration>> {
    match seconds {
        None => Ok(None),
        Some(s) if (0.0..1e9).contains(&s) => Ok(Some(Duration::from_secs_f64(s))),
        Some(s) => Err(crate::errors::input(format!(
            "checkpoint_every={s}: expected seconds between checkpoints, 0 or more"
        ))),
    }
}

/// The finished run in `out` as a `TraceResult` (its exact sums read back from
/// `run_state.bin`, so that the result equals the files bit for bit).
pub fn finished_result(
    py: Python<'_>,
    loaded: Arc<Loaded>,
    out: &Path,
    invocation: &Invocation,
    threads: usize,
) -> PyResult<TraceResult> {
    let (header, tally) = read_state(&out.join(RUN_STATE_FILE)).map_err(lib)?;
    result_of(py, loaded, (header, tally), invocation, threads)
}

/// A run's result from its run state, with its provenance.
fn result_of(
    py: Python<'_>,
    loaded: Arc<Loaded>,
    (header, tally): (StateHeader, Tally),
    invocation: &Invocation,
    threads: usize,
) -> PyResult<TraceResult> {
    let provenance = Provenance::of_run(
        invocation,
        loaded.device.info().version,
        &loaded.scene,
        &header,
        Some(threads),
        &[],
    );
    TraceResult::new(py, loaded, header, tally, threads, provenance)
}

/// Continues the stopped run in `folder` (a `Scene.trace(..., out=folder,
/// checkpoint_every=S)` or `traxer trace --checkpoint-every S` that was stopped)
/// to its end, writing the same files as an uninterrupted run, and returns its
/// result. A finished run's folder returns its result at once, once its scene
/// is checked to be the run's (the same file, input files and variables).
/// `scene`: where the scene file is now, if it moved (its SHA-256 is checked).
/// Ctrl-C stops it again after the current batch, with the checkpoint written.
#[pyfunction]
#[pyo3(signature = (folder, threads = 0, checkpoint_every = None, progress = false, scene = None), text_signature = "(folder, threads=0, checkpoint_every=60.0, progress=False, scene=None)")]
pub fn resume(
    py: Python<'_>,
    folder: PathBuf,
    threads: usize,
    checkpoint_every: Option<&Bound<'_, PyAny>>,
    progress: bool,
    scene: Option<PathBuf>,
) -> PyResult<TraceResult> {
    let checkpoint_every =
        crate::units::optional("checkpoint_every", checkpoint_every, Unit::Second)?.unwrap_or(60.0);
    // A resumed run stays resumable: it keeps its checkpoint.
    let settings = RunSettings {
        threads: self::threads(threads)?,
        checkpoint_every: checkpoint_interval(Some(checkpoint_every))?,
        fits: false,
        replace: false,
    };
    let invocation = Invocation::new([
        "python".to_string(),
        format!(
            "traxer.resume({:?}, threads={threads}, checkpoint_every={checkpoint_every})",
            folder.display().to_string()
        ),
    ]);
    let found = py
        .detach(|| open_stopped(&folder, scene.as_deref()))
        .map_err(lib)?;
    let mut run: Box<Resumable> = match found {
        Found::Stopped(run) => run,
        // A finished run: its result, once its scene is checked to be the
        // run's (as a stopped run's is).
        Found::Finished(_) => {
            let (device, scene, header, tally) = py
                .detach(|| open_finished(&folder, scene.as_deref()))
                .map_err(lib)?;
            let loaded = Arc::new(Loaded { scene, device });
            return result_of(py, loaded, (header, tally), &invocation, 0);
        }
    };
    let (traced, photons) = run.progress();
    let control = PyControl::new(photons, progress);
    control.bar.inc(traced);
    let finished = py.detach(|| run.run(&settings, &invocation, &control));
    control.bar.finish_and_clear();
    let finished = finished.map_err(|e| control.error(e))?;
    let threads = finished.result.threads;
    let Resumable { scene, device, .. } = *run;
    let loaded = Arc::new(Loaded { scene, device });
    finished_result(py, loaded, &folder, &invocation, threads)
}
