//! `traxer trace`: run a scene and write the sensor images and summary.

use super::{load_xray_scene, parse_define};
use anyhow::Context;
use std::path::PathBuf;
use traxer::output::{git_hash, write_run, Provenance};
use traxer::trace::{self, RunConfig};

/// Trace photons through a scene and write every sensor's image.
///
/// Writes into --out, per sensor object NAME: NAME.npy (flux = sum of weights, f64,
/// shape [ny, nx]), NAME_counts.npy, NAME.png and NAME_log.png (viridis), NAME.json
/// (provenance, sensor geometry, statistics); and summary.json for the whole run.
/// The same seed gives bit-identical images for any --threads.
#[derive(clap::Args)]
pub struct TraceArgs {
    /// Scene file (TOML); see docs/scene-format.md.
    pub scene: PathBuf,
    /// Number of photons to emit.
    #[arg(short = 'n', long, default_value_t = 1_000_000)]
    pub photons: u64,
    /// Random seed; photon i uses the stream derived from (seed, i).
    #[arg(short, long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (0 = one per core).
    #[arg(short = 'j', long, default_value_t = 0, value_parser = super::parse_threads)]
    pub threads: usize,
    /// Output folder (created if missing).
    #[arg(short, long, default_value = "out")]
    pub out: PathBuf,
    /// Override a scene variable declared in [vars]: -D name=value (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<String>,
    /// First photon index: trace photons [first, first + photons) of a larger run
    /// (for splitting one run into shards on a cluster).
    #[arg(long, default_value_t = 0)]
    pub first_photon: u64,
    /// No progress bar and no summary on stdout.
    #[arg(short, long)]
    pub quiet: bool,
}

pub fn run(a: TraceArgs) -> anyhow::Result<()> {
    if a.photons == 0 {
        return Err(super::InputError("--photons must be at least 1".into()).into());
    }
    if a.first_photon.checked_add(a.photons).is_none() {
        return Err(super::InputError(format!(
            "--first-photon {} + --photons {} runs past the last photon index (2^64 - 1)",
            a.first_photon, a.photons
        ))
        .into());
    }
    let (device, scene) = load_xray_scene(&a.scene, &a.define)?;
    if scene.sensors.is_empty() {
        eprintln!("warning: the scene has no sensor; only statistics will be written");
    }
    let cfg = RunConfig {
        photons: a.photons,
        seed: a.seed,
        threads: a.threads,
        first_photon: a.first_photon,
    };
    let bar = super::progress::bar(a.photons, "photons", a.quiet);
    let result = trace::run_with_progress(&scene, &cfg, &|n| bar.inc(n))
        .context("cannot start the worker threads")?;
    bar.finish_and_clear();
    let provenance = Provenance {
        traxer_version: env!("CARGO_PKG_VERSION").into(),
        git_hash: git_hash().into(),
        embree_version: device.info().version,
        scene_path: a.scene.display().to_string(),
        scene_sha256: scene.text_sha256.clone(),
        overrides: a.define.clone(),
        seed: a.seed,
        photons: a.photons,
        threads: result.threads,
        first_photon: a.first_photon,
        command_line: std::env::args().collect(),
        finished_unix_s: std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_secs())
            .unwrap_or(0),
    };
    let files = write_run(&a.out, &scene, &result, &provenance)
        .with_context(|| format!("cannot write the results into {}", a.out.display()))?;
    if !a.quiet {
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
            say!(
                "  sensor {}: {} photons, flux {:.6e}",
                spec.name,
                img.total_counts(),
                img.total_flux()
            );
            let g = traxer::analysis::ImageGeometry::of_sensor(spec);
            if let Some((q, _)) =
                traxer::analysis::analyse(&img.flux_summed(spec), &g, spec.focal_length)
            {
                let arc = |a: Option<f64>| a.map(|v| format!(" ({v:.1}″)")).unwrap_or_default();
                say!(
                    "    centroid ({:.4}, {:.4}) mm; HPD {:.4} mm{}, 80 % {:.4} mm{}, 90 % {:.4} mm{}",
                    q.centroid_mm[0], q.centroid_mm[1],
                    q.hpd_mm, arc(q.hpd_arcsec), q.d80_mm, arc(q.d80_arcsec), q.d90_mm, arc(q.d90_arcsec)
                );
            }
        }
        say!("wrote {} files to {}", files.len(), a.out.display());
    }
    Ok(())
}
