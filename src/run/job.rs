//! A trace's life in its results folder, the same for the CLI and Python: a new
//! run ([`TraceJob`]) or a stopped one found in its folder ([`open_stopped`]) is
//! traced with a checkpoint kept in the folder (`checkpoint.bin`, written
//! atomically between batches of photons, every `checkpoint_every` and when the
//! front end asks the run to stop), and finished runs write their results and
//! `run_state.bin` together ([`super::write_results`]). The front end hears of
//! progress and asks for stops through [`RunControl`]; it prints.

use super::{
    read_header, read_state, write_state, InputError, Invocation, RunIdentity, RunPart,
    RunStateError, Shard, StateHeader, Stopped, CHECKPOINT_FILE, RUN_STATE_FILE,
};
use crate::embree::Device;
use crate::files::OutputFolder;
use crate::output::{Outputs, Provenance};
use crate::scene::Scene;
use crate::trace::{self, Flow, RunConfig, RunResult, Tally, CHUNK};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// How a run goes, beyond what its identity fixes.
#[derive(Clone, Debug, Default)]
pub struct RunSettings {
    /// Worker threads; 0 = one per core (results do not depend on it).
    pub threads: usize,
    /// Time between checkpoints; `None`: no checkpoints.
    pub checkpoint_every: Option<Duration>,
    /// Also write each sensor's image as FITS.
    pub fits: bool,
    /// Replace a finished run of other inputs in the results folder (without
    /// it, such a folder is refused: see [`refuse_other_run`]).
    pub replace: bool,
}

/// What a front end hears of a run and how it asks it to stop.
pub trait RunControl: Sync {
    /// `photons` more are traced (called from worker threads).
    fn advance(&self, photons: u64);
    /// Whether the run should stop after the current batch (checked between
    /// batches; a checkpoint is written first).
    fn stop_requested(&self) -> bool {
        false
    }
    /// The run keeps a checkpoint from now on (`true`) or no longer (`false`):
    /// the CLI lets a signal stop it gracefully meanwhile.
    fn checkpointing(&self, _on: bool) {}
}

/// Why a run did not finish.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Input(#[from] InputError),
    #[error(transparent)]
    Merge(#[from] super::MergeError),
    #[error(transparent)]
    Stopped(#[from] Stopped),
    #[error(transparent)]
    State(#[from] RunStateError),
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    #[error(transparent)]
    Location(#[from] crate::files::OutputLocationError),
    #[error(transparent)]
    Embree(#[from] crate::embree::EmbreeError),
    #[error("cannot start the worker threads: {0}")]
    Threads(#[from] rayon::ThreadPoolBuildError),
    #[error(transparent)]
    Io(#[from] std::io::Error),
    #[error(transparent)]
    Study(#[from] crate::studies::StudyError),
}

impl RunError {
    /// Whether the user's input is at fault (exit code 2) rather than the machine.
    pub fn is_bad_input(&self) -> bool {
        match self {
            RunError::Study(e) => e.is_bad_input(),
            _ => !matches!(
                self,
                RunError::Stopped(_) | RunError::Threads(_) | RunError::Io(_) | RunError::Embree(_)
            ),
        }
    }
}

/// A finished run: its results folder, the files written and the result.
pub struct Finished {
    pub out: PathBuf,
    pub files: usize,
    pub result: RunResult,
    pub header: StateHeader,
}

/// A new run of `scene`: `cfg` (photons and first photon of the shard), `shard`.
pub struct TraceJob<'a> {
    pub scene: &'a Scene,
    pub embree_version: String,
    pub cfg: RunConfig,
    pub shard: Shard,
}

impl TraceJob<'_> {
    /// Traces into the results folder `out` (refusing a folder that holds a
    /// stopped run's checkpoint) and writes the results there.
    pub fn run(
        &self,
        out: &Path,
        settings: &RunSettings,
        invocation: &Invocation,
        control: &dyn RunControl,
    ) -> Result<Finished, RunError> {
        let outputs = Outputs {
            fits: settings.fits,
            photon_list: self.cfg.photon_list > 0,
        };
        let folder = prepare_folder(out, self.scene, outputs)?;
        refuse_unfinished_run(out)?;
        let part = RunPart::new(self.scene, &self.cfg, self.shard);
        refuse_other_run(out, &part.identity, settings.replace)?;
        let tally = Tally::new(self.scene);
        let run = Sitting {
            scene: self.scene,
            cfg: &self.cfg,
            embree_version: &self.embree_version,
            settings,
            invocation,
            outputs,
        };
        run.trace_into(part, tally, folder, control)
    }
}

/// A run traced in memory, nothing written (Python's `Scene.trace()` without
/// `out`): its run state as a folder's would hold it, and its provenance.
pub struct InMemory {
    pub header: StateHeader,
    pub tally: Tally,
    pub threads: usize,
    pub provenance: Provenance,
}

impl TraceJob<'_> {
    /// Traces the whole job in memory; a stop request ends it with nothing kept.
    pub fn run_in_memory(
        &self,
        invocation: &Invocation,
        control: &dyn RunControl,
    ) -> Result<InMemory, RunError> {
        let mut part = RunPart::new(self.scene, &self.cfg, self.shard);
        let start = Instant::now();
        let progress = |n| control.advance(n);
        let (tally, threads) = trace::run_part(
            self.scene,
            &self.cfg,
            Tally::new(self.scene),
            &progress,
            &mut |_| match control.stop_requested() {
                true => Flow::Stop,
                false => Flow::Continue,
            },
        )?;
        if tally.traced < self.cfg.photons {
            return Err(Stopped(format!(
                "stopped after {} of {} photons; nothing was kept",
                tally.traced, self.cfg.photons
            ))
            .into());
        }
        tally.stats.weights_tallied().map_err(InputError)?;
        part.seconds = start.elapsed().as_secs_f64();
        let header = part.header(&tally);
        let provenance = Provenance::of_run(
            invocation,
            self.embree_version.clone(),
            self.scene,
            &header,
            Some(threads),
            &[],
        );
        Ok(InMemory {
            header,
            tally,
            threads,
            provenance,
        })
    }
}

/// The results folder of a run of `scene`, prepared (locked, staged) for every
/// file a trace may leave there.
pub fn prepare_folder(
    out: &Path,
    scene: &Scene,
    outputs: Outputs,
) -> Result<OutputFolder, RunError> {
    Ok(super::results_folder(
        out,
        &super::results_file_names(scene, outputs),
    )?)
}

/// A new run into `out` while it holds another run's checkpoint would throw the
/// stopped run away: refused, saying how to continue it instead.
pub fn refuse_unfinished_run(out: &Path) -> Result<(), InputError> {
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
    )))
}

/// A run into `out` while it holds the results of a run with other inputs
/// (scene file, the files it reads, variables, seed, photons, shards, photon
/// list) would replace them without a word: refused unless `replace`, saying
/// what differs and how to go on. A run of the same inputs gives the same results (traxer is
/// deterministic), so replacing it loses nothing; nor does it matter which
/// traxer build made it.
pub fn refuse_other_run(
    out: &Path,
    identity: &super::RunIdentity,
    replace: bool,
) -> Result<(), InputError> {
    const REPLACE: &str = "`--replace` (traxer trace or merge), or `replace=True` in Python";
    let path = out.join(super::RUN_STATE_FILE);
    if replace || !path.exists() {
        return Ok(());
    }
    let Ok(then) = read_header(&path) else {
        return Err(InputError(format!(
            "{}: holds results whose run state {} cannot be read, so traxer cannot tell whether they are this run's; keep them and write elsewhere, or replace them with {REPLACE}",
            out.display(),
            path.display()
        )));
    };
    let then = super::RunIdentity {
        traxer_version: identity.traxer_version.clone(),
        git_hash: identity.git_hash.clone(),
        ..then.identity
    };
    match identity.difference(&then) {
        None => Ok(()),
        Some(diff) => Err(InputError(format!(
            "{}: holds the results of a run with other inputs (the new run: {diff}); they are kept. Write this run elsewhere (another --out, or another -D, whose default folder is its own), or replace them with {REPLACE}",
            out.display()
        ))),
    }
}

/// One sitting of a run: from a tally (empty, or a checkpoint's) to the end or
/// to a stop.
struct Sitting<'a> {
    scene: &'a Scene,
    cfg: &'a RunConfig,
    embree_version: &'a str,
    settings: &'a RunSettings,
    invocation: &'a Invocation,
    /// The files it writes (chosen once, with the folder prepared for them).
    outputs: Outputs,
}

impl Sitting<'_> {
    /// Traces the rest of `part` from `tally` and writes the results into
    /// `folder`, keeping a checkpoint there if asked to.
    fn trace_into(
        &self,
        mut part: RunPart,
        tally: Tally,
        folder: OutputFolder,
        control: &dyn RunControl,
    ) -> Result<Finished, RunError> {
        let (cfg, every) = (self.cfg, self.settings.checkpoint_every);
        let target = folder.target().to_path_buf();
        let checkpoint = target.join(CHECKPOINT_FILE);
        let (earlier, start) = (part.seconds, Instant::now());
        let mut last = Instant::now();
        let mut failed = None;
        control.checkpointing(every.is_some());
        let progress = |n| control.advance(n);
        let traced = trace::run_part(self.scene, cfg, tally, &progress, &mut |t| {
            let stop = control.stop_requested();
            let due = every.is_some_and(|every| last.elapsed() >= every);
            // Without checkpoints a stop leaves nothing behind.
            if t.traced < cfg.photons && every.is_some() && (stop || due) {
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
        // From here on a stop request ends the process at once (the front end's
        // business); the checkpoint stays for a resume.
        control.checkpointing(false);
        let (tally, threads) = traced?;
        if let Some(e) = failed {
            let message = format!("cannot write the checkpoint {}: {e}", checkpoint.display());
            return Err(std::io::Error::new(e.kind(), message).into());
        }
        if tally.traced < cfg.photons && every.is_none() {
            return Err(Stopped(format!(
                "stopped after {} of {} photons; nothing was written (keep checkpoints to continue a stopped run)",
                tally.traced, cfg.photons
            ))
            .into());
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
        tally.stats.weights_tallied().map_err(InputError)?;
        part.seconds = earlier + start.elapsed().as_secs_f64();
        let header = part.header(&tally);
        let provenance = Provenance::of_run(
            self.invocation,
            self.embree_version.to_string(),
            self.scene,
            &header,
            Some(threads),
            &[],
        );
        let (files, result) = super::write_results(
            folder,
            self.scene,
            &header,
            tally,
            threads,
            &provenance,
            self.outputs,
        )?;
        Ok(Finished {
            out: target,
            files,
            result,
            header,
        })
    }
}

/// What a folder given to resume holds.
pub enum Found {
    /// A finished run of this many photons: nothing to resume.
    Finished(u64),
    /// A stopped run, checked against its scene, ready to continue.
    Stopped(Box<Resumable>),
}

/// A stopped run and its scene, loaded again and checked to be the run's.
pub struct Resumable {
    pub dir: PathBuf,
    pub device: Device,
    pub scene: Scene,
    header: StateHeader,
    /// The checkpoint's tally, until the run continues from it.
    tally: Option<Tally>,
    shard: Shard,
}

impl Resumable {
    /// Photons traced before, and of the whole part.
    pub fn progress(&self) -> (u64, u64) {
        (self.header.traced, self.shard.photons())
    }

    /// Continues the run to its end (or the next stop) in its folder; once.
    pub fn run(
        &mut self,
        settings: &RunSettings,
        invocation: &Invocation,
        control: &dyn RunControl,
    ) -> Result<Finished, RunError> {
        let id = &self.header.identity;
        let cfg = RunConfig {
            photons: self.shard.photons(),
            seed: id.seed,
            threads: settings.threads,
            first_photon: self.shard.range().start,
            photon_list: id.photon_list,
        };
        let outputs = Outputs {
            fits: settings.fits,
            photon_list: id.photon_list > 0,
        };
        let folder = prepare_folder(&self.dir, &self.scene, outputs)?;
        let mut part = RunPart::new(&self.scene, &cfg, self.shard);
        part.seconds = self.header.seconds;
        let embree_version = self.device.info().version;
        let sitting = Sitting {
            scene: &self.scene,
            cfg: &cfg,
            embree_version: &embree_version,
            settings,
            invocation,
            outputs,
        };
        let tally = self.tally.take().ok_or_else(|| {
            InputError(format!(
                "{}: this run was continued already",
                self.dir.display()
            ))
        })?;
        sitting.trace_into(part, tally, folder, control)
    }
}

/// The stopped run in `dir` (its scene at `moved_scene` if it moved since),
/// checked: the same traxer build, scene and input files, a tally that fits.
pub fn open_stopped(dir: &Path, moved_scene: Option<&Path>) -> Result<Found, RunError> {
    let path = dir.join(CHECKPOINT_FILE);
    if !path.is_file() {
        if let Ok(h) = read_header(&dir.join(RUN_STATE_FILE)) {
            if h.complete() {
                return Ok(Found::Finished(h.photons));
            }
        }
        return Err(InputError(format!(
            "{}: is not the results folder of a stopped run (it has no {CHECKPOINT_FILE}; runs keep one with --checkpoint-every)",
            dir.display()
        ))
        .into());
    }
    let (header, tally) = read_state(&path)?;
    let this = (super::BUILD.version, super::BUILD.git_hash);
    let id = &header.identity;
    if (id.traxer_version.as_str(), id.git_hash.as_str()) != this {
        return Err(InputError(format!(
            "{}: was written by traxer {} ({}), this is {} ({}): continue it with that build, so that the photons traced before and after are traced alike",
            path.display(), id.traxer_version, id.git_hash, this.0, this.1
        ))
        .into());
    }
    let (device, scene) = reload_scene(
        &header,
        moved_scene,
        |scene| {
            format!(
            "{}: the run's scene {} is no longer there; if it moved, give its new place: `traxer trace NEW_PATH --resume {}` (its SHA-256 is checked)",
            path.display(),
            scene.display(),
            dir.display()
        )
        },
        |diff, _| {
            format!(
            "{}: the checkpoint is of {diff} as now: the scene file {} or a file it reads changed since the run stopped",
            path.display(),
            header.scene_path.display()
        )
        },
    )?;
    let shard = check_checkpoint(&path, &header, &tally, &scene)?;
    Ok(Found::Stopped(Box::new(Resumable {
        dir: dir.to_path_buf(),
        device,
        scene,
        header,
        tally: Some(tally),
        shard,
    })))
}

/// A finished run in `dir`, with its scene loaded again (from `moved_scene`
/// if the file moved) and checked to be the run's: the same scene file, input
/// files and variables, so that its images are read with the geometry that made
/// them. Another build may read it (the run state file's format is checked).
pub fn open_finished(
    dir: &Path,
    moved_scene: Option<&Path>,
) -> Result<(Device, Scene, StateHeader, Tally), RunError> {
    let path = dir.join(RUN_STATE_FILE);
    let (mut header, tally) = read_state(&path)?;
    if !header.complete() {
        return Err(InputError(format!(
            "{}: holds a partial merge of shards",
            path.display()
        ))
        .into());
    }
    // The results stand whichever build reads them: compare the rest.
    let recorded = (
        header.identity.traxer_version.clone(),
        header.identity.git_hash.clone(),
    );
    header.identity.traxer_version = super::BUILD.version.into();
    header.identity.git_hash = super::BUILD.git_hash.into();
    let (device, scene) = reload_scene(
        &header,
        moved_scene,
        |scene| {
            format!(
                "{}: the run's scene {} is no longer there; if it moved, give its new place (scene=NEW_PATH; its SHA-256 is checked)",
                path.display(),
                scene.display()
            )
        },
        |diff, scene| {
            format!(
                "{}: the run is of {diff} as the scene {} now: the scene file or a file it reads changed since the run",
                path.display(),
                scene.display()
            )
        },
    )?;
    (header.identity.traxer_version, header.identity.git_hash) = recorded;
    if !tally.fits(&scene) {
        return Err(InputError(format!(
            "{}: its images do not fit the scene's sensors",
            path.display()
        ))
        .into());
    }
    Ok((device, scene, header, tally))
}

/// The scene of a recorded run (`header`: a checkpoint's or a shard's), loaded
/// again — from `moved` if the file moved — and checked to be the one the run
/// traced (same file, input files, variables, build). `missing` and `changed`
/// say what is wrong, given the scene's path and the identities' difference.
pub(super) fn reload_scene(
    header: &StateHeader,
    moved: Option<&Path>,
    missing: impl FnOnce(&Path) -> String,
    changed: impl FnOnce(&str, &Path) -> String,
) -> Result<(Device, Scene), RunError> {
    let path = moved.map_or_else(|| header.scene_path.clone(), Path::to_path_buf);
    if !path.is_file() {
        return Err(InputError(missing(&path)).into());
    }
    let device = Device::new()?;
    let scene = Scene::load(&device, &path, &header.overrides)?;
    let id = &header.identity;
    let again = RunIdentity::new(&scene, id.seed, id.total_photons, id.shards, id.photon_list);
    match id.difference(&again) {
        Some(diff) => Err(InputError(changed(&diff, &path)).into()),
        None => Ok((device, scene)),
    }
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
    let fits = tally.fits(scene);
    let aligned = tally.traced == shard.photons()
        || (tally.traced < shard.photons() && tally.traced.is_multiple_of(CHUNK));
    if !fits || !aligned || tally.traced != header.traced || header.photons != shard.photons() {
        return Err(bad(
            "its tally does not fit the scene's sensors or its photon counts disagree: not a checkpoint of this run",
        ));
    }
    Ok(shard)
}
