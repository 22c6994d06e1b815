//! `traxer focus`: sweep a scene variable (normally the sensor position), measure
//! the image at each value with the same random numbers, and fit the best focus.

use super::measure::{pick_sensor, run_config, trace_and_measure};
use super::{load_xray_scene, parse_define, InputError};
use anyhow::Context;
use serde_json::json;
use std::fmt::Write as _;
use std::path::PathBuf;
use traxer::analysis::focus::{fit_defocus, DefocusFit};
use traxer::analysis::ImageQuality;
use traxer::files::atomic_write;
use traxer::output::{line_plot, write_json, Series};

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
pub struct FocusArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Scene variable that places the sensor (declared in [vars]).
    #[arg(long, default_value = "sensor_z")]
    pub var: String,
    /// First value of the variable.
    #[arg(long, allow_hyphen_values = true)]
    pub from: f64,
    /// Last value of the variable.
    #[arg(long, allow_hyphen_values = true)]
    pub to: f64,
    /// Number of values (evenly spaced, ends included).
    #[arg(long, default_value_t = 13)]
    pub steps: usize,
    /// Sensor to measure (default: the scene's only sensor).
    #[arg(long)]
    pub sensor: Option<String>,
    /// Photons per position.
    #[arg(short = 'n', long, default_value_t = 1_000_000)]
    pub photons: u64,
    /// Random seed (the same for every position).
    #[arg(short, long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (0 = one per core).
    #[arg(short = 'j', long, default_value_t = 0, value_parser = super::parse_threads)]
    pub threads: usize,
    /// Output folder.
    #[arg(short, long, default_value = "out/focus")]
    pub out: PathBuf,
    /// Override another scene variable: -D name=value (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<String>,
    /// Only the result line on stdout.
    #[arg(short, long)]
    pub quiet: bool,
}

struct Step {
    value: f64,
    quality: Option<ImageQuality>,
    on_sensor: u64,
}

pub fn run(a: FocusArgs) -> anyhow::Result<()> {
    if a.steps < 4 {
        return Err(InputError("--steps must be at least 4 to fit a focus curve".into()).into());
    }
    if !a.from.is_finite() || !a.to.is_finite() || a.from == a.to {
        return Err(InputError("--from and --to must be two different numbers".into()).into());
    }
    let cfg = run_config(a.photons, a.seed, a.threads)?;
    let mut steps = Vec::with_capacity(a.steps);
    let mut focal_length = None;
    let mut sensor_name = String::new();
    for i in 0..a.steps {
        let value = a.from + (a.to - a.from) * i as f64 / (a.steps - 1) as f64;
        let mut defines = a.define.clone();
        defines.push(format!("{}={value}", a.var));
        let (_device, scene) = load_xray_scene(&a.scene, &defines)?;
        let sensor = pick_sensor(&scene, a.sensor.as_deref())?;
        focal_length = scene.sensors[sensor].focal_length;
        sensor_name.clone_from(&scene.sensors[sensor].name);
        let m = trace_and_measure(&scene, sensor, &cfg)?;
        if !a.quiet {
            let q = m.quality.as_ref();
            say!(
                "{} = {value:>10.3}: HPD {:>8.4} mm, 80 % {:>8.4} mm, 90 % {:>8.4} mm ({} photons on {})",
                a.var,
                q.map_or(f64::NAN, |q| q.hpd_mm),
                q.map_or(f64::NAN, |q| q.d80_mm),
                q.map_or(f64::NAN, |q| q.d90_mm),
                m.on_sensor,
                sensor_name
            );
        }
        steps.push(Step {
            value,
            quality: m.quality,
            on_sensor: m.on_sensor,
        });
    }

    let series = |f: fn(&ImageQuality) -> f64| -> Vec<(f64, f64)> {
        steps
            .iter()
            .filter_map(|s| s.quality.as_ref().map(|q| (s.value, f(q))))
            .collect()
    };
    let measured = [
        ("HPD", series(|q| q.hpd_mm)),
        ("80 %", series(|q| q.d80_mm)),
        ("90 %", series(|q| q.d90_mm)),
    ];
    let fits: Vec<Result<DefocusFit, String>> =
        measured.iter().map(|(_, pts)| fit_defocus(pts)).collect();

    // A sensor too small for the defocused image cuts off its outer rings and
    // makes the diameters there meaningless.
    let most = steps.iter().map(|s| s.on_sensor).max().unwrap_or(0);
    let clipped: Vec<f64> = steps
        .iter()
        .filter(|s| (s.on_sensor as f64) < 0.995 * most as f64)
        .map(|s| s.value)
        .collect();
    if !clipped.is_empty() {
        eprintln!(
            "warning: fewer photons reach the sensor at {} = {clipped:?} than elsewhere in the sweep: \
             the image is probably larger than the sensor there (narrow the sweep or enlarge the sensor)",
            a.var
        );
    }
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let mut csv = format!("{},hpd_mm,d80_mm,d90_mm,photons_on_sensor\n", a.var);
    for s in &steps {
        let q = s.quality.as_ref();
        let _ = writeln!(
            csv,
            "{},{},{},{},{}",
            s.value,
            q.map_or(f64::NAN, |q| q.hpd_mm),
            q.map_or(f64::NAN, |q| q.d80_mm),
            q.map_or(f64::NAN, |q| q.d90_mm),
            s.on_sensor
        );
    }
    atomic_write(&a.out.join("focus.csv"), csv.as_bytes())?;
    let fit_json = |f: &Result<DefocusFit, String>| match f {
        Ok(f) => json!(f),
        Err(e) => json!({ "error": e }),
    };
    write_json(
        &a.out.join("focus.json"),
        &json!({
            "scene": a.scene.display().to_string(),
            "variable": a.var,
            "overrides": a.define,
            "sensor": sensor_name,
            "photons_per_position": a.photons,
            "seed": a.seed,
            "clipped_positions": clipped,
            "model": "D(z)^2 = d0^2 + slope^2 (z - z0)^2, weighted least squares on D^2 with weights 1/D^2; diameters in mm",
            "fit_hpd": fit_json(&fits[0]),
            "fit_d80": fit_json(&fits[1]),
            "fit_d90": fit_json(&fits[2]),
        }),
    )?;
    // Plot in arcseconds when the sensor knows its focal length.
    let to_unit = |d: f64| match focal_length {
        Some(f) => 2.0 * (0.5 * d / f).atan().to_degrees() * 3600.0,
        None => d,
    };
    let mut plot = Vec::new();
    for (k, ((label, pts), fit)) in measured.iter().zip(&fits).enumerate() {
        plot.push(
            Series::dots(
                format!("{label} measured"),
                pts.iter().map(|&(z, d)| (z, to_unit(d))).collect(),
            )
            .with_color(k),
        );
        if let Ok(f) = fit {
            let curve = (0..=200)
                .map(|k| {
                    let z = a.from + (a.to - a.from) * k as f64 / 200.0;
                    (z, to_unit(f.diameter_at(z)))
                })
                .collect();
            plot.push(
                Series::line(format!("{label} fit: best at {:.2}", f.z0), curve).with_color(k),
            );
        }
    }
    let png = a.out.join("focus.png");
    line_plot(
        &png,
        &format!("focus sweep: {}", a.scene.display()),
        &a.var,
        if focal_length.is_some() {
            "diameter (arcsec)"
        } else {
            "diameter (mm)"
        },
        &plot,
        (900, 600),
    )?;

    match &fits[0] {
        Ok(f) => {
            say!(
                "best focus (HPD fit): {} = {:.3} ± {:.3}; HPD there {:.4} mm{}",
                a.var,
                f.z0,
                f.z0_std_error,
                f.d0,
                focal_length
                    .map(|_| format!(" ({:.1}″)", to_unit(f.d0)))
                    .unwrap_or_default()
            );
            if !a.quiet {
                for ((label, _), fit) in measured.iter().zip(&fits).skip(1) {
                    match fit {
                        Ok(f) => say!("  {label} fit: best at {:.3} ± {:.3}", f.z0, f.z0_std_error),
                        Err(e) => say!("  {label} fit: {e}"),
                    }
                }
                say!(
                    "wrote focus.csv, focus.json, focus.png to {}",
                    a.out.display()
                );
            }
            Ok(())
        }
        Err(e) => Err(anyhow::anyhow!(
            "no best focus: {e} (the measurements are in {})",
            a.out.display()
        )),
    }
}
