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
    Ok(write_results(folder, scene, header, tally, threads, provenance, fits)?.0)
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
    fits: bool,
) -> std::io::Result<(usize, RunResult)> {
    let out = folder.target().to_path_buf();
    let failed = |e: std::io::Error| cannot_write(&out, e);
    write_state(&folder.path().join(RUN_STATE_FILE), header.clone(), &tally).map_err(failed)?;
    let result = tally.into_result(header.identity.photon_list, header.seconds, threads);
    // FITS carries the sky's frame, measured by tracing (a Sun scene only).
    let sky: Vec<_> = match fits {
        true => (0..scene.sensors.len())
            .map(|k| crate::studies::sky::calibrate(scene, k))
            .collect(),
        false => Vec::new(),
    };
    let files = write_run(
        folder.path(),
        scene,
        &result,
        provenance,
        fits.then_some(&sky[..]),
    )
    .map_err(failed)?;
    folder.commit().map_err(failed)?;
    Ok((files.len() + 1, result))
}

/// The one message for results that could not be written into `out`.
pub(super) fn cannot_write(out: &Path, e: std::io::Error) -> std::io::Error {
    let message = format!("cannot write the results into {}: {e}", out.display());
    std::io::Error::new(e.kind(), message)
}
