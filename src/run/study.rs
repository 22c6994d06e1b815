//! A study that traces point after point (`focus`'s positions,
//! `effective-area`'s angles, `fit-figure-error`'s evaluations) in its results
//! folder: the folder prepared for the study's files and its record, the record
//! opened (resumed, or refused if a stopped study would be thrown away), each
//! finished point recorded, the files every load of the scene reads checked
//! against the first load's (and a stopped sitting's), and at the end the
//! study's files written and put in place together ([`Study::finish`]). A
//! study command only computes and prints.

use super::record::{check_inputs, Record};
use super::{results_folder, RunError};
use crate::files::OutputFolder;
use crate::scene::{InputHashes, Scene};
use serde::{de::DeserializeOwned, Serialize};
use serde_json::Value;
use std::cell::{Cell, RefCell};
use std::path::{Path, PathBuf};

/// A study in its results folder.
pub struct Study<T> {
    /// The folder, staged: the study's files appear together at the end.
    pub folder: OutputFolder,
    record: RefCell<Record<T>>,
    record_path: PathBuf,
    /// The next point's position.
    position: Cell<usize>,
    /// The files the scene read, recorded by the first load (or a stopped
    /// sitting); every later load must read the same.
    inputs: RefCell<Option<InputHashes>>,
}

impl<T: Serialize + DeserializeOwned + Clone> Study<T> {
    /// Opens study `name` in `out` (files `files` besides its record) with
    /// `identity` (what must be equal to resume it); with `resume`, the points
    /// a stopped study recorded are taken up.
    pub fn open(
        out: &Path,
        name: &str,
        files: &[&str],
        identity: Value,
        resume: bool,
    ) -> Result<Study<T>, RunError> {
        let record_name = Record::<T>::file_name(name);
        let folder = results_folder(out, &[files, &[record_name.as_str()]].concat())?;
        let record = Record::open(out, name, identity, resume)?;
        let inputs = RefCell::new(record.inputs().cloned());
        Ok(Study {
            folder,
            record: RefCell::new(record),
            record_path: out.join(record_name),
            position: Cell::new(0),
            inputs,
        })
    }

    /// The points recorded before (to take instead of tracing).
    pub fn replay(&self) -> Vec<T> {
        self.record.borrow().recorded().to_vec()
    }

    /// Where the record is (for the message that says how to resume).
    pub fn record_path(&self) -> &Path {
        &self.record_path
    }

    /// What a stop (Ctrl-C) during the study says: where its `points` so far
    /// ("angles", "variations") are and how to continue.
    pub fn stop_message(&self, points: &str) -> String {
        format!(
            "stopped; the {points} so far are in {}: run the same command with --resume to continue",
            self.record_path.display()
        )
    }

    /// Ends the study: `write` writes its files into the staged folder, which
    /// then takes the results folder's place (with the record). A failure says
    /// which folder could not be written.
    pub fn finish<R>(self, write: impl FnOnce(&Path) -> std::io::Result<R>) -> std::io::Result<R> {
        super::write_results_folder(self.folder, write)
    }

    /// A load of the study's scene: it must read the files the first load read.
    pub fn check_scene(&self, scene: &Scene) -> Result<(), RunError> {
        check_inputs(self.inputs.borrow().as_ref(), scene)?;
        self.inputs
            .borrow_mut()
            .get_or_insert_with(|| scene.inputs.clone());
        Ok(())
    }

    /// The next point is done: recorded (with the scene's input files). The
    /// first failure to write the record is returned as a warning to show.
    #[must_use = "a failed write is returned as a warning to show"]
    pub fn point_done(&self, item: &T) -> Option<String> {
        let mut record = self.record.borrow_mut();
        if let Some(i) = self.inputs.borrow().as_ref() {
            record.set_inputs(i);
        }
        let position = self.position.get();
        self.position.set(position + 1);
        record.add(position, item)
    }

    /// The point at `position` is done (studies whose points carry their own
    /// numbering).
    #[must_use = "a failed write is returned as a warning to show"]
    pub fn point_done_at(&self, position: usize, item: &T) -> Option<String> {
        self.position.set(position);
        self.point_done(item)
    }
}
