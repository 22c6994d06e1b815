//! `traxer focus`: sweep a scene variable (normally the sensor position), measure
//! the image at each value with the same random numbers, and fit the best focus
//! (`traxer::studies::focus`).

use super::args::{OutputArgs, RunArgs, SceneArgs};
use super::{load_xray_scene, Warnings};
use std::sync::Mutex;
use traxer::output::plotted_diameter;
use traxer::scene::Scene;
use traxer::studies::focus::{FocusScan, FocusStudy, FocusSweep};
use traxer::studies::StudyError;

/// Find the best focus: trace the scene at several sensor positions and fit the
/// image diameters.
///
/// The scene variable --var (default sensor_z) takes --steps values from --from to
/// --to; every position is traced with the same seed, so the photons are the same
/// up to the sensor and the curve is smooth. The HPD, 80 % and 90 % diameters are
/// each fitted with D(z)² = D₀² + k²(z − z₀)²; the HPD's z₀ is the best focus. Writes
/// focus.csv, focus.json and focus.png into --out. Example (PANTER):
///   traxer focus scenes/panter_al_ka.toml --from -1460 --to -1580 --steps 13
#[derive(clap::Args)]
#[command(mut_arg("photons", |a| a.help("Photons per position")))]
pub struct FocusArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Scene variable that places the sensor (declared in [vars]).
    #[arg(value_name = "NAME", long, default_value = "sensor_z")]
    pub var: String,
    /// First value of the variable.
    #[arg(value_name = "VALUE", long, allow_hyphen_values = true)]
    pub from: f64,
    /// Last value of the variable.
    #[arg(value_name = "VALUE", long, allow_hyphen_values = true)]
    pub to: f64,
    /// Number of values (evenly spaced, ends included).
    #[arg(value_name = "N", long, default_value_t = 13)]
    pub steps: usize,
    /// Sensor to measure (default: the scene's only sensor).
    #[arg(value_name = "NAME", long)]
    pub sensor: Option<String>,
    /// Continue the stopped scan whose results folder is --out: run the same
    /// command with --resume; the positions it recorded (focus_checkpoint.jsonl)
    /// are not traced again.
    #[arg(long)]
    pub resume: bool,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

pub fn run(a: FocusArgs) -> anyhow::Result<()> {
    let sweep = FocusSweep {
        var: a.var.clone(),
        from: a.from,
        to: a.to,
        steps: a.steps,
        sensor: a.sensor.clone(),
    };
    sweep.values()?;
    let cfg = a.run.config()?;
    let (device, scene) = load_xray_scene(&a.scene)?;
    let warnings = Mutex::new(Warnings::default());
    warnings.lock().expect("not poisoned").seen(&scene);
    let load = |extra: &[String]| -> Result<Scene, StudyError> {
        let defines = traxer::scene::merged_overrides(&a.scene.vars.define, extra);
        let s = Scene::load(&device, &a.scene.scene, &defines)?;
        warnings.lock().expect("not poisoned").show(&s);
        Ok(s)
    };
    let study = FocusStudy::new(sweep, cfg, &load)?;
    let places = (&a.scene, &a.output);
    let (scan, _) = super::study::run_loaded(&study, (&device, &scene), places, a.resume)?;
    if !scan.clipped.is_empty() {
        tell!(
            "warning: fewer photons reach the sensor at {} = {:?} than elsewhere in the sweep: \
             the image is probably larger than the sensor there (narrow the sweep or enlarge the sensor)",
            a.var, scan.clipped
        );
    }
    print_fits(&a, &scan)
}

/// The best focus and the other fits on stdout; an error if the HPD fit failed.
fn print_fits(a: &FocusArgs, scan: &FocusScan) -> anyhow::Result<()> {
    let out = &a.output.scene_folder(&a.scene, "focus");
    let fits = &scan.fits;
    match &fits[0].1 {
        Ok(f) => {
            let arcsec = |d: f64| {
                scan.focal_length
                    .map(|fl| format!(" ({:.1}″)", plotted_diameter(d, Some(fl))))
                    .unwrap_or_default()
            };
            // The measured position nearest the focus: the fit's D₀ is a
            // parameter of its model, which need not be the image's HPD there.
            let nearest = scan
                .steps
                .iter()
                .filter_map(|s| s.quality.as_ref().map(|q| (s.value, q.hpd_mm)))
                .min_by(|a, b| (a.0 - f.z0).abs().total_cmp(&(b.0 - f.z0).abs()));
            let measured = nearest
                .map(|(z, d)| format!("; measured {d:.4} mm{} at {z:.3}", arcsec(d)))
                .unwrap_or_default();
            let at_focus = if f.d0_resolved {
                format!(
                    "HPD there {:.4} mm{} on the fitted curve{measured}",
                    f.d0,
                    arcsec(f.d0)
                )
            } else {
                // Where the curve is 3× the smallest measured HPD, on each side.
                let half = 3.0 * f.smallest_measured / f.slope;
                format!(
                    "the HPD there is below the smallest measured, {:.4} mm{}, but not resolved: the steps are coarser than the depth of focus (for it: --from {:.3} --to {:.3})",
                    f.smallest_measured,
                    arcsec(f.smallest_measured),
                    f.z0 - half,
                    f.z0 + half
                )
            };
            say!(
                "best focus (HPD fit): {} = {:.3} ± {:.3}; {at_focus}",
                a.var,
                f.z0,
                f.z0_std_error,
            );
            if !a.output.quiet.quiet {
                for (label, fit) in fits.iter().skip(1) {
                    match fit {
                        Ok(f) => say!("  {label} fit: best at {:.3} ± {:.3}", f.z0, f.z0_std_error),
                        Err(e) => say!("  {label} fit: {e}"),
                    }
                }
                say!(
                    "wrote focus.csv, focus.json, focus.png to {}",
                    out.display()
                );
            }
            Ok(())
        }
        Err(e) => Err(anyhow::anyhow!(
            "no best focus: {e} (the measurements are in {})",
            out.display()
        )),
    }
}
