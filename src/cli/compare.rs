//! `traxer compare`: one scene traced with its analytic objects exact and
//! tessellated at several resolutions (and, optionally, other scene files such
//! as one built from exported meshes), with the image quality, the photons
//! reaching the sensor and the speed of each, relative to the analytic run.

use super::measure::{pick_sensor, run_config, trace_and_measure, Measured};
use super::parse_define;
use anyhow::Context;
use serde_json::json;
use std::fmt::Write as _;
use std::path::PathBuf;
use traxer::files::atomic_write;
use traxer::geometry::Resolution;
use traxer::output::write_json;
use traxer::scene::{Representation, Scene};

/// Compare the analytic scene with meshes of it: HPD / 80 % / 90 %, photons on the
/// sensor and photons per second.
///
/// Every analytic object (the LLNL telescope's shells, backs and edges included)
/// is traced exact, then tessellated at each --resolutions entry SEGMENTSxRINGS
/// (mirrors with smooth normals). All runs use the same seed, so differences are
/// not Monte Carlo noise. --also adds other scene files (e.g. one that loads the
/// shipped meshes) as extra rows. Prints a Markdown table; writes compare.csv and
/// compare.json into --out. Example:
///   traxer compare scenes/panter_al_ka.toml --resolutions 8x1,30x1,120x2
#[derive(clap::Args)]
pub struct CompareArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Tessellations to compare, SEGMENTSxRINGS (comma separated).
    #[arg(long, value_delimiter = ',', value_parser = parse_resolution,
          default_value = "4x1,8x1,15x1,30x1,60x2,120x4")]
    pub resolutions: Vec<Resolution>,
    /// Other scene files to trace and compare (repeatable), e.g. a scene built
    /// from exported meshes; they get the same -D overrides.
    #[arg(long)]
    pub also: Vec<PathBuf>,
    /// Sensor to measure (default: the scene's only sensor).
    #[arg(long)]
    pub sensor: Option<String>,
    /// Photons per run.
    #[arg(short = 'n', long, default_value_t = 2_000_000)]
    pub photons: u64,
    /// Random seed (the same for every run).
    #[arg(short, long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (0 = one per core).
    #[arg(short = 'j', long, default_value_t = 0, value_parser = super::parse_threads)]
    pub threads: usize,
    /// Output folder.
    #[arg(short, long, default_value = "out/compare")]
    pub out: PathBuf,
    /// Override a scene variable: -D name=value (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<String>,
    /// Only the table on stdout.
    #[arg(short, long)]
    pub quiet: bool,
}

fn parse_resolution(s: &str) -> Result<Resolution, String> {
    let bad = || format!("expected SEGMENTSxRINGS with positive integers, e.g. 120x4, got `{s}`");
    let (a, b) = s.trim().split_once(['x', 'X']).ok_or_else(bad)?;
    let segments: usize = a.trim().parse().map_err(|_| bad())?;
    let rings: usize = b.trim().parse().map_err(|_| bad())?;
    if segments == 0 || rings == 0 {
        return Err(bad());
    }
    Ok(Resolution { segments, rings })
}

struct Row {
    label: String,
    triangles: usize,
    m: Measured,
}

pub fn run(a: CompareArgs) -> anyhow::Result<()> {
    let cfg = run_config(a.photons, a.seed, a.threads)?;
    let device = traxer::embree::Device::new()?;
    let mut runs: Vec<(String, PathBuf, Representation)> =
        vec![("analytic".into(), a.scene.clone(), Representation::Analytic)];
    for r in &a.resolutions {
        runs.push((
            format!("mesh {}x{}", r.segments, r.rings),
            a.scene.clone(),
            Representation::Tessellated(*r),
        ));
    }
    for f in &a.also {
        runs.push((
            f.display().to_string(),
            f.clone(),
            Representation::AsWritten,
        ));
    }
    let mut rows = Vec::new();
    for (label, path, repr) in runs {
        let scene = Scene::load_as(&device, &path, &a.define, repr)?;
        if scene.sources.is_empty() {
            return Err(super::InputError(format!(
                "{}: the scene has no [[sources]]: nothing to compare",
                path.display()
            ))
            .into());
        }
        let sensor = pick_sensor(&scene, a.sensor.as_deref())?;
        let m = trace_and_measure(&scene, sensor, &cfg)?;
        if !a.quiet {
            eprintln!(
                "{label}: {} triangles, {:.2} s, HPD {}",
                scene.triangle_count,
                m.seconds,
                m.quality
                    .as_ref()
                    .map_or("-".into(), |q| format!("{:.4} mm", q.hpd_mm))
            );
        }
        rows.push(Row {
            label,
            triangles: scene.triangle_count,
            m,
        });
    }

    let reference = &rows[0];
    let Some(q0) = reference.m.quality.clone() else {
        return Err(anyhow::anyhow!(
            "no photon reached the sensor in the analytic run: nothing to compare"
        ));
    };
    // Diameters in arcseconds when the sensor knows its focal length, else mm.
    let arcsec = q0.hpd_arcsec.is_some();
    let unit = if arcsec { "″" } else { " mm" };
    let pick = |q: &traxer::analysis::ImageQuality| -> [f64; 3] {
        if arcsec {
            [
                q.hpd_arcsec.unwrap_or(f64::NAN),
                q.d80_arcsec.unwrap_or(f64::NAN),
                q.d90_arcsec.unwrap_or(f64::NAN),
            ]
        } else {
            [q.hpd_mm, q.d80_mm, q.d90_mm]
        }
    };
    let d0 = pick(&q0);
    let pct = |x: f64, x0: f64| 100.0 * (x / x0 - 1.0);
    let mut md = String::from(
        "| representation | triangles | HPD | ΔHPD | 80 % | Δ80 | 90 % | Δ90 | on sensor | Δ on sensor | photons/s | time vs analytic |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut csv = String::from("representation,triangles,hpd,d80,d90,diameter_unit,hpd_diff_pct,d80_diff_pct,d90_diff_pct,on_sensor,on_sensor_diff_pct,photons_per_s,seconds\n");
    let mut json_rows = Vec::new();
    for r in &rows {
        let d = r.m.quality.as_ref().map_or([f64::NAN; 3], pick);
        let diff = [pct(d[0], d0[0]), pct(d[1], d0[1]), pct(d[2], d0[2])];
        let on = pct(r.m.on_sensor as f64, reference.m.on_sensor as f64);
        let time = r.m.seconds / reference.m.seconds;
        let _ = writeln!(
            md,
            "| {} | {} | {:.1}{unit} | {:+.2} % | {:.1}{unit} | {:+.2} % | {:.1}{unit} | {:+.2} % | {} | {:+.2} % | {:.2} M | {:.2} |",
            r.label,
            r.triangles,
            d[0],
            diff[0],
            d[1],
            diff[1],
            d[2],
            diff[2],
            r.m.on_sensor,
            on,
            r.m.photons_per_second() / 1e6,
            time
        );
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.label,
            r.triangles,
            d[0],
            d[1],
            d[2],
            if arcsec { "arcsec" } else { "mm" },
            diff[0],
            diff[1],
            diff[2],
            r.m.on_sensor,
            on,
            r.m.photons_per_second(),
            r.m.seconds
        );
        json_rows.push(json!({
            "representation": r.label,
            "triangles": r.triangles,
            "image_quality": r.m.quality,
            "diameter_diff_pct": { "hpd": diff[0], "d80": diff[1], "d90": diff[2] },
            "photons_on_sensor": r.m.on_sensor,
            "photons_on_sensor_diff_pct": on,
            "photons_per_s": r.m.photons_per_second(),
            "trace_seconds": r.m.seconds,
        }));
    }
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    atomic_write(&a.out.join("compare.csv"), csv.as_bytes())?;
    write_json(
        &a.out.join("compare.json"),
        &json!({
            "scene": a.scene.display().to_string(),
            "overrides": a.define,
            "photons": a.photons,
            "seed": a.seed,
            "threads": a.threads,
            "rows": json_rows,
        }),
    )?;
    say!("{}", md.trim_end());
    if !a.quiet {
        say!(
            "{} photons per run, seed {}; Δ relative to the analytic run; wrote compare.csv and compare.json to {}",
            a.photons,
            a.seed,
            a.out.display()
        );
    }
    Ok(())
}
