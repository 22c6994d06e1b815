//! The PANTER pictures: for each line (Al, Ti, Fe Kα) the sensor image (linear
//! and log) and the encircled energy, perfect mirrors against the fitted figure
//! errors (preset `llnl_panter`, data/figure_errors.toml), side by side, and one
//! plot of the encircled-energy curves of all six runs.
//!
//!     cargo run --release --example panter_pictures [PHOTONS]
//!
//! writes every run into out/panter_pictures/<line>_<variant>/ (the files of
//! `traxer trace`) and the comparisons into docs/img/panter_<line>_figure_error.png
//! and docs/img/panter_eef.png. Default 4 000 000 photons per run.

use std::path::Path;
use traxer::analysis::{analyse, ImageGeometry};
use traxer::output::{line_plot, write_montage, write_run, Provenance, Series, Tile};
use traxer::trace::RunConfig;

fn main() -> anyhow::Result<()> {
    let invocation = traxer::run::Invocation::new(std::env::args());
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let photons: u64 = match std::env::args().nth(1) {
        Some(s) => s.parse()?,
        None => 4_000_000,
    };
    let device = traxer::embree::Device::new()?;
    let out = root.join("out/panter_pictures");
    let mut eef_series = Vec::new();
    for (line, label) in [("al", "Al Kα"), ("ti", "Ti Kα"), ("fe", "Fe Kα")] {
        let scene_path = root.join(format!("scenes/panter_{line}_ka.toml"));
        let mut tiles = Vec::new();
        let mut dirs = Vec::new();
        for (variant, preset) in [("perfect", "none"), ("figure_error", "llnl_panter")] {
            let defines = vec![format!("figure_error={preset}")];
            let scene = traxer::scene::Scene::load(&device, &scene_path, &defines)?;
            let cfg = RunConfig::new(photons, 1);
            let result = traxer::trace::run(&scene, &cfg)?;
            let dir = out.join(format!("{line}_{variant}"));
            std::fs::create_dir_all(&dir)?;
            let provenance = Provenance::of_study(
                &invocation,
                device.info().version,
                &scene,
                (photons, 1),
                result.threads,
            );
            write_run(&dir, &scene, &result, &provenance, None)?;
            let spec = &scene.sensors[0];
            let (q, eef) = analyse(
                &result.images[0].flux_summed(spec),
                &ImageGeometry::of_sensor(spec),
                spec.focal_length,
            )
            .ok_or_else(|| anyhow::anyhow!("{line} {variant}: no image"))?;
            let arcsec = |d: Option<f64>| d.unwrap_or(f64::NAN);
            println!(
                "{label:6} {variant:13} HPD {:6.1}″  80 % {:6.1}″  90 % {:6.1}″  ({} photons on the sensor)",
                arcsec(q.hpd_arcsec),
                arcsec(q.d80_arcsec),
                arcsec(q.d90_arcsec),
                result.images[0].total_counts()
            );
            let f = spec.focal_length.unwrap_or(1500.0);
            eef_series.push(Series::line(
                format!("{label}, {}", variant.replace('_', " ")),
                eef.radius_mm
                    .iter()
                    .zip(&eef.fraction)
                    .step_by((eef.radius_mm.len() / 400).max(1))
                    .map(|(&r, &fr)| (2.0 * (r / f).atan().to_degrees() * 3600.0, fr))
                    .collect(),
            ));
            let caption = match variant {
                "perfect" => "perfect figure",
                _ => "figure errors",
            };
            dirs.push((dir, caption, q));
        }
        for (dir, caption, q) in &dirs {
            let hpd = q.hpd_arcsec.unwrap_or(f64::NAN);
            for (file, what) in [
                ("sensor.png", "linear"),
                ("sensor_log.png", "log"),
                ("sensor_eef.png", "EEF"),
            ] {
                tiles.push((
                    format!("{label}, {caption}, {what}: HPD {hpd:.0}″"),
                    dir.join(file),
                ));
            }
        }
        let tiles: Vec<Tile> = tiles
            .iter()
            .map(|(c, p)| Tile {
                caption: c.clone(),
                png: p,
            })
            .collect();
        let png = root.join(format!("docs/img/panter_{line}_figure_error.png"));
        write_montage(&png, &tiles, 3, 420, 300)?;
        println!("wrote {}", png.display());
    }
    // Whole curves: the images are 14 mm ≈ 1925″ wide; show out to 1000″.
    for s in &mut eef_series {
        s.points.retain(|p| p.0 <= 1000.0);
    }
    let png = root.join("docs/img/panter_eef.png");
    line_plot(
        &png,
        "PANTER: encircled energy, perfect vs figure-error mirrors",
        "diameter around the centroid [arcsec] (the EEF against 2r)",
        "fraction of flux",
        &eef_series,
        (900, 600),
    )?;
    println!("wrote {}", png.display());
    Ok(())
}
