//! `traxer merge`: adds the results of the shards of one run (`traxer trace
//! --shard K/N`) into the results of the whole run, bit-identical to tracing it
//! in one piece.

use super::args::{DefineArgs, OutputArgs, SceneArgs};
use super::resume::{file_names, fits_scene, read_shard, read_shard_tally, refuse_unfinished_run};
use super::{load_xray_scene, InputError};
use anyhow::Context;
use std::path::PathBuf;
use traxer::files::OutputFolder;
use traxer::output::Provenance;
use traxer::run::{merge, RunIdentity};

/// Add up the shards of a run into the results of the whole run.
///
/// Reads each shard folder's run_state.bin (the exact sums `traxer trace --shard
/// K/N` leaves), checks that the shards are finished parts of one run (same
/// scene file and files it reads, variables, seed, photons, number of shards
/// and traxer build),
/// none twice and none missing, and writes into --out the files of a single run
/// of all the photons: bit-identical images, projections, EEF, grid output,
/// photon list and statistics, in any order of the folders. The provenance
/// records the shards merged.
#[derive(clap::Args)]
pub struct MergeArgs {
    /// Results folders of the shards.
    #[arg(value_name = "SHARD_DIR", required = true)]
    pub shards: Vec<PathBuf>,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Merge although shards are missing; the result then holds fewer photons,
    /// and its provenance lists the missing shards.
    #[arg(long)]
    pub partial: bool,
    /// The scene file, if it has moved since the shards ran (it must be the same
    /// file: its SHA-256 is checked).
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// Also write each sensor's image as NAME.fits (see `traxer trace --fits`).
    #[arg(long)]
    pub fits: bool,
}

pub fn run(a: MergeArgs) -> anyhow::Result<()> {
    let out = &a.output.out;
    let same = |p: &PathBuf| std::fs::canonicalize(p).ok() == std::fs::canonicalize(out).ok();
    if let Some(dir) = a.shards.iter().find(|d| out.exists() && same(d)) {
        return Err(InputError(format!(
            "--out {}: is the shard folder {}; write the merge elsewhere",
            out.display(),
            dir.display()
        ))
        .into());
    }
    let shards = a
        .shards
        .iter()
        .map(|d| read_shard(d))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let folders: Vec<PathBuf> = a.shards.clone();
    let first = shards[0].1.clone();
    let scene_args = SceneArgs {
        scene: a.scene.clone().unwrap_or(first.scene_path.clone()),
        vars: DefineArgs {
            define: first.overrides.clone(),
        },
    };
    if !scene_args.scene.is_file() {
        return Err(InputError(format!(
            "{}: the shards' scene {} is no longer there; if it moved, give its new place with --scene FILE (its SHA-256 is checked)",
            folders[0].display(),
            scene_args.scene.display()
        ))
        .into());
    }
    let (device, scene) = load_xray_scene(&scene_args).with_context(|| {
        format!(
            "cannot load the scene of the shards in {}",
            folders[0].display()
        )
    })?;
    let id = &first.identity;
    let again = RunIdentity::new(&scene, id.seed, id.total_photons, id.shards, id.photon_list);
    if let Some(diff) = id.difference(&again) {
        return Err(InputError(format!(
            "{}: the shards are of {diff} (scene {}): the scene file or a file it reads changed since they ran, or --scene names another scene",
            folders[0].display(),
            scene_args.scene.display()
        ))
        .into());
    }
    // One shard's tally at a time: memory does not grow with the shards.
    let merged = merge(shards, a.partial, |dir, header| {
        let tally = read_shard_tally(dir, header)?;
        if !fits_scene(&tally, &scene) {
            return Err(InputError(format!(
                "{}: its sums do not fit the scene's sensors: not a shard of this run",
                dir.display()
            ))
            .into());
        }
        anyhow::Ok(tally)
    })?;
    let folder = OutputFolder::prepare(out, &file_names(&scene, id.photon_list > 0, a.fits))?;
    refuse_unfinished_run(out)?;
    let h = &merged.header;
    let provenance = Provenance::new(&super::invocation(), Some(device.info().version))
        .scene(&scene)
        .parts(h, &folders);
    let (files, result) =
        traxer::run::write_results(folder, &scene, h, merged.tally, 0, &provenance, a.fits)?;
    if !a.output.quiet.quiet {
        if !h.missing.is_empty() {
            tell!(
                "warning: a partial merge: {} of {} shards, {} of {} photons",
                h.parts.len(),
                id.shards,
                h.photons,
                id.total_photons
            );
        }
        super::trace::report(&scene, &result);
        say!(
            "merged {} shards; wrote {} files to {}",
            h.parts.len(),
            files,
            out.display()
        );
    }
    Ok(())
}
