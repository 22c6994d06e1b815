//! The photon loop of `traxer trace` with its checkpoints, and `--resume`: a run
//! keeps `checkpoint.bin` in its results folder (written atomically between
//! batches of photons, every `--checkpoint-every` seconds and on a stopping
//! signal), and a resumed run continues from it. Finished runs, resumed or not,
//! write their results and `run_state.bin` through
//! [`traxer::run::write_results`], which `traxer merge` uses too.

use super::signals::{checkpoint_on_signals, stop_requested};
use super::{load_xray_scene, progress, InputError, Stopped};
use anyhow::Context;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use traxer::embree::Device;
use traxer::files::OutputFolder;
use traxer::output::Provenance;
use traxer::run::{
    read_header, read_state, write_state, RunIdentity, RunPart, Shard, StateHeader,
    CHECKPOINT_FILE, RUN_STATE_FILE,
};
use traxer::scene::Scene;
use traxer::trace::{self, Flow, RunConfig, Tally, CHUNK};

/// How a run goes, beyond what its identity fixes.
pub struct Settings {
    pub threads: usize,
    pub quiet: bool,
    /// Time between checkpoints; `None`: no checkpoints.
    pub every: Option<Duration>,
    /// Also write each sensor's image as FITS.
    pub fits: bool,
    /// Where the scene file is now, if it moved since the run stopped.
    pub moved_scene: Option<PathBuf>,
}

/// Every file a trace may leave in its results folder: the results, the run
/// state, and the checkpoint while it runs.
pub fn file_names(scene: &Scene, photon_list: bool, fits: bool) -> Vec<String> {
    traxer::run::results_file_names(scene, photon_list, fits)
}

/// A new run into `out` while it holds another run's checkpoint would throw the
/// stopped run away: refused, saying how to continue it instead.
pub fn refuse_unfinished_run(out: &Path) -> anyhow::Result<()> {
    let path = out.join(CHECKPOINT_FILE);
    if !path.exists() {
        return Ok(());
    }
    let progress = match read_header(&path) {
        Ok(h) => format!(" ({} of {} photons traced)", h.traced, h.photons),
        Err(_) => String::new(),
    };
    Err(InputError(format!(
        "{}: holds the checkpoint of an unfinished run{progress}: continue it with `traxer trace --resume {}`, or remove {} to start afresh",
        out.display(),
        out.display(),
        path.display()
    ))
    .into())
}

/// Traces the rest of `part` from `tally` and writes the results into `folder`,
/// keeping a checkpoint there if asked to.
pub fn trace_into(
    device: &Device,
    scene: &Scene,
    cfg: &RunConfig,
    mut part: RunPart,
    tally: Tally,
    folder: OutputFolder,
    settings: &Settings,
) -> anyhow::Result<()> {
    let target = folder.target().to_path_buf();
    let checkpoint = target.join(CHECKPOINT_FILE);
    let bar = progress::bar(cfg.photons, "photons", settings.quiet);
    bar.inc(tally.traced);
    let (earlier, start) = (part.seconds, Instant::now());
    let mut last = Instant::now();
    let mut failed = None;
    checkpoint_on_signals(settings.every.is_some());
    let traced = trace::run_part(scene, cfg, tally, &|n| bar.inc(n), &mut |t| {
        let stop = stop_requested();
        let due = settings.every.is_some_and(|every| last.elapsed() >= every);
        if t.traced < cfg.photons && (stop || due) {
            part.seconds = earlier + start.elapsed().as_secs_f64();
            if let Err(e) = write_state(&checkpoint, part.header(t), t) {
                failed = Some(e);
                return Flow::Stop;
            }
            last = Instant::now();
        }
        if stop {
            Flow::Stop
        } else {
            Flow::Continue
        }
    });
    // From here on a signal stops at once; the checkpoint stays for --resume.
    checkpoint_on_signals(false);
    let (tally, threads) = traced.context("cannot start the worker threads")?;
    bar.finish_and_clear();
    if let Some(e) = failed {
        return Err(e).context(format!(
            "cannot write the checkpoint {}",
            checkpoint.display()
        ));
    }
    if tally.traced < cfg.photons {
        return Err(Stopped(format!(
            "stopped after {} of {} photons; the checkpoint {} holds them: continue with `traxer trace --resume {}`",
            tally.traced,
            cfg.photons,
            checkpoint.display(),
            target.display()
        ))
        .into());
    }
    part.seconds = earlier + start.elapsed().as_secs_f64();
    let header = part.header(&tally);
    let provenance = Provenance::new(&super::invocation(), Some(device.info().version))
        .scene(scene)
        .run(cfg, threads)
        .parts(&header, &[]);
    let (files, result) = traxer::run::write_results(
        folder,
        scene,
        &header,
        tally,
        threads,
        &provenance,
        settings.fits,
    )?;
    if !settings.quiet {
        super::trace::report(scene, &result);
        say!("wrote {} files to {}", files, target.display());
    }
    Ok(())
}

/// `traxer trace --resume DIR`.
pub fn resume(dir: &Path, settings: &Settings) -> anyhow::Result<()> {
    let path = dir.join(CHECKPOINT_FILE);
    if !path.is_file() {
        let done = dir.join(RUN_STATE_FILE);
        if let Ok(h) = read_header(&done) {
            if h.complete() {
                say!(
                    "{}: the run is finished ({} photons); nothing to resume",
                    dir.display(),
                    h.photons
                );
                return Ok(());
            }
        }
        return Err(InputError(format!(
            "{}: is not the results folder of a stopped run (it has no {CHECKPOINT_FILE}; runs keep one with --checkpoint-every)",
            dir.display()
        ))
        .into());
    }
    let (header, tally) = read_state(&path)?;
    let this = (env!("CARGO_PKG_VERSION"), env!("TRAXER_GIT_HASH"));
    let id = &header.identity;
    if (id.traxer_version.as_str(), id.git_hash.as_str()) != this {
        return Err(InputError(format!(
            "{}: was written by traxer {} ({}), this is {} ({}): continue it with that build, so that the photons traced before and after are traced alike",
            path.display(), id.traxer_version, id.git_hash, this.0, this.1
        ))
        .into());
    }
    let scene_args = super::args::SceneArgs {
        scene: settings
            .moved_scene
            .clone()
            .unwrap_or_else(|| header.scene_path.clone()),
        vars: super::args::DefineArgs {
            define: header.overrides.clone(),
        },
    };
    if !scene_args.scene.is_file() {
        return Err(InputError(format!(
            "{}: the run's scene {} is no longer there; if it moved, give its new place: `traxer trace NEW_PATH --resume {}` (its SHA-256 is checked)",
            path.display(),
            scene_args.scene.display(),
            dir.display()
        ))
        .into());
    }
    let (device, scene) = load_xray_scene(&scene_args)
        .with_context(|| format!("cannot load the scene of the checkpoint {}", path.display()))?;
    let again = RunIdentity::new(&scene, id.seed, id.total_photons, id.shards, id.photon_list);
    if let Some(diff) = id.difference(&again) {
        return Err(InputError(format!(
            "{}: the checkpoint is of {diff} as now: the scene file {} or a file it reads changed since the run stopped",
            path.display(),
            header.scene_path.display()
        ))
        .into());
    }
    let shard = check_checkpoint(&path, &header, &tally, &scene)?;
    let cfg = RunConfig {
        photons: shard.photons(),
        seed: id.seed,
        threads: settings.threads,
        first_photon: shard.range().start,
        photon_list: id.photon_list,
    };
    let folder =
        OutputFolder::prepare(dir, &file_names(&scene, id.photon_list > 0, settings.fits))?;
    let mut part = RunPart::new(&scene, &cfg, shard);
    part.seconds = header.seconds;
    if !settings.quiet {
        say!(
            "resuming {} after {} of {} photons",
            dir.display(),
            tally.traced,
            cfg.photons
        );
    }
    trace_into(&device, &scene, &cfg, part, tally, folder, settings)
}

/// The checkpoint's shard, after checking that its tally fits the scene and
/// stops at a batch boundary (a damaged or foreign file would otherwise crash).
fn check_checkpoint(
    path: &Path,
    header: &StateHeader,
    tally: &Tally,
    scene: &Scene,
) -> Result<Shard, InputError> {
    let bad = |what: &str| InputError(format!("{}: {what}", path.display()));
    let id = &header.identity;
    let [index] = header.parts[..] else {
        return Err(bad("holds a merge of shards, not one run's checkpoint"));
    };
    if id.shards == 0 || index == 0 || index > id.shards || id.shards > id.total_photons {
        return Err(bad("names an impossible shard"));
    }
    let shard = Shard {
        index,
        count: id.shards,
        total: id.total_photons,
    };
    let fits = fits_scene(tally, scene);
    let aligned = tally.traced == shard.photons()
        || (tally.traced < shard.photons() && tally.traced.is_multiple_of(CHUNK));
    if !fits || !aligned || tally.traced != header.traced || header.photons != shard.photons() {
        return Err(bad(
            "its tally does not fit the scene's sensors or its photon counts disagree: not a checkpoint of this run",
        ));
    }
    Ok(shard)
}

/// Whether a tally has the scene's sensors, pixels and objects.
pub fn fits_scene(tally: &Tally, scene: &Scene) -> bool {
    tally.images.len() == scene.sensors.len()
        && tally.images.iter().zip(&scene.sensors).all(|(i, s)| {
            let n = s.pixel_count() * s.bands();
            i.counts.len() == n
                && i.flux_sum.len() == n
                && i.paths.class_images.as_ref().is_none_or(|c| {
                    c.len() == traxer::history::PathClass::ALL.len()
                        && c.iter().all(|c| c.len() == s.pixel_count())
                })
        })
        && tally.stats.hits_per_object.len() == scene.objects.len()
        && tally.stats.recorded_per_sensor.len() == scene.sensors.len()
}

/// A folder given to `traxer merge`, with its run state.
pub fn read_shard(dir: &Path) -> anyhow::Result<(PathBuf, StateHeader)> {
    let path = dir.join(RUN_STATE_FILE);
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
pub fn read_shard_tally(dir: &Path, header: &StateHeader) -> anyhow::Result<Tally> {
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
