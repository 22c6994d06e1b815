//! `traxer fit-figure-error`: fit the figure-error parameters of a scene's mirrors
//! to measured HPD / 80 % / 90 % diameters (`traxer::studies::fit`), with
//! progress, a CSV history and the result as a preset file.

use super::args::{OutputArgs, RunArgs, SceneArgs};
use super::{load_xray_scene, progress, InputError};
use anyhow::Context;
use traxer::output::{write_fit, FitReport, Provenance, FIT_FILES};
use traxer::run::record::base_identity;
use traxer::run::Study;
use traxer::studies::fit::{
    fit, seed_spread, Bounds, Evaluation, FitSettings, LocalAlgorithm, PARAMETERS,
};
use traxer::studies::{pick_sensor, Diameters};

/// Fit the mirrors' figure errors to measured image quality.
///
/// Every mirror of the scene gets the same parameters (in_plane_narrow,
/// in_plane_wide, wide_fraction, out_of_plane; widths in arcsec). Each candidate is
/// traced with the same photons (--seed), so the objective — the sum of squared
/// relative errors of HPD, 80 % and 90 % diameters — is smooth; NLopt's DIRECT-L
/// searches the bounds globally, Sbplx polishes the best point. Writes
/// history.csv, fit.json and figure_error.toml (a preset for data/figure_errors.toml
/// or a scene's [figure_errors]) into --out; while it runs, fit_checkpoint.json
/// records every evaluation, so that a stopped fit continues with --resume.
/// Example (PANTER Al Kα):
///   traxer fit-figure-error scenes/panter_al_ka.toml --target-hpd 206 --target-c80 397 --target-c90 549
#[derive(clap::Args)]
#[command(mut_arg("photons", |a| a.help("Photons per evaluation")))]
#[command(mut_arg("seed", |a| a.help("Random seed of every evaluation (common random numbers)")))]
#[command(mut_arg("quiet", |a| a.help("No progress bar and no line per evaluation")))]
pub struct FitFigureErrorArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Measured half-power diameter (arcsec).
    #[arg(value_name = "ARCSEC", long)]
    pub target_hpd: f64,
    /// Measured 80 % diameter (arcsec).
    #[arg(value_name = "ARCSEC", long)]
    pub target_c80: f64,
    /// Measured 90 % diameter (arcsec).
    #[arg(value_name = "ARCSEC", long)]
    pub target_c90: f64,
    /// Search range NAME=LOW:HIGH, or NAME=VALUE to hold it fixed (repeatable).
    /// Defaults: in_plane_narrow=0:120, in_plane_wide=0:900, wide_fraction=0:0.6,
    /// out_of_plane=0.
    #[arg(long = "bound", value_name = "NAME=LOW:HIGH")]
    pub bounds: Vec<String>,
    /// Evaluations of the global search (DIRECT-L).
    #[arg(value_name = "N", long, default_value_t = 150)]
    pub global_evals: u32,
    /// Evaluations of the local polish.
    #[arg(value_name = "N", long, default_value_t = 60)]
    pub local_evals: u32,
    /// Local optimiser of the polish.
    #[arg(long, value_enum, default_value = "sbplx")]
    pub local_algorithm: LocalAlgorithmArg,
    /// Extra seeds traced with the best parameters to show the Monte Carlo spread.
    #[arg(value_name = "K", long, default_value_t = 3)]
    pub check_seeds: u64,
    /// Sensor to measure (default: the scene's only sensor).
    #[arg(value_name = "NAME", long)]
    pub sensor: Option<String>,
    /// Name of the preset written to figure_error.toml.
    #[arg(value_name = "PRESET", long, default_value = "fitted")]
    pub name: String,
    /// Continue the stopped fit whose results folder is --out: run the same
    /// command with --resume; the evaluations it recorded (fit_checkpoint.json)
    /// are taken instead of traced, and the fit ends as if never stopped.
    #[arg(long)]
    pub resume: bool,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// NLopt's derivative-free local optimisers, as command-line values.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum LocalAlgorithmArg {
    Bobyqa,
    Sbplx,
    NelderMead,
}

impl From<LocalAlgorithmArg> for LocalAlgorithm {
    fn from(a: LocalAlgorithmArg) -> LocalAlgorithm {
        match a {
            LocalAlgorithmArg::Bobyqa => LocalAlgorithm::Bobyqa,
            LocalAlgorithmArg::Sbplx => LocalAlgorithm::Sbplx,
            LocalAlgorithmArg::NelderMead => LocalAlgorithm::NelderMead,
        }
    }
}

fn parse_bounds(specs: &[String]) -> Result<Bounds, InputError> {
    let mut b = Bounds::default();
    for spec in specs {
        let bad = |why: &str| InputError(format!("--bound {spec}: {why}"));
        let (name, range) = spec
            .split_once('=')
            .ok_or_else(|| bad("expected NAME=LOW:HIGH or NAME=VALUE"))?;
        let i = PARAMETERS
            .iter()
            .position(|p| *p == name.trim())
            .ok_or_else(|| {
                bad(&format!(
                    "unknown parameter (known: {})",
                    PARAMETERS.join(", ")
                ))
            })?;
        let number = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| bad("expected non-negative numbers"))
        };
        let (lo, hi) = match range.split_once(':') {
            Some((l, h)) => (number(l)?, number(h)?),
            None => {
                let v = number(range)?;
                (v, v)
            }
        };
        if lo > hi {
            return Err(bad("LOW must not exceed HIGH"));
        }
        if i == 2 && hi > 1.0 {
            return Err(bad("wide_fraction is a probability (0 to 1)"));
        }
        b.lower[i] = lo;
        b.upper[i] = hi;
    }
    Ok(b)
}

pub fn run(a: FitFigureErrorArgs) -> anyhow::Result<()> {
    let run = a.run.config()?;
    let (device, mut scene) = load_xray_scene(&a.scene)?;
    let settings = fit_settings(&a, &scene, &run)?;
    let study: Study<Evaluation> = Study::open(
        &a.output.scene_folder(&a.scene.scene, "fit"),
        "fit",
        &FIT_FILES,
        identity(&scene, &settings),
        a.resume,
    )?;
    let replay = study.replay();
    let quiet = a.output.quiet.quiet;
    if !quiet && a.resume {
        say!("resuming: {} evaluations recorded", replay.len());
    }
    super::signals::set_stop_message(format!(
        "stopped; the evaluations so far are in {}: run the same command with --resume to continue",
        study.record_path().display()
    ));
    // Progress in evaluations (DIRECT-L may stop early; the bar then ends
    // short of its length); the seed check counts as its traces finish.
    let evaluations = a.global_evals as u64 + a.local_evals as u64 + a.check_seeds;
    let bar = progress::bar(evaluations, "evaluations", quiet);
    let started = std::time::Instant::now();
    let result = fit(&mut scene, &settings, &replay, &|_| {}, |e, best| {
        bar.inc(1);
        if let Some(w) = study.point_done_at(e.index - 1, e) {
            tell!("warning: {w}");
        }
        if !quiet && e.index > replay.len() {
            bar.suspend(|| tell!("{}", evaluation_line(e, best, &started)));
        }
    });
    let fit_seconds = started.elapsed().as_secs_f64();
    let result = result?;
    // Monte Carlo spread: the best parameters with other seeds (the fit saw one).
    let traced = std::sync::atomic::AtomicU64::new(0);
    let spread = seed_spread(&mut scene, &settings, &result.best, a.check_seeds, &|n| {
        let before = traced.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        let checks_done = (before + n) / run.photons - before / run.photons;
        bar.inc(checks_done);
    });
    bar.finish_and_clear();
    let spread = spread?;
    let provenance = Provenance::new(&super::invocation(), Some(device.info().version))
        .scene(&scene)
        .run(&run, result.threads);
    let report = FitReport {
        result: &result,
        settings: &settings,
        spread: &spread,
        extra_seeds: a.check_seeds,
        preset_name: &a.name,
        fit_seconds,
    };
    let out = &a.output.scene_folder(&a.scene.scene, "fit");
    let folder = study.folder;
    write_fit(folder.path(), &report, &provenance)
        .and_then(|_| folder.commit())
        .with_context(|| format!("cannot write the results into {}", out.display()))?;
    print_result(&report, out);
    Ok(())
}

/// The fit's settings from the command line, checked against the scene.
fn fit_settings(
    a: &FitFigureErrorArgs,
    scene: &traxer::scene::Scene,
    run: &traxer::trace::RunConfig,
) -> anyhow::Result<FitSettings> {
    let target = Diameters {
        hpd: a.target_hpd,
        d80: a.target_c80,
        d90: a.target_c90,
    };
    if ![target.hpd, target.d80, target.d90]
        .iter()
        .all(|v| v.is_finite() && *v > 0.0)
    {
        return Err(InputError("the targets must be positive diameters (arcsec)".into()).into());
    }
    let bounds = parse_bounds(&a.bounds)?;
    let sensor = pick_sensor(scene, a.sensor.as_deref())?;
    if scene.sensors[sensor].focal_length.is_none() {
        return Err(InputError(format!(
            "sensor `{}` has no focal_length: the diameters in arcseconds need one",
            scene.sensors[sensor].name
        ))
        .into());
    }
    Ok(FitSettings {
        bounds,
        target,
        run: run.clone(),
        sensor,
        global_evaluations: a.global_evals,
        local_evaluations: a.local_evals,
        local_algorithm: a.local_algorithm.into(),
    })
}

/// One line per evaluation: its parameters and diameters, and the best so far.
fn evaluation_line(e: &Evaluation, best: &Evaluation, started: &std::time::Instant) -> String {
    let p = &e.parameters;
    let d = e.diameters.map_or("no image".into(), |d| {
        format!("{:.1}″ {:.1}″ {:.1}″", d.hpd, d.d80, d.d90)
    });
    format!(
        "eval {:>4} ({}, {:.0} s): narrow {:.2}″ wide {:.2}″ fraction {:.4} out {:.2}″ → {d}, error {:.3e} | best {:.3e} (eval {})",
        e.index,
        e.stage,
        started.elapsed().as_secs_f64(),
        p.in_plane_narrow,
        p.in_plane_wide,
        p.wide_fraction,
        p.out_of_plane,
        e.error,
        best.error,
        best.index
    )
}

/// What must be equal for a recorded evaluation to be this fit's.
fn identity(scene: &traxer::scene::Scene, s: &FitSettings) -> serde_json::Value {
    let mut id = base_identity(scene);
    id.extend([
        ("sensor".into(), scene.sensors[s.sensor].name.clone().into()),
        ("photons".into(), s.run.photons.into()),
        ("seed".into(), s.run.seed.into()),
        ("target_arcsec".into(), serde_json::json!(s.target)),
        ("bounds_lower".into(), serde_json::json!(s.bounds.lower)),
        ("bounds_upper".into(), serde_json::json!(s.bounds.upper)),
        ("global_evaluations".into(), s.global_evaluations.into()),
        ("local_evaluations".into(), s.local_evaluations.into()),
        (
            "local_algorithm".into(),
            format!("{:?}", s.local_algorithm).into(),
        ),
    ]);
    id.into()
}

/// The result on stdout.
fn print_result(report: &FitReport, out: &std::path::Path) {
    let (result, spread, target) = (report.result, report.spread, &report.settings.target);
    let p = &result.best.parameters;
    say!(
        "best after {} evaluations ({:.0} s): in_plane_narrow {:.2}″, in_plane_wide {:.2}″, wide_fraction {:.4}, out_of_plane {:.2}″",
        result.history.len(),
        report.fit_seconds,
        p.in_plane_narrow,
        p.in_plane_wide,
        p.wide_fraction,
        p.out_of_plane
    );
    let (hpd, d80, d90) = (spread.hpd, spread.d80, spread.d90);
    say!(
        "  HPD {:.1} ± {:.1}″ (target {}), 80 % {:.1} ± {:.1}″ (target {}), 90 % {:.1} ± {:.1}″ (target {}); mean ± sd over {} seeds",
        hpd.0, hpd.1, target.hpd, d80.0, d80.1, target.d80, d90.0, d90.1, target.d90, spread.seeds
    );
    say!(
        "wrote history.csv, fit.json, figure_error.toml to {}",
        out.display()
    );
}
