//! `traxer merge` as a job: the shard folders' run states read (headers first),
//! their scene loaded again and checked to be theirs (scene file, input files,
//! variables, build), the tallies added one at a time ([`super::merge`]), and the
//! results of the whole run written as a finished run's.

use super::job::{prepare_folder, refuse_other_run, refuse_unfinished_run, reload_scene};
use super::{
    merge, read_header, read_state, Finished, InputError, Invocation, RunError, StateHeader,
    CHECKPOINT_FILE, RUN_STATE_FILE,
};
use crate::embree::Device;
use crate::output::{Outputs, Provenance};
use crate::scene::Scene;
use crate::trace::Tally;
use std::path::{Path, PathBuf};

/// What to merge and where.
pub struct MergeJob<'a> {
    /// The shards' results folders.
    pub shards: &'a [PathBuf],
    pub out: &'a Path,
    /// Merge although shards are missing.
    pub partial: bool,
    /// The scene file, if it moved since the shards ran.
    pub moved_scene: Option<&'a Path>,
    pub fits: bool,
    /// Replace the results of a run with other inputs in `out` (refused
    /// without it).
    pub replace: bool,
}

/// A finished merge, with the scene it was checked against.
pub struct MergedRun {
    pub scene: Scene,
    pub finished: Finished,
}

impl MergeJob<'_> {
    pub fn run(&self, invocation: &Invocation) -> Result<MergedRun, RunError> {
        let out = self.out;
        let same = |p: &PathBuf| std::fs::canonicalize(p).ok() == std::fs::canonicalize(out).ok();
        if let Some(dir) = self.shards.iter().find(|d| out.exists() && same(d)) {
            return Err(InputError(format!(
                "--out {}: is the shard folder {}; write the merge elsewhere",
                out.display(),
                dir.display()
            ))
            .into());
        }
        let read: Vec<&Path> = self.shards.iter().map(|d| d.as_path()).collect();
        crate::files::refuse_replacing_inputs(out, &read)?;
        let shards = self
            .shards
            .iter()
            .map(|d| read_shard(d))
            .collect::<Result<Vec<_>, _>>()?;
        let first_dir = &self.shards[0];
        let first = shards[0].1.clone();
        let (device, scene) = self.scene_of(first_dir, &first)?;
        let merged = merge(shards, self.partial, |dir, header| {
            let tally = read_shard_tally(dir, header)?;
            if !tally.fits(&scene) {
                return Err(RunError::from(InputError(format!(
                    "{}: its sums do not fit the scene's sensors: not a shard of this run",
                    dir.display()
                ))));
            }
            Ok(tally)
        })?;
        let outputs = Outputs {
            fits: self.fits,
            photon_list: first.identity.photon_list > 0,
        };
        let folder = prepare_folder(out, &scene, outputs)?;
        refuse_unfinished_run(out)?;
        refuse_other_run(out, &merged.header.identity, self.replace)?;
        let header = merged.header;
        let provenance = Provenance::of_run(
            invocation,
            device.info().version,
            &scene,
            &header,
            None,
            self.shards,
        );
        let (files, result) = super::write_results(
            folder,
            &scene,
            &header,
            merged.tally,
            0,
            &provenance,
            outputs,
        )?;
        let finished = Finished {
            out: out.to_path_buf(),
            files,
            result,
            header,
        };
        Ok(MergedRun { scene, finished })
    }

    /// The shards' scene, loaded again (from where it is now if it moved) and
    /// checked to be the one they traced.
    fn scene_of(&self, first_dir: &Path, first: &StateHeader) -> Result<(Device, Scene), RunError> {
        reload_scene(
            first,
            self.moved_scene,
            |scene| {
                format!(
                "{}: the shards' scene {} is no longer there; if it moved, give its new place with --scene FILE (its SHA-256 is checked)",
                first_dir.display(),
                scene.display()
            )
            },
            |diff, scene| {
                format!(
                "{}: the shards are of {diff} (scene {}): the scene file or a file it reads changed since they ran, or --scene names another scene",
                first_dir.display(),
                scene.display()
            )
            },
        )
    }
}

/// A shard's folder and the header of its run state.
fn read_shard(dir: &Path) -> Result<(PathBuf, StateHeader), RunError> {
    let path = dir.join(RUN_STATE_FILE);
    if path.exists() && !path.is_file() {
        return Err(InputError(format!(
            "{}: is not a file (a folder or a device): a run's {RUN_STATE_FILE} is the file traxer trace writes; put the run's own back",
            path.display()
        ))
        .into());
    }
    if !path.is_file() {
        let hint = if dir.join(CHECKPOINT_FILE).is_file() {
            format!(
                "its run was stopped: finish it with `traxer trace --resume {}`",
                dir.display()
            )
        } else {
            "traxer trace writes it with every run".into()
        };
        return Err(InputError(format!(
            "{}: holds no {RUN_STATE_FILE} ({hint})",
            dir.display()
        ))
        .into());
    }
    Ok((dir.to_path_buf(), read_header(&path)?))
}

/// The tally of the shard in `dir` whose header `header` was read before: the
/// file must still hold that header (whole and checksummed).
fn read_shard_tally(dir: &Path, header: &StateHeader) -> Result<Tally, RunError> {
    let path = dir.join(RUN_STATE_FILE);
    let (now, tally) = read_state(&path)?;
    if &now != header {
        return Err(InputError(format!(
            "{}: changed while the merge read it",
            path.display()
        ))
        .into());
    }
    Ok(tally)
}
