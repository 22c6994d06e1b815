//! The running record of a study that traces point after point
//! (`fit-figure-error`'s evaluations, `focus`'s steps, `effective-area`'s
//! angles): `NAME_checkpoint.json` in the results folder, rewritten atomically
//! after every point, with what identifies the study (scene, variables, photons,
//! seed, its settings, traxer build). `--resume` reads it back and the study
//! takes the recorded points instead of tracing them again; every point depends
//! only on its settings and seed, so a study stopped at any moment and resumed
//! ends exactly as an uninterrupted one. The file disappears when the results
//! are put in place (it is not among them).
//!
//! The record carries the SHA-256 of the files the scene reads (`inputs`) and,
//! under `sha256`, that of its own text without that key: a record whose inputs
//! changed, or that was edited or damaged, is refused rather than replayed.

use super::InputError;
use crate::files::atomic_write;
use crate::scene::{input_difference, InputHashes, Scene};
use serde::{de::DeserializeOwned, Serialize};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// The identity every record starts from: the build, the scene file and its
/// variables; studies add their settings.
pub fn base_identity(scene: &Scene) -> serde_json::Map<String, Value> {
    let v = json!({
        "traxer_version": super::BUILD.version,
        "git_hash": super::BUILD.git_hash,
        "scene_sha256": scene.text_sha256,
        "variables": scene.vars,
        "inputs": scene.inputs,
    });
    v.as_object().expect("an object").clone()
}

/// The identity of a study that loads its scene file several times (with
/// different variables): the build, the file's SHA-256 and the `-D` overrides.
pub fn file_identity(
    scene: &Path,
    overrides: &[String],
) -> Result<serde_json::Map<String, Value>, InputError> {
    let bytes = std::fs::read(scene)
        .map_err(|e| InputError(format!("{}: cannot read it: {e}", scene.display())))?;
    let v = json!({
        "traxer_version": super::BUILD.version,
        "git_hash": super::BUILD.git_hash,
        "scene_sha256": crate::files::sha256_hex(&bytes),
        "overrides": overrides,
    });
    Ok(v.as_object().expect("an object").clone())
}

/// The record of a study being written into its results folder.
pub struct Record<T> {
    path: PathBuf,
    format: String,
    identity: Value,
    /// The files the scene read (studies that load their scene several times
    /// record them with the first load and check every later one).
    inputs: Option<InputHashes>,
    items: Vec<T>,
    /// A write failed (said once; the study goes on).
    failed: bool,
}

impl<T: Serialize + DeserializeOwned + Clone> Record<T> {
    /// The file name of `study`'s record.
    pub fn file_name(study: &str) -> String {
        format!("{study}_checkpoint.json")
    }

    /// Opens `study`'s record in `out`: with `resume`, the stopped study's
    /// points (checked to be this study's); without, refuses a folder holding a
    /// stopped study.
    pub fn open(
        out: &Path,
        study: &str,
        identity: Value,
        resume: bool,
    ) -> Result<Record<T>, InputError> {
        let mut record = Record {
            path: out.join(Self::file_name(study)),
            format: format!("traxer {study} checkpoint 1"),
            identity,
            inputs: None,
            items: Vec::new(),
            failed: false,
        };
        let p = record.path.display();
        match (resume, record.path.is_file()) {
            (false, false) => {}
            (false, true) => {
                return Err(InputError(format!(
                    "{}: holds the record of a stopped {study} ({p}): continue it by running the same command with --resume, or remove the file to start afresh",
                    out.display()
                )))
            }
            (true, false) => {
                return Err(InputError(format!(
                    "{}: has no {}: there is no stopped {study} to resume here",
                    out.display(),
                    Self::file_name(study)
                )))
            }
            (true, true) => (record.items, record.inputs) = record.read()?,
        }
        Ok(record)
    }

    /// The recorded points and inputs, after checking the record is whole and
    /// this study's.
    #[allow(clippy::type_complexity)]
    fn read(&self) -> Result<(Vec<T>, Option<InputHashes>), InputError> {
        let p = self.path.display();
        let text = std::fs::read_to_string(&self.path)
            .map_err(|e| InputError(format!("{p}: cannot read it: {e}")))?;
        let mut doc: Value = serde_json::from_str(&text)
            .map_err(|e| InputError(format!("{p}: is not a traxer record: {e}")))?;
        let recorded = doc
            .as_object_mut()
            .and_then(|d| d.remove("sha256"))
            .unwrap_or_default();
        if recorded.as_str() != Some(checksum(&doc).as_str()) {
            return Err(InputError(format!(
                "{p}: is damaged or was edited (its `sha256` is not that of its contents): remove it to start the study afresh"
            )));
        }
        if doc["format"] != self.format.as_str() {
            return Err(InputError(format!(
                "{p}: is not a record of this command (`format` is not \"{}\")",
                self.format
            )));
        }
        if let Some(diff) = difference(&doc["identity"], &self.identity) {
            return Err(InputError(format!(
                "{p}: records another run: {diff}; resume with the same scene, options and traxer build"
            )));
        }
        let inputs = match doc.get("inputs") {
            None => None,
            Some(v) => Some(
                serde_json::from_value(v.clone())
                    .map_err(|e| InputError(format!("{p}: its inputs cannot be read: {e}")))?,
            ),
        };
        let points = serde_json::from_value(doc["points"].clone())
            .map_err(|e| InputError(format!("{p}: its points cannot be read: {e}")))?;
        Ok((points, inputs))
    }

    /// The files the scene read, as recorded (by an earlier sitting or an
    /// earlier load).
    pub fn inputs(&self) -> Option<&InputHashes> {
        self.inputs.as_ref()
    }

    /// Records the files the scene read, written with the next point.
    pub fn set_inputs(&mut self, inputs: &InputHashes) {
        self.inputs.get_or_insert_with(|| inputs.clone());
    }

    /// Points recorded before (to take instead of tracing).
    pub fn recorded(&self) -> &[T] {
        &self.items
    }

    /// The point at `position` (0-based) is done: recorded and the file
    /// rewritten, unless it was recorded before. The first failure to write is
    /// returned as a warning to show (the study goes on, but cannot be resumed).
    #[must_use = "a failed write is returned as a warning to show"]
    pub fn add(&mut self, position: usize, item: &T) -> Option<String> {
        if position < self.items.len() {
            return None;
        }
        self.items.push(item.clone());
        let mut doc = json!({
            "format": self.format,
            "identity": self.identity,
            "points": self.items,
        });
        if let Some(inputs) = &self.inputs {
            doc["inputs"] = json!(inputs);
        }
        doc["sha256"] = checksum(&doc).into();
        let text = serde_json::to_string(&doc).expect("plain values");
        match atomic_write(&self.path, text.as_bytes()) {
            Err(err) if !self.failed => {
                self.failed = true;
                Some(format!(
                    "cannot record the progress ({err}); it cannot be resumed if stopped"
                ))
            }
            _ => None,
        }
    }
}

/// The SHA-256 of a record's text (without its `sha256` key). serde_json writes
/// the keys of its maps in one order and numbers exactly (`float_roundtrip`),
/// so the text read back and written again is the text written.
fn checksum(doc: &Value) -> String {
    crate::files::sha256_hex(serde_json::to_string(doc).expect("plain values").as_bytes())
}

/// Whether `scene` read the same files as recorded (`then`, if any); else which
/// one changed.
pub fn check_inputs(then: Option<&InputHashes>, scene: &Scene) -> Result<(), InputError> {
    match then.and_then(|t| input_difference(t, &scene.inputs)) {
        None => Ok(()),
        Some(diff) => Err(InputError(format!(
            "{}: the study so far was traced with {diff} as now: a file the scene reads changed; remove the record to start afresh",
            scene.path.display()
        ))),
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
