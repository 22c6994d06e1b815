//! Throughput measurement: photons per second through a scene, and the raw Embree
//! `rtcIntersect1` rate on the very rays that run asked for, so the ratio shows how
//! much of the time is traxer's own work rather than Embree's; the best rate
//! Embree reaches on the same rays when they come sorted (coherent rays share
//! BVH nodes in the cache); the time to build the BVH of a large mesh; the
//! process's peak memory (resident set) while a scene is loaded and traced.
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
    /// The fastest `rtcIntersect1` rate on the same rays in the orders tried
    /// ([`RayOrder`]), and that order.
    pub best_raw_rays_per_second: f64,
    pub best_order: RayOrder,
    pub triangles: usize,
    /// Seconds Embree took to build the scene's BVH.
    pub bvh_seconds: f64,
    /// The process's peak resident memory (MB, 10⁶ bytes) from loading the
    /// scene (when the caller has called [`reset_peak_rss`] before) to the end
    /// of the trace, before the raw rays are recorded ([`peak_rss_mb`]); where
    /// the system reports it (Linux).
    pub peak_rss_mb: Option<f64>,
    /// For a scene with nested shells, the same rays answered by the
    /// nested-shell search beside Embree for the rest.
    pub nested_shells: Option<NestedShellRates>,
}

/// The rays of a run answered two ways on the same threads: Embree on the whole
/// scene, and [`NestedShells`] for the shells plus Embree on everything else
/// (spider, sensor, CAD parts).
#[derive(Clone, Debug, serde::Serialize)]
pub struct NestedShellRates {
    pub shells: usize,
    pub embree_rays_per_second: f64,
    pub nested_rays_per_second: f64,
    /// Rays whose nearest object and distance (to 1e-9 relative) agree.
    pub agreeing_fraction: f64,
}

/// Starts a new peak-memory measurement: the kernel's high-water mark of the
/// resident set is set back to the current resident set (Linux ≥ 4.0:
/// writing 5 to /proc/self/clear_refs). Without it the peak is since the
/// process started.
pub fn reset_peak_rss() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// The process's peak resident set since it started or since
/// [`reset_peak_rss`] (MB, 10⁶ bytes: VmHWM of /proc/self/status); `None`
/// where the system does not report it.
pub fn peak_rss_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0 / 1e6)
}

/// Orders in which the recorded rays are replayed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RayOrder {
    /// As the run issued them (photon by photon).
    AsTraced,
    /// Sorted along a Z-order (Morton) curve of the direction, then of the origin.
    DirectionThenOrigin,
    /// Sorted along a Z-order curve of the origin, then of the direction.
    OriginThenDirection,
}

impl RayOrder {
    pub fn describe(&self) -> &'static str {
        match self {
            RayOrder::AsTraced => "as traced",
            RayOrder::DirectionThenOrigin => "sorted by direction, then origin",
            RayOrder::OriginThenDirection => "sorted by origin, then direction",
        }
    }
}

/// Keeps every query of a run as it was issued (f64 origin and direction, the
/// surface it leaves), so that the replay asks Embree exactly the same questions.
struct Recorder(Vec<Query>);

impl QueryHook for Recorder {
    fn query(&mut self, q: &Query) {
        self.0.push(*q);
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
    // The trace's peak, before the replayed rays below take memory of their own.
    let peak_rss_mb = peak_rss_mb();

    let mut rec = Recorder(Vec::new());
    let first = cfg.first_photon;
    let replayed = raw_photons.min(photons);
    trace::trace_range_with(scene, cfg.seed, first, first + replayed, &mut rec);
    let rays = rec.0;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    let raw_rate = pool.install(|| replay_rate(scene, &rays));
    let (mut best_raw, mut best_order) = (raw_rate, RayOrder::AsTraced);
    for order in [RayOrder::DirectionThenOrigin, RayOrder::OriginThenDirection] {
        let sorted = sorted_rays(&rays, order);
        let rate = pool.install(|| replay_rate(scene, &sorted));
        if rate > best_raw {
            (best_raw, best_order) = (rate, order);
        }
    }
    let nested_shells = pool.install(|| nested_shell_rates(scene, &rays));
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
        best_raw_rays_per_second: best_raw,
        best_order,
        triangles: scene.triangle_count,
        bvh_seconds: scene.bvh_seconds,
        peak_rss_mb,
        nested_shells,
    })
}

/// Times the shell search against Embree over every object on `rays` (`None`
/// for a scene without nested shells).
fn nested_shell_rates(scene: &Scene, rays: &[Query]) -> Option<NestedShellRates> {
    let search = scene.shell_search.as_ref()?;
    let agreeing = rays
        .par_iter()
        .filter(|q| {
            let full = scene.embree.intersect(q).map(|h| (h.geometry, h.t));
            match (full, search.intersect(q).map(|h| (h.geometry, h.t))) {
                (None, None) => true,
                (Some(a), Some(b)) => a.0 == b.0 && (a.1 - b.1).abs() <= 1e-9 * a.1.abs().max(1.0),
                _ => false,
            }
        })
        .count();
    let nested_rate = rate_of(rays, &|c: &[Query]| {
        c.iter().filter(|q| search.intersect(q).is_some()).count()
    });
    let embree_rate = rate_of(rays, &|c: &[Query]| scene.embree.intersect_raw(c));
    Some(NestedShellRates {
        shells: search.shells.ids().count(),
        embree_rays_per_second: embree_rate,
        nested_rays_per_second: nested_rate,
        agreeing_fraction: agreeing as f64 / rays.len().max(1) as f64,
    })
}

/// Bare `rtcIntersect1` rays per second on `rays` in the current thread pool
/// (after one warm-up pass; at least three passes and one second).
fn replay_rate(scene: &Scene, rays: &[Query]) -> f64 {
    rate_of(rays, &|c: &[Query]| scene.embree.intersect_raw(c))
}

/// Rays per second that `answer` (hits in a slice of rays) gets through `rays`
/// in the current thread pool (after one warm-up pass; at least three passes
/// and one second).
fn rate_of(rays: &[Query], answer: &(dyn Fn(&[Query]) -> usize + Sync)) -> f64 {
    let pass = || -> usize { rays.par_chunks(4096).map(answer).sum() };
    pass();
    let t = Instant::now();
    let mut rounds = 0;
    while rounds < 3 || t.elapsed().as_secs_f64() < 1.0 {
        std::hint::black_box(pass());
        rounds += 1;
    }
    (rays.len() * rounds) as f64 / t.elapsed().as_secs_f64()
}

/// The rays in `order`: keys from 10-bit quantised origins (over the rays' own
/// bounding box) and unit directions, interleaved bit by bit (Z-order).
fn sorted_rays(rays: &[Query], order: RayOrder) -> Vec<Query> {
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for q in rays {
        for k in 0..3 {
            lo[k] = lo[k].min(q.origin[k]);
            hi[k] = hi[k].max(q.origin[k]);
        }
    }
    let cell = |v: f64, lo: f64, hi: f64| -> u64 {
        let f = if hi > lo { (v - lo) / (hi - lo) } else { 0.0 };
        (f.clamp(0.0, 1.0) * 1023.0) as u64
    };
    let key = |q: &Query| -> u64 {
        let (o, d) = (q.origin, q.dir);
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            .sqrt()
            .max(f64::MIN_POSITIVE);
        let origin = morton([0, 1, 2].map(|k| cell(o[k], lo[k], hi[k])));
        let dir = morton([0, 1, 2].map(|k| cell(d[k] / n, -1.0, 1.0)));
        match order {
            RayOrder::DirectionThenOrigin => dir << 30 | origin,
            _ => origin << 30 | dir,
        }
    };
    let mut sorted = rays.to_vec();
    if order != RayOrder::AsTraced {
        sorted.sort_by_cached_key(key);
    }
    sorted
}

/// Interleaves the low 10 bits of three numbers (x in bit 0, y in bit 1, ...).
fn morton(v: [u64; 3]) -> u64 {
    (0..10).fold(0, |m, bit| {
        m | (0..3).fold(0, |acc, k| acc | ((v[k] >> bit) & 1) << (3 * bit + k))
    })
}

/// Seconds to commit (build the BVH of) an Embree scene holding one triangle
/// mesh of `n_triangles` or a few more: a tessellated cylinder, long thin
/// triangles like a tessellated telescope shell. Returns (triangles, seconds).
pub fn bvh_build_seconds(
    device: &crate::embree::Device,
    n_triangles: usize,
) -> Result<(usize, f64), crate::embree::EmbreeError> {
    use crate::geometry::{AzimuthRange, Resolution, RevolutionQuadric, Surface};
    let rings = 100;
    let segments = n_triangles.div_ceil(2 * rings);
    let cylinder = RevolutionQuadric::cylinder(100.0, 0.0, 200.0, AzimuthRange::FULL);
    let mesh = cylinder.tessellate(Resolution { segments, rings });
    let vertices = mesh.positions.iter().map(|p| p.as_vec3().to_array());
    let mut builder = device.scene::<crate::scene::AnalyticPieces>();
    let count = mesh.triangles.len();
    builder.add_triangles(0, vertices, mesh.triangles.into())?;
    let t = Instant::now();
    let committed = builder.commit()?;
    let seconds = t.elapsed().as_secs_f64();
    drop(committed);
    Ok((count, seconds))
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

#[cfg(test)]
mod tests {
    use super::{morton, peak_rss_mb, reset_peak_rss, sorted_rays, RayOrder};
    use crate::embree::Query;

    /// Bit i of each coordinate lands in bit 3i (+0, +1, +2 for x, y, z).
    #[test]
    fn morton_interleaves_bits() {
        assert_eq!(morton([1, 0, 0]), 1);
        assert_eq!(morton([0, 1, 0]), 2);
        assert_eq!(morton([0, 0, 1]), 4);
        assert_eq!(morton([3, 0, 0]), 0b1001);
        assert_eq!(morton([0, 0, 1 << 9]), 1 << 29);
        assert_eq!(morton([1023, 1023, 1023]), (1 << 30) - 1);
    }

    /// Sorting keeps every ray once, and puts rays that start at the same point
    /// next to each other (14 origins: 13 changes of origin along the list).
    #[test]
    fn sorted_rays_are_a_permutation_grouped_by_origin() {
        let rays: Vec<Query> = (0..1000)
            .map(|i| {
                let side = if i % 2 == 0 { -100.0 } else { 100.0 };
                Query {
                    origin: [side, (i % 7) as f64, 0.0],
                    dir: [0.0, 0.0, -1.0],
                    t_max: f64::INFINITY,
                    start_geometry: i % 3,
                }
            })
            .collect();
        let sorted = sorted_rays(&rays, RayOrder::OriginThenDirection);
        let key = |r: &Query| format!("{r:?}");
        let mut a: Vec<String> = rays.iter().map(key).collect();
        let mut b: Vec<String> = sorted.iter().map(key).collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
        let changes = sorted
            .windows(2)
            .filter(|w| w[0].origin != w[1].origin)
            .count();
        assert_eq!(changes, 13);
    }

    #[test]
    fn the_peak_memory_sees_a_touched_allocation() {
        // 400 MB written byte by byte are resident: the high-water mark rises
        // by most of that. Not all of it: tests running beside this one may
        // free memory they held when `before` was read (a 188.5 MB rise was
        // seen for 200 MB under the parallel suite), so the bound leaves
        // 100 MB for them; a mark that missed the block would rise by ~0.
        reset_peak_rss();
        let Some(before) = peak_rss_mb() else {
            return; // not Linux: nothing is reported, and the report says so
        };
        let block = vec![1u8; 400_000_000];
        std::hint::black_box(&block);
        let after = peak_rss_mb().unwrap();
        assert!(after - before > 300.0, "{before} → {after} MB");
    }
}
