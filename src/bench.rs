//! Throughput measurement: photons per second through a scene, and the raw Embree
//! `rtcIntersect1` rate on the very rays that run asked for, so the ratio shows how
//! much of the time is traxer's own work rather than Embree's.
//!
//! Data flow: used by `traxer bench` and `cargo bench`; reads a built `Scene`.

use crate::embree::Query;
use crate::progress::Progress;
use crate::raycast::QueryHook;
use crate::scene::Scene;
use crate::trace::{self, RunConfig};
use rayon::prelude::*;
use std::time::Instant;

#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchReport {
    pub photons: u64,
    pub threads: usize,
    pub seconds: f64,
    pub photons_per_second: f64,
    pub sensor_photons_per_second: f64,
    pub queries_per_photon: f64,
    pub raw_rays: usize,
    pub raw_rays_per_second: f64,
    /// photons/s × queries/photon ÷ raw rays/s: 1 means no time outside Embree.
    pub embree_fraction: f64,
    pub triangles: usize,
}

struct Recorder(Vec<([f32; 3], [f32; 3])>);

impl QueryHook for Recorder {
    fn query(&mut self, q: &Query) {
        let f = |v: [f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32];
        self.0.push((f(q.origin), f(q.dir)));
    }
}

/// Traces the run `cfg` asks for, then replays the queries of its first
/// `raw_photons` photons through plain `rtcIntersect1` on as many threads.
/// `progress` hears of the timed run's photons.
pub fn run(
    scene: &Scene,
    cfg: &RunConfig,
    raw_photons: u64,
    progress: &dyn Progress,
) -> Result<BenchReport, rayon::ThreadPoolBuildError> {
    let (photons, threads) = (cfg.photons, cfg.threads);
    // Warm-up (page faults, lazy Embree initialisation).
    trace::trace_range(scene, 7, 0, 20_000.min(photons));
    let r = trace::run_with_progress(scene, cfg, progress)?;

    let mut rec = Recorder(Vec::new());
    let first = cfg.first_photon;
    let replayed = raw_photons.min(photons);
    trace::trace_range_with(scene, cfg.seed, first, first + replayed, &mut rec);
    let rays = rec.0;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let raw = |_| -> usize {
        rays.par_chunks(4096)
            .map(|c| scene.embree.intersect_raw(c))
            .sum()
    };
    pool.install(|| raw(())); // warm-up
    let t = Instant::now();
    let mut rounds = 0;
    while rounds < 3 || t.elapsed().as_secs_f64() < 1.0 {
        pool.install(|| raw(()));
        rounds += 1;
    }
    let raw_rate = (rays.len() * rounds) as f64 / t.elapsed().as_secs_f64();
    let pps = r.stats.photons_emitted as f64 / r.seconds;
    let qpp = r.stats.embree_queries as f64 / r.stats.photons_emitted as f64;
    Ok(BenchReport {
        photons,
        threads: r.threads,
        seconds: r.seconds,
        photons_per_second: pps,
        sensor_photons_per_second: r.stats.reached_sensor as f64 / r.seconds,
        queries_per_photon: qpp,
        raw_rays: rays.len(),
        raw_rays_per_second: raw_rate,
        embree_fraction: pps * qpp / raw_rate,
        triangles: scene.triangle_count,
    })
}

/// Reflectivity evaluations per second of one coating on one thread: direct
/// (optical constants + Parratt recursion) and through a table (as the photon loop
/// does), on random energies in [e_min, e_max] and angles in 0–3°.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ReflectivityRates {
    pub coating: String,
    pub direct_per_second: f64,
    pub table_per_second: f64,
    pub table_build_seconds: f64,
    pub table_nodes: usize,
}

pub fn reflectivity_rates(
    coating: &crate::xray::Coating,
    e_min: f64,
    e_max: f64,
) -> ReflectivityRates {
    let t0 = Instant::now();
    let table = crate::xray::ReflectivityTable::new(coating, e_min, e_max, 5f64.to_radians())
        .expect("energies in range");
    let build = t0.elapsed().as_secs_f64();
    let mut rng = crate::random::PhotonRng::new(5, 0);
    let points: Vec<(f64, f64)> = (0..200_000)
        .map(|_| {
            (
                e_min + (e_max - e_min) * rng.uniform(),
                3f64.to_radians() * rng.uniform(),
            )
        })
        .collect();
    let t = Instant::now();
    let mut sum = 0.0;
    for &(e, th) in &points[..20_000] {
        sum += coating.reflectivity(e, th).unwrap_or(0.0);
    }
    let direct = 20_000.0 / t.elapsed().as_secs_f64();
    let t = Instant::now();
    for &(e, th) in &points {
        sum += table.reflectivity(e, th);
    }
    let tabled = points.len() as f64 / t.elapsed().as_secs_f64();
    std::hint::black_box(sum);
    ReflectivityRates {
        coating: coating.name.clone(),
        direct_per_second: direct,
        table_per_second: tabled,
        table_build_seconds: build,
        table_nodes: table.len(),
    }
}
