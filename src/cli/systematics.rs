//! `traxer systematics`: the image's systematic uncertainty, the scene traced
//! under each source of uncertainty with common random numbers
//! (`traxer::studies::systematics`).

use super::args::{OutputArgs, SamplingArgs, SceneArgs};
use super::{load_xray_scene, InputError, Warnings};
use std::sync::Mutex;
use traxer::output::SYSTEMATICS_FILES;
use traxer::scene::Scene;
use traxer::studies::systematics::{self, Request, Settings, Systematics, SystematicsStudy};
use traxer::studies::StudyError;

/// The image's systematic uncertainty: the scene traced under each source of
/// uncertainty with the same photons.
///
/// Sources (by default every one the scene's variables support; --sources
/// picks): figure (--figure-draws parameter sets drawn from the covariance
/// that fit-figure-error saved with the mirrors' preset; parameters the fit
/// left unconstrained are held, the others drawn given them),
/// optical_constants (the coatings' f1, f2 from Chantler's table instead of
/// Henke's, variable mirror_optical_constants), solar_model (B16-GS98 against the scene's B16-AGSS09met), pointing_x/pointing_y (the
/// Sun's centre moved by ±--pointing, variables offset_x/offset_y),
/// tilt_x/tilt_y (the telescope's axis turned by ±--tilt about its centre
/// plane, variables telescope_tilt_x/y), gas_pressure/gas_temperature (the
/// detector gas within the given ranges), and any scene variable with --vary.
/// Every variation is traced with --photons photons of the same seed (common
/// random numbers), so differences are the sources' effects, not noise.
/// Writes systematics.csv (one row per variation: flux, flux in the central
/// square, HPD/80 %/90 %, centroid), systematics.json (each source's σ and
/// shift, the total in quadrature), per-pixel mean and σ images (map_*.npy,
/// systematics.fits, PNG) on the sensor's detector pixel grid (or the image
/// binned to ≤ 256 pixels a side). Example (CAST's axion–electron image):
///   traxer systematics scenes/cast_axion_electron_image.toml -n 1e6
#[derive(clap::Args)]
pub struct SystematicsArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Photons traced per variation.
    #[arg(short = 'n', long, value_name = "N", default_value = "1000000", value_parser = super::args::parse_count)]
    pub photons: u64,
    /// Sources of uncertainty, comma-separated (default: every one the scene
    /// supports): figure, optical_constants, solar_model, pointing_x,
    /// pointing_y, tilt_x, tilt_y, gas_pressure, gas_temperature.
    #[arg(long, value_name = "LIST")]
    pub sources: Option<String>,
    /// Parameter sets drawn from the figure-error covariance.
    #[arg(long, value_name = "N", default_value_t = 20)]
    pub figure_draws: usize,
    /// The figure-error preset whose covariance to draw from (default: the
    /// scene variable figure_error).
    #[arg(long, value_name = "NAME")]
    pub figure_preset: Option<String>,
    /// Figure parameters held at the preset's values, comma-separated, or
    /// "none" (default: those the fit found unconstrained).
    #[arg(long, value_name = "LIST")]
    pub figure_hold: Option<String>,
    /// Pointing offset of the Sun's centre (arcmin), ± in x and in y.
    #[arg(long, value_name = "ARCMIN", default_value_t = 1.0)]
    pub pointing: f64,
    /// Tilt of the telescope's axis (arcmin), ± towards x and towards y.
    #[arg(long, value_name = "ARCMIN", default_value_t = 1.0)]
    pub tilt: f64,
    /// The alternative solar model.
    #[arg(long, value_name = "MODEL", default_value = "b16_gs98")]
    pub solar_model: String,
    /// Gas pressure range (mbar) [default: the scene's ± 50 mbar].
    #[arg(long, value_name = "LOW:HIGH")]
    pub gas_pressure: Option<String>,
    /// Gas temperature range (K) [default: the scene's ± 10 K].
    #[arg(long, value_name = "LOW:HIGH")]
    pub gas_temperature: Option<String>,
    /// Vary a scene variable over a range (repeatable): NAME=LOW:HIGH.
    #[arg(long, value_name = "NAME=LOW:HIGH")]
    pub vary: Vec<String>,
    /// Sensor to image on (default: the scene's only sensor).
    #[arg(value_name = "NAME", long)]
    pub sensor: Option<String>,
    /// Side (mm) of the central square whose flux the table gives.
    #[arg(value_name = "MM", long, default_value_t = 5.0)]
    pub central: f64,
    /// A circle of this radius (mm) about the sensor's centre instead of the
    /// central square: a signal region.
    #[arg(value_name = "MM", long, conflicts_with = "central")]
    pub central_radius: Option<f64>,
    /// Continue the stopped study whose results folder is --out: run the same
    /// command with --resume; the variations it recorded
    /// (systematics_checkpoint.jsonl) are not traced again.
    #[arg(long)]
    pub resume: bool,
    #[command(flatten)]
    pub sampling: SamplingArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// LOW:HIGH of option `what`.
fn range(what: &str, s: &str) -> Result<[f64; 2], InputError> {
    let bad = || InputError(format!("--{what} {s}: expected LOW:HIGH, two numbers"));
    let (a, b) = s.split_once(':').ok_or_else(bad)?;
    let lh = [a, b].map(|x| x.trim().parse::<f64>());
    match lh {
        [Ok(l), Ok(h)] if l.is_finite() && h.is_finite() && l < h => Ok([l, h]),
        [Ok(_), Ok(_)] => Err(InputError(format!("--{what} {s}: LOW must be below HIGH"))),
        _ => Err(bad()),
    }
}

/// A comma-separated list.
fn list(s: &str) -> Vec<String> {
    s.split(',')
        .map(|p| p.trim().to_string())
        .filter(|p| !p.is_empty())
        .collect()
}

fn request(a: &SystematicsArgs) -> Result<Request, InputError> {
    let vary = a
        .vary
        .iter()
        .map(|v| {
            let (name, r) = v
                .split_once('=')
                .ok_or_else(|| InputError(format!("--vary {v}: expected NAME=LOW:HIGH")))?;
            Ok((name.trim().to_string(), range("vary", r)?))
        })
        .collect::<Result<_, InputError>>()?;
    for (what, x) in [("pointing", a.pointing), ("tilt", a.tilt)] {
        if !(x.is_finite() && x > 0.0) {
            return Err(InputError(format!(
                "--{what} {x}: expected a positive angle in arcmin"
            )));
        }
    }
    Ok(Request {
        sources: a.sources.as_deref().map(list),
        figure_draws: a.figure_draws,
        figure_preset: a.figure_preset.clone(),
        figure_hold: a.figure_hold.as_deref().map(|h| match h.trim() {
            "none" => Vec::new(),
            h => list(h),
        }),
        pointing_arcmin: a.pointing,
        tilt_arcmin: a.tilt,
        solar_model: a.solar_model.clone(),
        gas_pressure_mbar: a
            .gas_pressure
            .as_deref()
            .map(|s| range("gas-pressure", s))
            .transpose()?,
        gas_temperature_k: a
            .gas_temperature
            .as_deref()
            .map(|s| range("gas-temperature", s))
            .transpose()?,
        vary,
        seed: a.sampling.seed,
    })
}

pub fn run(a: SystematicsArgs) -> anyhow::Result<()> {
    let (req, settings) = (request(&a)?, settings(&a));
    systematics::check(&settings)?;
    let (device, scene) = load_xray_scene(&a.scene)?;
    let plan = systematics::plan(&scene, &req)?;
    let quiet = a.output.quiet.quiet;
    if !quiet {
        print_plan(&plan);
    }
    let warnings = Mutex::new(Warnings::default());
    let load = |extra: &[String]| -> Result<Scene, StudyError> {
        let defines = traxer::scene::merged_overrides(&a.scene.vars.define, extra);
        let s = Scene::load(&device, &a.scene.scene, &defines)?;
        warnings.lock().expect("not poisoned").show(&s);
        Ok(s)
    };
    let study = SystematicsStudy {
        settings,
        plan: &plan,
        load: &load,
        scene_name: scene.name_for_people(),
    };
    let scene_args = (&a.scene, &a.output);
    let (s, out) = super::study::run_loaded(&study, (&device, &scene), scene_args, a.resume)?;
    if !quiet {
        print_table(&s);
        say!(
            "wrote {} to {}",
            SYSTEMATICS_FILES.all().join(", "),
            out.display()
        );
    }
    Ok(())
}

/// How each variation is traced.
fn settings(a: &SystematicsArgs) -> Settings {
    Settings {
        sampling: a.sampling.block(a.photons, &a.sensor),
        central_mm: a.central_radius.unwrap_or(a.central),
        central_circle: a.central_radius.is_some(),
    }
}

/// What will be traced.
fn print_plan(p: &systematics::Plan) {
    say!("{} variations (the nominal scene and):", p.variations.len());
    for s in &p.sources {
        say!("  {:<16} {}", s.name, s.what);
    }
    for (name, why) in &p.skipped {
        say!("  {name:<16} skipped: {why}");
    }
    for n in &p.notes {
        say!("  note: {n}");
    }
}

/// Each source's σ on stdout.
fn print_table(s: &Systematics) {
    use systematics::summary::metric::*;
    let nominal = systematics::summary::metrics(&s.outcomes[0]);
    let pct = |m: usize, x: f64| 100.0 * x / nominal[m];
    say!(
        "nominal: flux {:.4e}, central {} {:.4e} ({:.2} %), HPD {:.1}″, 80 % {:.1}″, 90 % {:.1}″, centroid ({:.3}, {:.3}) mm",
        nominal[FLUX],
        traxer::studies::systematics::central_words(s.facts.central_mm, s.facts.central_circle),
        nominal[CENTRAL_FLUX],
        100.0 * nominal[CENTRAL_FLUX] / nominal[FLUX],
        nominal[HPD],
        nominal[D80],
        nominal[D90],
        nominal[CENTROID_X],
        nominal[CENTROID_Y]
    );
    say!("σ by source          flux    central      HPD      80 %      90 %   centroid x, y");
    let row = |name: &str, e: &dyn Fn(usize) -> f64| {
        say!(
            "  {name:<16} {:>6.2} %  {:>6.2} %  {:>6.1}″  {:>6.1}″  {:>6.1}″   {:.3}, {:.3} mm",
            pct(FLUX, e(FLUX)),
            pct(CENTRAL_FLUX, e(CENTRAL_FLUX)),
            e(HPD),
            e(D80),
            e(D90),
            e(CENTROID_X),
            e(CENTROID_Y)
        );
    };
    for src in &s.sources {
        row(&src.name, &|m| src.effects[m].sigma);
    }
    row("total", &|m| s.total_sigma[m]);
    if let Some(r) = s.noise_to_sigma {
        say!(
            "Monte Carlo noise of the σ map (from two halves of the photons): {:.1} % of its σ, √(Σnoise²/Σσ²); map_sigma_noise.npy per pixel",
            100.0 * r
        );
    }
}
