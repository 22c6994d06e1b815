//! `traxer merge`: adds the results of the shards of one run (`traxer trace
//! --shard K/N`) into the results of the whole run, bit-identical to tracing it
//! in one piece.

use super::args::OutputArgs;
use std::path::PathBuf;
use traxer::run::{MergeJob, MergedRun};

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
    /// Replace the results of a run with other inputs in --out; without it such
    /// a folder is refused and kept.
    #[arg(long)]
    pub replace: bool,
}

pub fn run(a: MergeArgs) -> anyhow::Result<()> {
    let out = a.output.folder("merged");
    let job = MergeJob {
        shards: &a.shards,
        out: &out,
        partial: a.partial,
        moved_scene: a.scene.as_deref(),
        fits: a.fits,
        replace: a.replace,
    };
    let MergedRun { scene, finished } = job.run(&super::invocation())?;
    super::Warnings::default().show(&scene);
    // Warnings show even with -q.
    let (h, id) = (&finished.header, &finished.header.identity);
    if !h.missing.is_empty() {
        tell!(
            "warning: a partial merge: {} of {} shards, {} of {} photons",
            h.parts.len(),
            id.shards,
            h.photons,
            id.total_photons
        );
    }
    super::report::warn_about_sensors(&scene, &finished.result);
    if !a.output.quiet.quiet {
        super::report::report(&scene, &finished.result);
        say!(
            "merged {} shards; wrote {} files to {}",
            h.parts.len(),
            finished.files,
            finished.out.display()
        );
    }
    Ok(())
}
