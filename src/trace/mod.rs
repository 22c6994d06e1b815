//! The photon loop and its parallel driver.
//!
//! Data flow: photon indices are cut into fixed chunks; rayon traces chunks in
//! parallel, photon i with the random stream (seed, i) ([`crate::random`]); each
//! chunk returns its sensor records and statistics, and the chunks are merged in
//! index order. The merged images are therefore bit-identical for any thread count.

mod photon;
mod stats;

pub use photon::{trace_photon, Record};
pub use stats::Statistics;

use crate::progress::Progress;
use crate::random::PhotonRng;
use crate::raycast::QueryHook;
use crate::scene::Scene;
use crate::sensor::SensorImage;
use rayon::prelude::*;
use std::time::Instant;

/// Photons per chunk: large enough to amortise scheduling, small enough to balance
/// two cores and keep progress reports coming.
pub const CHUNK: u64 = 4096;
/// Chunks traced between two ordered merges (bounds the memory held in records).
const CHUNKS_PER_BATCH: u64 = 256;

/// How to run (the I/O-side settings; physics lives in the scene).
#[derive(Clone, Debug)]
pub struct RunConfig {
    pub photons: u64,
    pub seed: u64,
    /// Worker threads; 0 = one per core.
    pub threads: usize,
    /// Trace photon indices [first_photon, first_photon + photons): a shard of a
    /// larger run gives exactly its part of that run.
    pub first_photon: u64,
}

impl RunConfig {
    /// `photons` photons of the run with `seed`, from photon 0, on every core.
    pub fn new(photons: u64, seed: u64) -> RunConfig {
        RunConfig {
            photons,
            seed,
            threads: 0,
            first_photon: 0,
        }
    }
}

/// Images and statistics of a finished run.
pub struct RunResult {
    pub images: Vec<SensorImage>,
    pub stats: Statistics,
    pub seconds: f64,
    pub threads: usize,
}

/// Traces `cfg.photons` photons through the scene.
pub fn run(scene: &Scene, cfg: &RunConfig) -> Result<RunResult, rayon::ThreadPoolBuildError> {
    run_with_progress(scene, cfg, &())
}

/// [`run`], telling `progress` of every chunk of photons finished.
pub fn run_with_progress(
    scene: &Scene,
    cfg: &RunConfig,
    progress: &dyn Progress,
) -> Result<RunResult, rayon::ThreadPoolBuildError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(cfg.threads)
        .build()?;
    let threads = pool.current_num_threads();
    let start = Instant::now();
    let mut images: Vec<SensorImage> = scene.sensors.iter().map(SensorImage::new).collect();
    let mut stats = Statistics::new(scene.objects.len(), scene.sensors.len());
    let n_chunks = cfg.photons.div_ceil(CHUNK);
    let mut next = 0;
    while next < n_chunks {
        let end = (next + CHUNKS_PER_BATCH).min(n_chunks);
        let results: Vec<(Vec<Record>, Statistics)> = pool.install(|| {
            (next..end)
                .into_par_iter()
                .map(|c| {
                    let lo = c * CHUNK;
                    let hi = (lo + CHUNK).min(cfg.photons);
                    let r = trace_range(
                        scene,
                        cfg.seed,
                        cfg.first_photon + lo,
                        cfg.first_photon + hi,
                    );
                    progress.advance(hi - lo);
                    r
                })
                .collect()
        });
        for (records, s) in results {
            for r in records {
                images[r.sensor as usize].record(r.pixel, r.weight);
            }
            stats.add(&s);
        }
        next = end;
    }
    Ok(RunResult {
        images,
        stats,
        seconds: start.elapsed().as_secs_f64(),
        threads,
    })
}

/// Traces photons [lo, hi) on this thread.
pub fn trace_range(scene: &Scene, seed: u64, lo: u64, hi: u64) -> (Vec<Record>, Statistics) {
    trace_range_with(scene, seed, lo, hi, &mut ())
}

/// As [`trace_range`], calling `hook` with every Embree query.
pub fn trace_range_with<H: QueryHook>(
    scene: &Scene,
    seed: u64,
    lo: u64,
    hi: u64,
    hook: &mut H,
) -> (Vec<Record>, Statistics) {
    let mut stats = Statistics::new(scene.objects.len(), scene.sensors.len());
    let mut records = Vec::new();
    let n_sources = scene.sources.len() as u64;
    if n_sources == 0 {
        // A scene for visible-light renders only: nothing is emitted.
        return (
            Vec::new(),
            Statistics::new(scene.objects.len(), scene.sensors.len()),
        );
    }
    for i in lo..hi {
        let mut rng = PhotonRng::new(seed, i);
        let photon = scene.sources[(i % n_sources) as usize].emit(&mut rng);
        if let Some(r) = trace_photon(scene, photon, &mut rng, &mut stats, hook) {
            records.push(r);
        }
    }
    (records, stats)
}
