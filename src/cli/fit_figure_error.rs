//! `traxer fit-figure-error`: fit the figure-error parameters of a scene's mirrors
//! to measured HPD / 80 % / 90 % diameters (`traxer::studies::fit`), with
//! progress, a CSV history and the result as a preset file.

use super::args::{OutputArgs, RunArgs, SceneArgs};
use super::{load_xray_scene, progress, InputError};
use traxer::output::{write_fit, FitReport, Provenance, FIT_FILES};
use traxer::run::record::base_identity;
use traxer::run::Study;
use traxer::scene::Scene;
use traxer::studies::fit::{
    fit, seed_spread, Bounds, Evaluation, FitSettings, LocalAlgorithm, Spread, PARAMETERS,
};
use traxer::studies::fit_errors::{
    parameter_errors, predict, sensitivity, ParameterErrors, Prediction,
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
/// or a scene's [figure_errors]) into --out; while it runs, fit_checkpoint.jsonl
/// records every evaluation, so that a stopped fit continues with --resume.
/// After the fit: the parameters' errors (Monte Carlo, and for --target-error)
/// and, for each --predict scene, its diameters with their errors (fit.json).
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
    /// Uncertainty (1σ) assumed for each target diameter, in per cent of it: the
    /// fit error of the parameters and of the predictions (the measured numbers
    /// come without one; it also stands for the model's misfit).
    #[arg(value_name = "PCT", long, default_value_t = 2.0)]
    pub target_error: f64,
    /// A scene to predict with the fitted parameters (repeatable; loaded with the
    /// same -D overrides): its diameters with their Monte Carlo and fit errors,
    /// e.g. --predict scenes/panter_ti_ka.toml --predict scenes/panter_fe_ka.toml.
    #[arg(value_name = "SCENE", long)]
    pub predict: Vec<std::path::PathBuf>,
    /// Seeds traced for each prediction (its Monte Carlo error).
    #[arg(value_name = "N", long, default_value_t = 4)]
    pub predict_seeds: u64,
    /// Name of the preset written to figure_error.toml.
    #[arg(value_name = "PRESET", long, default_value = "fitted")]
    pub name: String,
    /// Continue the stopped fit whose results folder is --out: run the same
    /// command with --resume; the evaluations it recorded (fit_checkpoint.jsonl)
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
    let mut predicted = prediction_scenes(&a)?;
    let study: Study<Evaluation> = Study::open(
        &a.output.scene_folder(&a.scene, "fit"),
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
    super::signals::set_stop_message(study.stop_message("evaluations"));
    // Progress in evaluations (DIRECT-L may stop early; the bar then ends
    // short of its length); the traces after the fit count as they finish.
    let evaluations = evaluations_planned(&a, &settings, predicted.len());
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
    let after = after_fit(&a, (&mut scene, &mut predicted), &settings, &result, &bar);
    bar.finish_and_clear();
    let (spread, errors, predictions) = after?;
    let provenance = Provenance::of_study(
        &super::invocation(),
        device.info().version,
        &scene,
        (run.photons, run.seed),
        result.threads,
    );
    let report = FitReport {
        result: &result,
        settings: &settings,
        spread: &spread,
        extra_seeds: a.check_seeds,
        preset_name: &a.name,
        fit_seconds,
        errors: &errors,
        predictions: &predictions,
    };
    let out = &a.output.scene_folder(&a.scene, "fit");
    study.finish(|dir| write_fit(dir, &report, &provenance))?;
    print_result(&report, out);
    Ok(())
}

/// The evaluations the bar counts: the fit's budget, the seed check, the
/// sensitivity (two traces per free parameter) and each prediction's seeds and
/// sensitivity.
fn evaluations_planned(a: &FitFigureErrorArgs, settings: &FitSettings, predictions: usize) -> u64 {
    let b = &settings.bounds;
    let free = (0..4).filter(|&i| b.upper[i] > b.lower[i]).count() as u64;
    a.global_evals as u64
        + a.local_evals as u64
        + a.check_seeds
        + 2 * free
        + predictions as u64 * (a.predict_seeds.max(2) + 2 * free)
}

/// After the fit: the Monte Carlo spread of the best parameters over other
/// seeds (the fit saw one), then the parameters' errors and the predictions;
/// `bar` advances by one at every finished trace.
fn after_fit(
    a: &FitFigureErrorArgs,
    (scene, predicted): (&mut Scene, &mut [(Scene, usize)]),
    settings: &FitSettings,
    result: &traxer::studies::fit::FitResult,
    bar: &progress::Bar,
) -> anyhow::Result<(Spread, ParameterErrors, Vec<Prediction>)> {
    let photons = settings.run.photons;
    let traced = std::sync::atomic::AtomicU64::new(0);
    let per_trace = |n: u64| {
        let before = traced.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        bar.inc((before + n) / photons - before / photons);
    };
    let spread = seed_spread(scene, settings, &result.best, a.check_seeds, &per_trace)?;
    let (mut errors, predictions) = errors_and_predictions(
        a,
        scene,
        predicted,
        settings,
        (&result.best, &spread),
        &per_trace,
    )?;
    let free: Vec<usize> = (0..4)
        .filter(|&i| settings.bounds.upper[i] > settings.bounds.lower[i])
        .collect();
    errors.assess(&free, &settings.bounds, &result.history);
    Ok((spread, errors, predictions))
}

/// The scenes of --predict, loaded with the fit's -D overrides, each with
/// the sensor to measure (the --sensor name, or its only one).
fn prediction_scenes(a: &FitFigureErrorArgs) -> anyhow::Result<Vec<(Scene, usize)>> {
    if !(a.target_error.is_finite() && a.target_error > 0.0 && a.target_error < 100.0) {
        return Err(InputError(format!(
            "--target-error {}: expected a percentage between 0 and 100",
            a.target_error
        ))
        .into());
    }
    a.predict
        .iter()
        .map(|path| {
            let args = SceneArgs {
                scene: path.clone(),
                vars: a.scene.vars.clone(),
            };
            let (_, scene) = load_xray_scene(&args)
                .map_err(|e| e.context(format!("--predict {}", path.display())))?;
            let sensor = pick_sensor(&scene, a.sensor.as_deref())
                .map_err(|e| InputError(format!("--predict {}: {e}", path.display())))?;
            check_predictable(&scene, sensor, path)?;
            if scene.sensors[sensor].focal_length.is_none() {
                return Err(InputError(format!(
                    "{}: sensor `{}` has no focal_length, which the diameters in arcseconds need",
                    path.display(),
                    scene.sensors[sensor].name
                ))
                .into());
            }
            Ok((scene, sensor))
        })
        .collect()
}

/// Photons of the trial trace that checks a --predict scene before the fit.
const TRIAL_PHOTONS: u64 = 20_000;

/// Refuses, before the fit runs, a --predict scene whose diameters the fitted
/// figure errors cannot predict: one without a mirror for them to act on, or
/// one where no photon of a short trial trace reaches the sensor.
fn check_predictable(scene: &Scene, sensor: usize, path: &std::path::Path) -> anyhow::Result<()> {
    let mirrors = scene
        .objects
        .iter()
        .any(|o| matches!(o.material, traxer::material::Material::Mirror { .. }));
    if !mirrors {
        return Err(InputError(format!(
            "--predict {}: the scene has no mirror for the fitted figure errors to act on",
            path.display()
        ))
        .into());
    }
    let trial = traxer::trace::run(scene, &traxer::trace::RunConfig::new(TRIAL_PHOTONS, 1))?;
    if trial.images[sensor].total_flux() <= 0.0 {
        return Err(InputError(format!(
            "--predict {}: no photon of a {TRIAL_PHOTONS}-photon trial trace reaches sensor `{}`, so its diameters cannot be predicted (check the sensor's place and the sources)",
            path.display(),
            scene.sensors[sensor].name
        ))
        .into());
    }
    Ok(())
}

/// The fitted parameters' errors (from the fit scene's sensitivity, the seed
/// spread and --target-error) and each --predict scene's diameters with theirs.
fn errors_and_predictions(
    a: &FitFigureErrorArgs,
    scene: &mut Scene,
    predicted: &mut [(Scene, usize)],
    settings: &FitSettings,
    (best, spread): (&Evaluation, &Spread),
    progress: &dyn traxer::progress::Progress,
) -> Result<(ParameterErrors, Vec<Prediction>), traxer::studies::StudyError> {
    let p = &best.parameters;
    let j = sensitivity(scene, settings, p, progress)?;
    let mc_sd =
        [spread.hpd.1, spread.d80.1, spread.d90.1].map(|v| if v.is_finite() { v } else { 0.0 });
    let errors = parameter_errors(&j, p, mc_sd, &settings.target, a.target_error / 100.0)?;
    let predictions = predicted
        .iter_mut()
        .map(|(s, sensor)| {
            let here = FitSettings {
                sensor: *sensor,
                ..settings.clone()
            };
            predict(s, &here, p, &errors, a.predict_seeds, progress).map_err(|e| match e {
                traxer::studies::StudyError::Input(m) => traxer::studies::StudyError::Input(
                    format!("--predict {}: {m}", s.path.display()),
                ),
                other => other,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((errors, predictions))
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
    // The name becomes a key of figure_error.toml: a dot would nest tables.
    let bare = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    if a.name.is_empty() || !a.name.chars().all(bare) {
        return Err(InputError(format!(
            "--name {:?}: a preset name is a bare TOML key: letters, digits, _ and - (e.g. llnl_panter_sigma_0p5)",
            a.name
        ))
        .into());
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
    let e = report.errors;
    for i in 0..e.names.len() {
        say!("  {}", e.quoted(i));
    }
    for d in &e.degenerate {
        say!("  {d}");
    }
    for p in report.predictions {
        let d = &p.diameters;
        say!(
            "  predicted {}: HPD {:.1} ± {:.1} ± {:.1}″, 80 % {:.1} ± {:.1} ± {:.1}″, 90 % {:.1} ± {:.1} ± {:.1}″ (mean of {} seeds ± Monte Carlo ± fit)",
            p.scene, d.hpd, p.monte_carlo[0], p.fit[0], d.d80, p.monte_carlo[1], p.fit[1],
            d.d90, p.monte_carlo[2], p.fit[2], p.seeds
        );
    }
    say!(
        "wrote history.csv, fit.json, figure_error.toml to {}",
        out.display()
    );
}
