//! A finished run's results folder: `run_state.bin` (the exact sums, for
//! `traxer merge`) and every file of [`write_run`], put in place together. Used by
//! `traxer trace` (also resumed), `traxer merge` and the Python module's
//! `TraceResult.save`.

use super::{write_state, StateHeader, CHECKPOINT_FILE, RUN_STATE_FILE};
use crate::files::OutputFolder;
use crate::output::{write_run, Outputs, Provenance};
use crate::scene::Scene;
use crate::trace::{RunResult, Tally};
use std::path::Path;

/// The results folder `out` of any command, prepared for the files `names`
/// (checked writable, locked against a second writer, staged: the files appear
/// together when it is committed). Every front end prepares its folders here.
pub fn results_folder<S: AsRef<str>>(
    out: &Path,
    names: &[S],
) -> Result<OutputFolder, crate::files::OutputLocationError> {
    OutputFolder::prepare(out, names)
}

/// [`results_folder`] for a command that reads the folders `inputs` (runs,
/// shards): refuses an `out` that is one of them or holds one.
pub fn results_folder_reading<S: AsRef<str>>(
    out: &Path,
    names: &[S],
    inputs: &[&Path],
) -> Result<OutputFolder, crate::files::OutputLocationError> {
    crate::files::refuse_replacing_inputs(out, inputs)?;
    OutputFolder::prepare(out, names)
}

/// Saves a finished run (its tally, in memory) into the results folder `out`,
/// as `traxer trace` would have: `run_state.bin` and every result file. A
/// folder holding a run of other inputs is refused unless `replace`.
#[allow(clippy::too_many_arguments)]
pub fn save_results(
    out: &Path,
    scene: &Scene,
    header: &StateHeader,
    tally: Tally,
    threads: usize,
    provenance: &Provenance,
    fits: bool,
    replace: bool,
) -> Result<usize, super::RunError> {
    let outputs = Outputs {
        fits,
        photon_list: header.identity.photon_list > 0,
    };
    let names = results_file_names(scene, outputs);
    let folder = results_folder(out, &names)?;
    super::job::refuse_other_run(out, &header.identity, replace)?;
    Ok(write_results(folder, scene, header, tally, threads, provenance, outputs)?.0)
}

/// Every file a finished run leaves in its results folder: the results, the run
/// state, and the checkpoint a run keeps while it runs (listed so that a stale
/// one is replaced, never mixed in).
pub fn results_file_names(scene: &Scene, outputs: Outputs) -> Vec<String> {
    let mut names = crate::output::run_file_names(scene, outputs);
    names.push(RUN_STATE_FILE.into());
    names.push(CHECKPOINT_FILE.into());
    names
}

/// Writes a finished run's `run_state.bin` and results into `folder` and puts
/// them in place; returns the number of files and the run's result (the tally,
/// moved, not copied: it may be large).
pub fn write_results(
    folder: OutputFolder,
    scene: &Scene,
    header: &StateHeader,
    tally: Tally,
    threads: usize,
    provenance: &Provenance,
    outputs: Outputs,
) -> std::io::Result<(usize, RunResult)> {
    // FITS carries the sky's frame, measured by tracing (a Sun scene only).
    let sky: Vec<_> = match outputs.fits {
        true => (0..scene.sensors.len())
            .map(|k| crate::studies::sky::calibrate(scene, k))
            .collect(),
        false => Vec::new(),
    };
    write_results_folder(folder, |dir| {
        write_state(&dir.join(RUN_STATE_FILE), header.clone(), &tally)?;
        let result = tally.into_result(header.identity.photon_list, header.seconds, threads);
        let files = write_run(
            dir,
            scene,
            &result,
            provenance,
            outputs.fits.then_some(&sky[..]),
        )?;
        Ok((files.len() + 1, result))
    })
}

/// Writes the prepared results folder `folder`: `write` puts the files into
/// its staging place, which then takes the folder's place, all together (a
/// failure or a stop leaves the previous results); a failure names the
/// folder. Every result is written here: runs, studies, and the one-shot
/// results of the front ends (the solar flux, the live window's save,
/// Python's saves).
pub fn write_results_folder<R>(
    folder: OutputFolder,
    write: impl FnOnce(&Path) -> std::io::Result<R>,
) -> std::io::Result<R> {
    let out = folder.target().to_path_buf();
    let failed = |e: std::io::Error| cannot_write(&out, e);
    let written = write(folder.path()).map_err(failed)?;
    folder.commit().map_err(failed)?;
    Ok(written)
}

/// Saves photons traced outside a run (the live window's: from photon 0 with
/// `seed`, on one thread) into `dir`: a trace's result files, and the
/// front end's files `more` (their names, and how it writes them), together.
/// Returns the photons saved.
pub fn save_traced(
    dir: &Path,
    scene: &Scene,
    (embree_version, invocation): (String, &super::Invocation),
    (seed, tally): (u64, Tally),
    (more, write_more): (&[&str], impl FnOnce(&Path) -> std::io::Result<()>),
) -> Result<u64, super::RunError> {
    let mut names = crate::output::run_file_names(scene, Outputs::default());
    names.extend(more.iter().map(|m| m.to_string()));
    let folder = results_folder(dir, &names)?;
    let traced = tally.traced;
    let provenance =
        Provenance::of_study(invocation, embree_version, scene, (traced.max(1), seed), 1);
    let result = tally.into_result(0, 0.0, 1);
    write_results_folder(folder, |out| {
        write_run(out, scene, &result, &provenance, None)?;
        write_more(out)
    })?;
    Ok(traced)
}

/// The one message for results that could not be written into `out`.
pub(super) fn cannot_write(out: &Path, e: std::io::Error) -> std::io::Error {
    let message = format!("cannot write the results into {}: {e}", out.display());
    std::io::Error::new(e.kind(), message)
}
