//! `traxer fit-figure-error`: fit the figure-error parameters of a scene's mirrors
//! to measured HPD / 80 % / 90 % diameters (`traxer::studies::fit`), with
//! progress, a CSV history and the result as a preset file.

use super::args::{OutputArgs, RunArgs, SceneArgs};
use super::{load_xray_scene, InputError};
use traxer::output::FitReport;
use traxer::scene::Scene;
use traxer::studies::fit::{Bounds, FitSettings, LocalAlgorithm, PARAMETERS};
use traxer::studies::fit_study::{AfterFit, FitStudy};
use traxer::studies::{pick_sensor, Diameters, StudyError};

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
    let (device, scene) = load_xray_scene(&a.scene)?;
    let settings = fit_settings(&a, &scene, &run)?;
    let after = AfterFit {
        check_seeds: a.check_seeds,
        target_fraction: a.target_error / 100.0,
        predict_seeds: a.predict_seeds,
        preset_name: a.name.clone(),
    };
    let load = |extra: &[String]| -> Result<Scene, StudyError> {
        let defines = traxer::scene::merged_overrides(&a.scene.vars.define, extra);
        Ok(Scene::load(&device, &a.scene.scene, &defines)?)
    };
    let study = FitStudy::new(&scene, settings, after, &load, prediction_scenes(&a)?)?;
    let places = (&a.scene, &a.output);
    let (output, out) = super::study::run_loaded(&study, (&device, &scene), places, a.resume)?;
    print_result(&FitReport::of(&study, &output), &out);
    Ok(())
}

/// The scenes of --predict, loaded with the fit's -D overrides, each with
/// the sensor to measure (the --sensor name, or its only one).
fn prediction_scenes(a: &FitFigureErrorArgs) -> anyhow::Result<Vec<(Scene, usize)>> {
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
            Ok((scene, sensor))
        })
        .collect()
}

/// The fit's settings from the command line, its sensor picked in the scene.
fn fit_settings(
    a: &FitFigureErrorArgs,
    scene: &traxer::scene::Scene,
    run: &traxer::trace::RunConfig,
) -> anyhow::Result<FitSettings> {
    Ok(FitSettings {
        bounds: parse_bounds(&a.bounds)?,
        target: Diameters {
            hpd: a.target_hpd,
            d80: a.target_c80,
            d90: a.target_c90,
        },
        run: run.clone(),
        sensor: pick_sensor(scene, a.sensor.as_deref())?,
        global_evaluations: a.global_evals,
        local_evaluations: a.local_evals,
        local_algorithm: a.local_algorithm.into(),
    })
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
