//! The running record of `traxer fit-figure-error`: `fit_checkpoint.json` in the
//! results folder, rewritten atomically after every evaluation, with what
//! identifies the fit (scene, variables, photons, seed, bounds, targets, budget,
//! traxer build). `--resume` reads it back, and the fit replays the recorded
//! evaluations instead of tracing them (`traxer::studies::fit::fit`), so a fit
//! stopped at any moment and resumed ends exactly as an uninterrupted one. The
//! file disappears when the results are put in place.

use super::InputError;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use traxer::files::atomic_write;
use traxer::scene::Scene;
use traxer::studies::fit::{Evaluation, FitSettings};

/// The record's file name.
pub const FIT_CHECKPOINT: &str = "fit_checkpoint.json";
const FORMAT: &str = "traxer fit checkpoint 1";

/// What must be equal for a recorded evaluation to be this fit's.
pub fn identity(scene: &Scene, settings: &FitSettings) -> Value {
    let s = settings;
    json!({
        "traxer_version": env!("CARGO_PKG_VERSION"),
        "git_hash": env!("TRAXER_GIT_HASH"),
        "scene_sha256": scene.text_sha256,
        "variables": scene.vars,
        "sensor": scene.sensors[s.sensor].name,
        "photons": s.run.photons,
        "seed": s.run.seed,
        "target_arcsec": s.target,
        "bounds_lower": s.bounds.lower,
        "bounds_upper": s.bounds.upper,
        "global_evaluations": s.global_evaluations,
        "local_evaluations": s.local_evaluations,
        "local_algorithm": format!("{:?}", s.local_algorithm),
    })
}

/// The record of a fit being written into the results folder `out`.
pub struct FitRecord {
    path: PathBuf,
    identity: Value,
    evaluations: Vec<Evaluation>,
    /// The first write failure (reported once; the fit goes on).
    failed: bool,
}

impl FitRecord {
    /// Opens the record in `out`: with `resume`, the stopped fit's evaluations
    /// (checked to be this fit's); without, refuses a folder holding a stopped fit.
    pub fn open(out: &Path, identity: Value, resume: bool) -> Result<FitRecord, InputError> {
        let path = out.join(FIT_CHECKPOINT);
        let exists = path.is_file();
        let mut record = FitRecord {
            path,
            identity,
            evaluations: Vec::new(),
            failed: false,
        };
        let p = record.path.display();
        match (resume, exists) {
            (false, false) => {}
            (false, true) => {
                return Err(InputError(format!(
                    "{}: holds the record of a stopped fit ({p}): continue it by running the same command with --resume, or remove the file to start afresh",
                    out.display()
                )))
            }
            (true, false) => {
                return Err(InputError(format!(
                    "{}: has no {FIT_CHECKPOINT}: there is no stopped fit to resume here",
                    out.display()
                )))
            }
            (true, true) => record.evaluations = record.read()?,
        }
        Ok(record)
    }

    /// The recorded evaluations, after checking the record is this fit's.
    fn read(&self) -> Result<Vec<Evaluation>, InputError> {
        let p = self.path.display();
        let text = std::fs::read_to_string(&self.path)
            .map_err(|e| InputError(format!("{p}: cannot read it: {e}")))?;
        let doc: Value = serde_json::from_str(&text)
            .map_err(|e| InputError(format!("{p}: is not a fit record: {e}")))?;
        if doc["format"] != FORMAT {
            return Err(InputError(format!(
                "{p}: is not a fit record (`format` is not \"{FORMAT}\")"
            )));
        }
        if let Some(diff) = difference(&doc["identity"], &self.identity) {
            return Err(InputError(format!(
                "{p}: records another fit: {diff}; resume with the same scene, options and traxer build"
            )));
        }
        serde_json::from_value(doc["evaluations"].clone())
            .map_err(|e| InputError(format!("{p}: its evaluations cannot be read: {e}")))
    }

    /// Evaluations recorded before (to replay).
    pub fn recorded(&self) -> &[Evaluation] {
        &self.evaluations
    }

    /// Records evaluation `e`; rewrites the file when it is new.
    pub fn add(&mut self, e: &Evaluation) {
        if e.index <= self.evaluations.len() {
            return; // replayed: recorded already
        }
        self.evaluations.push(e.clone());
        let doc = json!({
            "format": FORMAT,
            "identity": self.identity,
            "evaluations": self.evaluations,
        });
        let text = serde_json::to_string(&doc).expect("plain values");
        if let Err(err) = atomic_write(&self.path, text.as_bytes()) {
            if !self.failed {
                tell!("warning: cannot record the fit's progress ({err}); it cannot be resumed if stopped");
                self.failed = true;
            }
        }
    }
}

/// The first key whose value differs, said for a person.
fn difference(recorded: &Value, now: &Value) -> Option<String> {
    let (Some(a), Some(b)) = (recorded.as_object(), now.as_object()) else {
        return Some("its identity cannot be read".into());
    };
    b.iter().find(|(k, v)| a.get(*k) != Some(v)).map(|(k, v)| {
        format!(
            "{k} {} there, {v} now",
            a.get(k).map_or("(none)".into(), Value::to_string)
        )
    })
}
