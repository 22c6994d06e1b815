//! `traxer trace`: run a scene and write the sensor images and summary.

use super::args::{OutputArgs, RunArgs, SceneArgs};
use super::{load_xray_scene, progress, InputError};
use anyhow::Context;
use traxer::analysis::{analyse, ImageGeometry};
use traxer::files::OutputFolder;
use traxer::output::{write_run, Provenance};
use traxer::trace::{self, RunResult};

/// Trace photons through a scene and write every sensor's image.
///
/// Writes into --out, per sensor object NAME: NAME.npy (flux = sum of weights, f64,
/// shape [ny, nx], or [bands, ny, nx] with energy bins), NAME_counts.npy (photons
/// per pixel), NAME.png and NAME_log.png (viridis), NAME_eef.png (encircled energy
/// with the 50/80/90 % diameters), NAME_projections.csv (x and y profiles),
/// NAME.json (provenance, sensor geometry, image quality, statistics); and
/// summary.json for the whole run. The same seed gives bit-identical images for any
/// --threads.
#[derive(clap::Args)]
pub struct TraceArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub output: OutputArgs,
    /// First photon index: trace photons [first, first + photons) of a larger run
    /// (for splitting one run into shards on a cluster).
    #[arg(value_name = "K", long, default_value_t = 0)]
    pub first_photon: u64,
    /// Also write photons.npy (a NumPy structured array) and photons.csv: the first
    /// N photons recorded on any sensor, with position, direction, energy, weight
    /// and history (reflections, first and last mirror, path class).
    #[arg(value_name = "N", long, default_value_t = 0)]
    pub photon_list: usize,
}

pub fn run(a: TraceArgs) -> anyhow::Result<()> {
    let mut cfg = a.run.config()?;
    if a.first_photon.checked_add(cfg.photons).is_none() {
        return Err(InputError(format!(
            "--first-photon {} + --photons {} runs past the last photon index (2^64 - 1)",
            a.first_photon, cfg.photons
        ))
        .into());
    }
    cfg.first_photon = a.first_photon;
    // About 100 bytes each in memory: a list is for looking at photons, not all.
    const MAX_LIST: usize = 20_000_000;
    if a.photon_list > MAX_LIST {
        return Err(InputError(format!(
            "--photon-list {}: at most {MAX_LIST} photons are listed",
            a.photon_list
        ))
        .into());
    }
    cfg.photon_list = a.photon_list;
    let (device, scene) = load_xray_scene(&a.scene)?;
    let names = traxer::output::run_file_names(&scene, a.photon_list > 0);
    let folder = OutputFolder::prepare(&a.output.out, &names)?;
    if scene.sensors.is_empty() {
        tell!("warning: the scene has no sensor; only statistics will be written");
    }
    let quiet = a.output.quiet.quiet;
    let bar = progress::bar(cfg.photons, "photons", quiet);
    let result = trace::run_with_progress(&scene, &cfg, &|n| bar.inc(n))
        .context("cannot start the worker threads")?;
    bar.finish_and_clear();
    let provenance = Provenance::new(Some(device.info().version))
        .scene(&scene)
        .run(&cfg, result.threads);
    let out = &a.output.out;
    let files = write_run(folder.path(), &scene, &result, &provenance)
        .and_then(|files| folder.commit().map(|_| files))
        .with_context(|| format!("cannot write the results into {}", out.display()))?;
    if !quiet {
        report(&scene, &result);
        say!("wrote {} files to {}", files.len(), out.display());
    }
    Ok(())
}

/// The run's statistics and each sensor's image quality on stdout.
fn report(scene: &traxer::scene::Scene, result: &RunResult) {
    let s = &result.stats;
    say!(
        "traced {} photons in {:.2} s with {} threads ({:.0} photons/s)",
        s.photons_emitted,
        result.seconds,
        result.threads,
        s.photons_emitted as f64 / result.seconds
    );
    say!(
        "  reached a sensor {} ({:.2} %), absorbed {}, mirror backs {}, below surface (figure error) {}, escaped {}, outside sensor area {}, max interactions {}",
        s.reached_sensor,
        100.0 * s.reached_sensor as f64 / s.photons_emitted as f64,
        s.absorbed, s.absorbed_mirror_back, s.scattered_below_surface, s.escaped, s.sensor_outside_area, s.max_interactions_reached
    );
    for (spec, img) in scene.sensors.iter().zip(&result.images) {
        match scene.rate_per_unit_weight(s.photons_emitted) {
            Some(k) => say!(
                "  sensor {}: {} photons, {:.4e} axions/s",
                spec.name,
                img.total_counts(),
                img.total_flux() * k
            ),
            None => say!(
                "  sensor {}: {} photons, flux {:.6e}",
                spec.name,
                img.total_counts(),
                img.total_flux()
            ),
        }
        let g = ImageGeometry::of_sensor(spec);
        if let Some((q, _)) = analyse(&img.flux_summed(spec), &g, spec.focal_length) {
            let arc = |a: Option<f64>| a.map(|v| format!(" ({v:.1}″)")).unwrap_or_default();
            say!(
                "    centroid ({:.4}, {:.4}) mm; HPD {:.4} mm{}, 80 % {:.4} mm{}, 90 % {:.4} mm{}",
                q.centroid_mm[0],
                q.centroid_mm[1],
                q.hpd_mm,
                arc(q.hpd_arcsec),
                q.d80_mm,
                arc(q.d80_arcsec),
                q.d90_mm,
                arc(q.d90_arcsec)
            );
        }
    }
}
