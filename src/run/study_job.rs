//! A study's life, for every study and every front end: its settings checked,
//! its identity (the scene's and the settings'), its results folder and record
//! opened (resumed, or refused if a stopped study would be thrown away) when it
//! has one, the stop message set, the points recorded as they finish, a stop
//! between points on request, the provenance, and its files written together
//! at the end. The CLI's study commands and Python's study methods only parse
//! their arguments into a study's settings (`studies::StudyKind`) and show the
//! output.

use super::record::base_identity;
use super::{Invocation, RunError, Stopped, Study};
use crate::output::{Provenance, StudyFiles};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::studies::{PointOrigin, StudyError};
use std::path::Path;

/// What a front end does for a running study: shows progress, says whether
/// to stop, shows warnings, and learns what a stop would say.
pub trait StudyControl: Progress {
    /// A warning to show (a record that could not be written).
    fn warn(&self, warning: &str);
    /// From now on a stop leaves a record to resume: what the stop says (the
    /// CLI hands it to its signal handler).
    fn stoppable(&self, _message: &str) {}
    /// A point is done; the study describes it so (`StudyKind::describe`).
    fn point_finished(&self, _description: &str) {}
    /// A resumed study has ended: what it took from the record.
    fn resumed(&self, _message: &str) {}
}

/// Where a study's files go: a results folder (with its record, so that a
/// stopped study resumes), or nowhere (the output is returned only).
pub struct StudyPlace<'a> {
    pub out: Option<&'a Path>,
    /// Take up the points a stopped study recorded in `out`.
    pub resume: bool,
}

/// Runs study `kind` on `scene` (loaded by the front end) and returns its
/// output and provenance; with a folder, writes its files there.
pub fn run_study<K: StudyFiles>(
    kind: &K,
    scene: &Scene,
    (embree_version, invocation): (String, &Invocation),
    place: StudyPlace,
    control: &dyn StudyControl,
) -> Result<(K::Output, Provenance), RunError> {
    kind.check()?;
    crate::studies::require_sources(scene)?;
    let study = match place.out {
        Some(out) => {
            let mut id = base_identity(scene);
            if let serde_json::Value::Object(settings) =
                serde_json::to_value(kind).map_err(|e| RunError::Io(std::io::Error::other(e)))?
            {
                id.extend(settings);
            }
            let files = kind.files();
            let files: Vec<&str> = files.iter().map(String::as_str).collect();
            Some(Study::<K::Point>::open(
                out,
                K::NAME,
                &files,
                id.into(),
                place.resume,
            )?)
        }
        None => None,
    };
    if let Some(s) = &study {
        // A resumed study's scene must read the files the stopped one read.
        s.check_scene(scene)?;
    }
    let replay = study.as_ref().map(Study::replay).unwrap_or_default();
    let stop_message = match &study {
        Some(s) => {
            let m = s.stop_message(K::POINTS);
            control.stoppable(&m);
            m
        }
        None => format!(
            "stopped; the {} so far are lost (give the study a results folder to resume it)",
            K::POINTS
        ),
    };
    let mut from_record = 0;
    let mut on_point = |p: &K::Point, origin: PointOrigin| {
        from_record += usize::from(origin == PointOrigin::Record);
        if let Some(w) = study.as_ref().and_then(|s| s.point_done(p)) {
            control.warn(&w);
        }
        if let Some(d) = kind.describe(p) {
            control.point_finished(&d);
        }
    };
    let output = match kind.run(scene, &replay, control, &mut on_point) {
        Err(StudyError::Stopped) => return Err(RunError::Stopped(Stopped(stop_message))),
        other => other?,
    };
    if from_record > 0 {
        control.resumed(&format!(
            "resumed: {from_record} {} taken from the record, the rest traced",
            K::POINTS
        ));
    }
    let sampling = kind.sampling();
    let provenance = kind.provenance(
        Provenance::of_study(
            invocation,
            embree_version,
            scene,
            (sampling.photons, sampling.seed),
            K::threads_used(&output),
        )
        .with_points_from_record(study.as_ref().map(|_| from_record)),
    );
    if let Some(study) = study {
        study.finish(|dir| kind.write(dir, &output, &provenance))?;
    }
    Ok((output, provenance))
}

/// Writes a finished study's files into `folder` (staged, put in place
/// together): what a front end's `save` of a study held in memory does.
pub fn save_study<K: StudyFiles>(
    kind: &K,
    folder: &Path,
    output: &K::Output,
    provenance: &Provenance,
) -> Result<(), RunError> {
    let out = super::results_folder(folder, &kind.files())?;
    super::write_results_folder(out, |dir| kind.write(dir, output, provenance))?;
    Ok(())
}
