//! `traxer trace`: run a scene and write the sensor images and summary.

use super::args::{DefineArgs, OutputArgs, RunArgs, SceneArgs};
use super::{load_xray_scene, resume, InputError};
use std::path::PathBuf;
use std::time::Duration;
use traxer::run::{RunSettings, Shard, TraceJob};

/// Trace photons through a scene and write every sensor's image.
///
/// Writes into --out, per sensor object NAME: NAME.npy (flux = sum of weights, f64,
/// shape [ny, nx], or [bands, ny, nx] with energy bins), NAME_counts.npy (photons
/// per pixel), NAME.png and NAME_log.png (viridis), NAME_eef.png (encircled energy
/// with the 50/80/90 % diameters), NAME_projections.csv (x and y profiles),
/// NAME.json (provenance, sensor geometry, image quality, statistics); a sensor
/// with a detector `pixel_grid` also NAME_grid.npy/.png/.csv (the image on the
/// detector's pixels), one with a `gas` NAME_conversion_depth.csv/.png and
/// NAME_conversion_spectrum.csv (where and at which energies the X-rays convert),
/// and with a Sun and several emission processes NAME_<process>.npy; with --fits
/// NAME.fits (WCS in mm on the sensor, in arcsec at its focal length and, for a
/// Sun, helioprojective on the sky); summary.json for the whole run; and
/// run_state.bin, the exact sums for `traxer merge`. The same seed gives bit-identical images for any --threads, for a run
/// cut into --shard parts and merged, and for a run stopped and resumed.
#[derive(clap::Args)]
pub struct TraceArgs {
    /// Scene file (TOML); see docs/scene-format.md.
    #[arg(required_unless_present = "resume")]
    pub scene: Option<PathBuf>,
    #[command(flatten)]
    pub vars: DefineArgs,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub output: OutputArgs,
    /// Trace shard K of N of the run of --photons photons (1 ≤ K ≤ N; e.g.
    /// --shard $SLURM_ARRAY_TASK_ID/16), for `traxer merge` to add up into the
    /// bit-identical result of the whole run.
    #[arg(value_name = "K/N", long)]
    pub shard: Option<String>,
    /// Also write photons.npy (a NumPy structured array) and photons.csv: the first
    /// N photons recorded on any sensor, with position, direction, energy, weight
    /// (in the units of the sensor's image: axions per second with a Sun, else
    /// the source's weight, which summary.json → sources[].weight explains) and
    /// history (reflections, first and last mirror, path
    /// class).
    #[arg(value_name = "N", long, default_value_t = 0)]
    pub photon_list: usize,
    /// Write a checkpoint (DIR/checkpoint.bin) at most every this many seconds
    /// (0: after every batch of about a million photons), and on SIGINT/SIGTERM
    /// before stopping; `--resume DIR` continues the run.
    #[arg(value_name = "SECONDS", long)]
    pub checkpoint_every: Option<f64>,
    /// Continue the stopped run whose results folder is DIR, from its checkpoint
    /// (scene, variables, seed, photons and shard come from it; give SCENE only
    /// if the scene file has moved since: its SHA-256 is checked).
    #[arg(value_name = "DIR", long, conflicts_with_all = ["define", "photons", "seed", "shard", "photon_list", "out"])]
    pub resume: Option<PathBuf>,
    /// Also write each sensor's flux image as NAME.fits: a float64 primary image
    /// (a cube [band, y, x] with energy bins) whose header holds the WCS in mm on
    /// the sensor, an alternative WCS "A" in arcsec at the sensor's focal length,
    /// BUNIT, the energy range and the provenance.
    #[arg(long)]
    pub fits: bool,
    /// A mass scan: also one image per axion mass (eV), from the same photons
    /// (NAME_by_mass.npy, totals in NAME.json → by_mass). Shorthand for
    /// -D axion_masses_ev=[LIST], the variable the shipped magnet scenes give
    /// their [magnet] masses_ev; needs the magnet on (the shipped Sun scenes have it on).
    #[arg(value_name = "LIST", long, conflicts_with = "resume")]
    pub masses: Option<String>,
    /// Replace the results of a run with other inputs (scene, variables, seed,
    /// photons, shards) in the results folder; without it such a folder is
    /// refused and kept.
    #[arg(long, conflicts_with = "resume")]
    pub replace: bool,
}

pub fn run(a: TraceArgs) -> anyhow::Result<()> {
    let settings = RunSettings {
        threads: a.run.sampling.threads,
        checkpoint_every: checkpoint_interval(a.checkpoint_every)?,
        fits: a.fits,
        replace: a.replace,
    };
    let quiet = a.output.quiet.quiet;
    if let Some(dir) = &a.resume {
        return resume::resume(dir, a.scene.as_deref(), &settings, quiet);
    }
    let mut cfg = a.run.config()?;
    let shard = match &a.shard {
        Some(text) => Shard::parse(text, cfg.photons).map_err(InputError)?,
        None => Shard::whole(cfg.photons),
    };
    cfg.first_photon = shard.range().start;
    cfg.photons = shard.photons();
    cfg.photon_list = traxer::run::check_photon_list(a.photon_list, traxer::run::FrontEnd::Cli)?;
    let mut vars = a.vars.clone();
    if let Some(list) = &a.masses {
        vars.define.push(mass_scan_define(list)?);
    }
    let scene_args = SceneArgs {
        scene: a
            .scene
            .clone()
            .expect("clap requires a scene without --resume"),
        vars,
    };
    let (device, scene) = load_xray_scene(&scene_args)?;
    if scene.sensors.is_empty() {
        tell!("warning: the scene has no sensor; only statistics will be written");
    }
    let job = TraceJob {
        scene: &scene,
        embree_version: device.info().version,
        cfg,
        shard,
    };
    let control = resume::CliControl::new(job.cfg.photons, quiet);
    let out = a.output.scene_folder(&scene_args, "");
    let finished = job.run(&out, &settings, &super::invocation(), &control);
    resume::finish(&scene, finished?, &control, quiet);
    Ok(())
}

/// `--masses LIST` as the override of the shipped scenes' mass-scan variable.
fn mass_scan_define(list: &str) -> Result<String, InputError> {
    let masses = list
        .split(',')
        .map(|m| match m.trim().parse::<f64>() {
            // As written before (the override's text is part of a run's
            // identity), except a huge whole number, which `to_string` spells
            // as an integer of 20 digits that TOML cannot hold: `{:?}` keeps
            // it a float (1e19), for the magnet to refuse by its value.
            Ok(v) if v.is_finite() && v >= 0.0 => Ok(match v.to_string() {
                s if s.len() > 16 => format!("{v:?}"),
                s => s,
            }),
            _ => Err(InputError(format!(
                "--masses {list}: `{m}` is not a mass ≥ 0 in eV (give e.g. --masses 0,0.01,0.02)"
            ))),
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(format!("axion_masses_ev=[{}]", masses.join(",")))
}

/// `--checkpoint-every` checked: a finite number of seconds ≥ 0.
fn checkpoint_interval(s: Option<f64>) -> Result<Option<Duration>, InputError> {
    match s {
        None => Ok(None),
        Some(v) if (0.0..1e9).contains(&v) => Ok(Some(Duration::from_secs_f64(v))),
        Some(v) => Err(InputError(format!(
            "--checkpoint-every {}: expected seconds between checkpoints, 0 or more",
            traxer::text::number(v)
        ))),
    }
}
