//! The running record of a study that traces point after point
//! (`fit-figure-error`'s evaluations, `focus`'s steps, `effective-area`'s
//! angles): `NAME_checkpoint.jsonl` in the results folder, a header line with
//! what identifies the study (scene, variables, photons, seed, its settings,
//! traxer build), then one line per finished point, appended (a study of n
//! points writes O(n) bytes, not the O(n²) of a file rewritten per point). `--resume` reads it back and the study
//! takes the recorded points instead of tracing them again; every point depends
//! only on its settings and seed, so a study stopped at any moment and resumed
//! ends exactly as an uninterrupted one. The file disappears when the results
//! are put in place (it is not among them).
//!
//! The header carries the SHA-256 of the files the scene reads (`inputs`) and,
//! under `sha256`, that of its own text without that key; each point's line
//! the SHA-256 of the line before's and its point's text (a chain): a record
//! whose inputs changed, or that was edited or damaged, is refused rather than
//! replayed.

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
    /// The chained SHA-256 of the last line on disk; `None` until this
    /// sitting has written the whole file once (the next point rewrites it).
    chain: Option<String>,
    /// A write failed (said once; the study goes on).
    failed: bool,
}

impl<T: Serialize + DeserializeOwned + Clone> Record<T> {
    /// The file name of `study`'s record.
    pub fn file_name(study: &str) -> String {
        format!("{study}_checkpoint.jsonl")
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
            format: format!("traxer {study} checkpoint 2"),
            identity,
            inputs: None,
            items: Vec::new(),
            chain: None,
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
    /// this study's. A last line without its newline is a point whose append a
    /// kill cut short: left out (its point is traced again).
    #[allow(clippy::type_complexity)]
    fn read(&self) -> Result<(Vec<T>, Option<InputHashes>), InputError> {
        let p = self.path.display();
        let text = std::fs::read_to_string(&self.path)
            .map_err(|e| InputError(format!("{p}: cannot read it: {e}")))?;
        let damaged = |line: usize| {
            InputError(format!(
                "{p}: line {line} is damaged or was edited (its `sha256` is not that of its contents and the lines before): remove the file to start the study afresh"
            ))
        };
        let whole = text.rsplit_once('\n').map_or("", |(whole, _)| whole);
        let mut lines = whole.lines();
        let mut header: Value = lines
            .next()
            .and_then(|l| serde_json::from_str(l).ok())
            .ok_or_else(|| InputError(format!("{p}: is not a traxer record")))?;
        let recorded = header
            .as_object_mut()
            .and_then(|d| d.remove("sha256"))
            .unwrap_or_default();
        let mut chain = checksum(&header);
        if recorded.as_str() != Some(chain.as_str()) {
            return Err(damaged(1));
        }
        if header["format"] != self.format.as_str() {
            return Err(InputError(format!(
                "{p}: is not a record of this command (`format` is not \"{}\")",
                self.format
            )));
        }
        if let Some(diff) = difference(&header["identity"], &self.identity) {
            return Err(InputError(format!(
                "{p}: records another run: {diff}; resume with the same scene, options and traxer build"
            )));
        }
        let inputs = match header.get("inputs") {
            None => None,
            Some(v) => Some(
                serde_json::from_value(v.clone())
                    .map_err(|e| InputError(format!("{p}: its inputs cannot be read: {e}")))?,
            ),
        };
        let mut points = Vec::new();
        for (k, line) in lines.enumerate() {
            let mut doc: Value = serde_json::from_str(line).map_err(|_| damaged(k + 2))?;
            let recorded = doc
                .as_object_mut()
                .and_then(|d| d.remove("sha256"))
                .unwrap_or_default();
            chain = chained(&chain, &doc["point"]);
            if recorded.as_str() != Some(chain.as_str()) {
                return Err(damaged(k + 2));
            }
            points.push(serde_json::from_value(doc["point"].take()).map_err(|e| {
                InputError(format!(
                    "{p}: its point on line {} cannot be read: {e}",
                    k + 2
                ))
            })?);
        }
        Ok((points, inputs))
    }

    /// The files the scene read, as recorded (by an earlier sitting or an
    /// earlier load).
    pub fn inputs(&self) -> Option<&InputHashes> {
        self.inputs.as_ref()
    }

    /// Records the files the scene read, written with the next point.
    pub fn set_inputs(&mut self, inputs: &InputHashes) {
        if self.inputs.is_none() {
            self.inputs = Some(inputs.clone());
            // The header carries them: the next point rewrites the file.
            self.chain = None;
        }
    }

    /// Points recorded before (to take instead of tracing).
    pub fn recorded(&self) -> &[T] {
        &self.items
    }

    /// The point at `position` (0-based) is done: recorded, unless it was
    /// recorded before. The point is appended as one line, so a study of n
    /// points writes O(n) bytes in all; the file is written whole (atomically)
    /// only by a sitting's first point. The first failure to write is returned
    /// as a warning to show; the study goes on, and the file keeps the points
    /// before the failure (nothing more is written to it: a line chained to
    /// one that is missing would make the whole record read as damaged).
    #[must_use = "a failed write is returned as a warning to show"]
    pub fn add(&mut self, position: usize, item: &T) -> Option<String> {
        if position < self.items.len() {
            return None;
        }
        self.items.push(item.clone());
        if self.failed {
            // After a failed write the file stops where it was: a later line
            // chained to the one that failed would make the whole record read
            // as damaged, and the points before it could not be resumed.
            return None;
        }
        let written = match &self.chain {
            Some(chain) => {
                let (line, chain) = point_line(chain, item);
                self.chain = Some(chain);
                append(&self.path, line.as_bytes())
            }
            None => {
                let (text, chain) = self.whole_text();
                self.chain = Some(chain);
                atomic_write(&self.path, text.as_bytes())
            }
        };
        match written {
            Err(err) if !self.failed => {
                self.failed = true;
                Some(format!(
                    "cannot record the progress in {} ({err}): the study goes on, but a stop now keeps only the {} point(s) recorded before; that record stays behind in the folder until the study ends (then it is removed) — a resume takes up those points and traces the rest",
                    self.path.display(),
                    position
                ))
            }
            _ => None,
        }
    }

    /// The whole record's text and the chain after its last line.
    fn whole_text(&self) -> (String, String) {
        let mut header = json!({
            "format": self.format,
            "identity": self.identity,
        });
        if let Some(inputs) = &self.inputs {
            header["inputs"] = json!(inputs);
        }
        let mut chain = checksum(&header);
        header["sha256"] = chain.clone().into();
        let mut text = serde_json::to_string(&header).expect("plain values");
        text.push('\n');
        for item in &self.items {
            let (line, next) = point_line(&chain, item);
            text.push_str(&line);
            chain = next;
        }
        (text, chain)
    }
}

/// A point's line (with its newline) after the line whose chain is `chain`,
/// and the chain after it.
fn point_line<T: Serialize>(chain: &str, item: &T) -> (String, String) {
    let point = json!(item);
    let next = chained(chain, &point);
    let mut line =
        serde_json::to_string(&json!({ "point": point, "sha256": next })).expect("plain values");
    line.push('\n');
    (line, next)
}

/// Appends one line in a single write: a kill leaves at most that line
/// without its newline, which reading leaves out.
fn append(path: &Path, line: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut f = std::fs::OpenOptions::new().append(true).open(path)?;
    f.write_all(line)?;
    f.sync_data()
}

/// The SHA-256 of a record's header text (without its `sha256` key). serde_json
/// writes the keys of its maps in one order and numbers exactly
/// (`float_roundtrip`), so the text read back and written again is the text
/// written.
fn checksum(doc: &Value) -> String {
    crate::files::sha256_hex(serde_json::to_string(doc).expect("plain values").as_bytes())
}

/// The chain after a point: the SHA-256 of the previous line's chain and the
/// point's text, so that an edited, removed or reordered line is found.
fn chained(chain: &str, point: &Value) -> String {
    let text = serde_json::to_string(point).expect("plain values");
    crate::files::sha256_hex(format!("{chain}{text}").as_bytes())
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
    b.iter()
        .find(|(k, v)| a.get(*k) != Some(v))
        .map(|(k, v)| match (a.get(k), v) {
            // Lists (angles, energies, variations): where they part, not both
            // whole.
            (Some(Value::Array(x)), Value::Array(y)) => {
                let at = x.iter().zip(y).position(|(p, q)| p != q);
                let value = |l: &[Value], i: usize| l.get(i).map_or("nothing".into(), short);
                match at {
                    Some(i) => format!(
                        "{k}: number {} is {} there, {} now ({} values there, {} now)",
                        i + 1,
                        value(x, i),
                        value(y, i),
                        x.len(),
                        y.len()
                    ),
                    None => format!("{k}: {} values there, {} now", x.len(), y.len()),
                }
            }
            (there, now) => format!(
                "{k} {} there, {} now",
                there.map_or("(none)".into(), short),
                short(now)
            ),
        })
}

/// A value for a message, at most 120 characters.
fn short(v: &Value) -> String {
    crate::text::shorten(&v.to_string(), 120)
}

#[cfg(test)]
mod tests {
    use super::Record;
    use serde_json::json;

    #[test]
    fn a_full_disk_keeps_the_points_before_it_and_says_where_they_are() {
        // /dev/full fails every write with "No space left on device": the
        // record's file is pointed at it after two points, then back.
        let dir = tempfile::tempdir().unwrap();
        let mut r: Record<u32> = Record::open(dir.path(), "focus", json!({"a": 1}), false).unwrap();
        assert_eq!(r.add(0, &10), None);
        assert_eq!(r.add(1, &11), None);
        let path = dir.path().join(Record::<u32>::file_name("focus"));
        let before = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        std::os::unix::fs::symlink("/dev/full", &path).unwrap();
        let said = r.add(2, &12).expect("the failure is said");
        assert!(
            said.contains("No space left on device")
                && said.contains(&path.display().to_string())
                && said.contains("keeps only the 2 point(s) recorded before"),
            "{said}"
        );
        // Said once; and nothing more is written once the disk has room.
        std::fs::remove_file(&path).unwrap();
        std::fs::write(&path, &before).unwrap();
        assert_eq!(r.add(3, &13), None);
        assert_eq!(std::fs::read(&path).unwrap(), before);
        // What stays behind resumes with its two points.
        let again: Record<u32> = Record::open(dir.path(), "focus", json!({"a": 1}), true).unwrap();
        assert_eq!(again.recorded(), &[10, 11]);
    }
}
