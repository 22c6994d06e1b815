//! `traxer bench`: photons per second, and raw Embree rays per second on the same
//! rays.

use super::{load_xray_scene, parse_define};
use std::path::PathBuf;

/// Measure tracing speed on a scene and compare it with raw Embree queries.
///
/// Prints photons/s, photons reaching a sensor per second, Embree queries per
/// photon, the raw rtcIntersect1 rate on the very rays of the run, and the share of
/// the run spent inside Embree.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// Scene file to trace.
    pub scene: PathBuf,
    /// Photons for the timed run.
    #[arg(short = 'n', long, default_value_t = 2_000_000)]
    pub photons: u64,
    /// Worker threads (0 = one per core).
    #[arg(short = 'j', long, default_value_t = 0, value_parser = super::parse_threads)]
    pub threads: usize,
    /// Photons whose queries are replayed for the raw Embree rate.
    #[arg(long, default_value_t = 300_000)]
    pub raw_photons: u64,
    /// Override a scene variable: -D name=value.
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<String>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: BenchArgs) -> anyhow::Result<()> {
    if a.photons == 0 {
        return Err(super::InputError("--photons must be at least 1".into()).into());
    }
    let (_device, scene) = load_xray_scene(&a.scene, &a.define)?;
    let r = traxer::bench::run(&scene, a.photons, a.threads, a.raw_photons)?;
    if a.json {
        say!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        say!(
            "scene {} ({} triangles), {} threads",
            a.scene.display(),
            r.triangles,
            r.threads
        );
        say!(
            "  traced           {:>12.0} photons/s ({} photons in {:.2} s)",
            r.photons_per_second,
            r.photons,
            r.seconds
        );
        say!(
            "  reaching sensor  {:>12.0} photons/s",
            r.sensor_photons_per_second
        );
        say!(
            "  Embree queries   {:>12.3} per photon",
            r.queries_per_photon
        );
        say!(
            "  raw rtcIntersect1{:>12.0} rays/s (same {} rays, no traxer work)",
            r.raw_rays_per_second,
            r.raw_rays
        );
        say!(
            "  photons/s × queries/photon ÷ raw rays/s = {:.2}",
            r.embree_fraction
        );
    }
    Ok(())
}
