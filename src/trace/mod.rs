//! The photon loop and its drivers. `photon` follows one photon through the
//! scene ([`trace_photon`]: mirrors, absorbers, foils, sensors) and
//! [`Statistics`] counts the photons' fates; this module holds the one chunk
//! rule ([`chunk_range`]), the [`Tally`] a run accumulates, and [`run_part`],
//! which traces a run or a part of one (a shard, a resumed sitting, a
//! systematics variation) over rayon, and [`run_part_with`], the same loop
//! with a study's own way of tracing a chunk (a PSF point's tilted beam and
//! tables); [`map_chunks`], the same chunks for a study that keeps per photon
//! what a tally does not (the effective area's path steps, the sky
//! calibration's positions); [`live`] feeds the live window. No other file
//! loops over photon chunks (tests/it/layout.rs). The life of a run around it
//! (results folder, checkpoints, shards, provenance) is `run`'s.
//!
//! Data flow: photon indices are cut into fixed chunks; rayon traces chunks in
//! parallel, photon i with the random stream (seed, i) ([`crate::random`]); each
//! chunk's sensor records and statistics are added to the run's [`Tally`] by
//! the worker that traced it, in whatever order the chunks finish, and only the
//! photon list is joined in photon order. Sensors add weights exactly (see
//! [`crate::sensor::exact`]), so the images are bit-identical for any thread
//! count, and tallies of parts of a run (shards, a run resumed from a checkpoint)
//! add up to the bit-identical tally of the whole.

pub mod live;
mod photon;
mod stats;

pub use photon::{trace_photon, AtItsEnergy, Attenuation, Record, RecordedPhoton, WithTables};
pub use stats::Statistics;

use crate::progress::Progress;
use crate::random::PhotonRng;
use crate::raycast::QueryHook;
use crate::scene::Scene;
use crate::sensor::campaign::CampaignTally;
use crate::sensor::SensorImage;
use rayon::prelude::*;
use std::time::Instant;

/// Photons per chunk: large enough to amortise scheduling, small enough to balance
/// two cores and keep progress reports coming.
pub const CHUNK: u64 = 4096;
/// The photon indices of chunk `c` of a run of `photons` photons whose first
/// photon is `first`: [`CHUNK`] photons each, the last one shorter. With photon i
/// drawing from the stream `PhotonRng::new(seed, i)`, this is the one rule that
/// makes every driver (runs, shards, resumes, the live window, effective-area
/// sweeps) trace the same photons, however the work is split.
pub fn chunk_range(first: u64, c: u64, photons: u64) -> std::ops::Range<u64> {
    let lo = c * CHUNK;
    let hi = (lo + CHUNK).min(photons);
    first + lo..first + hi
}

/// Chunks per batch: between batches the photon list is joined in photon order,
/// checkpoints are written and stops happen (the images are exact sums, added by
/// each worker as its chunk ends, in any order).
const CHUNKS_PER_BATCH: u64 = 256;
/// Photons per batch.
pub const BATCH_PHOTONS: u64 = CHUNK * CHUNKS_PER_BATCH;

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
    /// Keep the details of the first this many recorded photons (photon list).
    pub photon_list: usize,
}

impl RunConfig {
    /// `photons` photons of the run with `seed`, from photon 0, on every core.
    pub fn new(photons: u64, seed: u64) -> RunConfig {
        RunConfig {
            photons,
            seed,
            threads: 0,
            first_photon: 0,
            photon_list: 0,
        }
    }
}

/// What a run, or a part of one, has accumulated so far: exact sums, so that
/// parts add up to the whole in any order ([`Tally::add`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tally {
    pub images: Vec<SensorImage>,
    /// The first recorded photons, in photon order (at most the list asked for).
    pub photons: Vec<RecordedPhoton>,
    pub stats: Statistics,
    /// Photons traced so far, from the part's first photon on.
    pub traced: u64,
    /// With a magnet's campaign, its tallies per sensor; else empty.
    #[serde(default)]
    pub campaign: Vec<CampaignTally>,
}

impl Tally {
    /// Whether the tally has the scene's sensors, pixels and objects (a
    /// tally read from a file may be of another scene).
    pub fn fits(&self, scene: &Scene) -> bool {
        self.images.len() == scene.sensors.len()
            && self.images.iter().zip(&scene.sensors).all(|(i, s)| {
                let n = s.pixel_count() * s.bands();
                i.counts.len() == n
                    && i.flux_sum.len() == n
                    && i.paths.class_images.as_ref().is_none_or(|c| {
                        c.len() == crate::history::PathClass::ALL.len()
                            && c.iter().all(|c| c.len() == s.pixel_count())
                    })
            })
            && self
                .campaign
                .iter()
                .map(|c| c.len())
                .eq(campaign_sizes(scene))
            && self.stats.hits_per_object.len() == scene.objects.len()
            && self.stats.recorded_per_sensor.len() == scene.sensors.len()
    }

    /// Nothing traced yet.
    pub fn new(scene: &Scene) -> Tally {
        Tally {
            images: scene.sensors.iter().map(SensorImage::new).collect(),
            photons: Vec::new(),
            stats: Statistics::new(scene.objects.len(), scene.sensors.len()),
            traced: 0,
            campaign: campaign_tallies(scene),
        }
    }

    /// Adds the tally of another, disjoint part of the same run; keeps the first
    /// `photon_list` recorded photons of both (each part holds its own first ones,
    /// so these are the first ones of the union).
    pub fn add(&mut self, other: &Tally, photon_list: usize) {
        for (a, b) in self.images.iter_mut().zip(&other.images) {
            a.add(b);
        }
        self.photons.extend_from_slice(&other.photons);
        self.photons.sort_by_key(|p| p.index);
        self.photons.truncate(photon_list);
        for (a, b) in self.campaign.iter_mut().zip(&other.campaign) {
            a.add(b);
        }
        self.stats.add(&other.stats);
        self.traced += other.traced;
    }

    /// Adds the photons of the next chunk of `scene` (chunks are added in
    /// photon order); keeps the first `photon_list` recorded photons. Does not
    /// count `traced`.
    pub fn add_chunk(&mut self, scene: &Scene, chunk: Chunk, photon_list: usize) {
        self.add_records(scene, &chunk);
        self.add_listed(chunk.listed, photon_list);
    }

    /// Adds the sensor records and statistics of a chunk of `scene` (whose Sun
    /// says how each photon's weight splits among the process images, and
    /// whose magnet's mass scan the chunk's factors serve). The sums are
    /// exact, so chunks may come in any order.
    pub fn add_records(&mut self, scene: &Scene, chunk: &Chunk) {
        let emission = scene.sun_emission();
        let masses = chunk.mass_factors.len() / chunk.records.len().max(1);
        // One part of each photon's record at a time (see `SensorImage::record_flux`).
        for r in &chunk.records {
            self.images[r.sensor as usize].record_flux(r.pixel, r.weight);
        }
        for (i, r) in chunk.records.iter().enumerate() {
            let shares =
                emission.map_or_else(Default::default, |e| e.process_weights(r.process, r.cell));
            let factors = &chunk.mass_factors[i * masses..(i + 1) * masses];
            self.images[r.sensor as usize].record_split((r.pixel, r.weight), &shares, factors);
        }
        for r in &chunk.records {
            let h = &r.history;
            self.images[r.sensor as usize].record_path(
                (r.pixel, r.weight),
                (h.class(), h.first_mirror, h.last_mirror),
                (r.energy, r.conversion.as_ref()),
            );
        }
        for (a, b) in self.campaign.iter_mut().zip(&chunk.campaign) {
            a.add(b);
        }
        self.stats.add(&chunk.stats);
    }

    /// Appends the listed photons of the next chunk in photon order, up to
    /// `photon_list` in all.
    fn add_listed(&mut self, listed: Vec<RecordedPhoton>, photon_list: usize) {
        let room = photon_list.saturating_sub(self.photons.len());
        self.photons.extend(listed.into_iter().take(room));
    }

    /// The same numbers as a run's result.
    pub fn into_result(self, photon_list: usize, seconds: f64, threads: usize) -> RunResult {
        RunResult {
            images: self.images,
            photons: self.photons,
            photon_list,
            stats: self.stats,
            seconds,
            threads,
            campaign: self.campaign,
        }
    }
}

/// What to do after a batch of photons (see [`run_part`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    Continue,
    /// Stop after this batch; the tally so far is returned.
    Stop,
}

/// Images and statistics of a finished run.
pub struct RunResult {
    pub images: Vec<SensorImage>,
    /// The first `photon_list` recorded photons, in photon order.
    pub photons: Vec<RecordedPhoton>,
    /// How many were asked for (0: no photon list).
    pub photon_list: usize,
    pub stats: Statistics,
    pub seconds: f64,
    pub threads: usize,
    /// With a magnet's campaign, its tallies per sensor; else empty.
    pub campaign: Vec<CampaignTally>,
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
    let start = Instant::now();
    let (tally, threads) = run_part(scene, cfg, Tally::new(scene), progress, &mut |_| {
        Flow::Continue
    })?;
    Ok(tally.into_result(cfg.photon_list, start.elapsed().as_secs_f64(), threads))
}

/// Continues the run `cfg` from `tally` (photons `tally.traced` on, which must be
/// a multiple of [`CHUNK`] or all of them), calling `after_batch` with the tally
/// after every batch of [`BATCH_PHOTONS`] photons; stops early when it says so.
/// Returns the tally and the number of worker threads.
pub fn run_part(
    scene: &Scene,
    cfg: &RunConfig,
    tally: Tally,
    progress: &dyn Progress,
    after_batch: &mut dyn FnMut(&Tally) -> Flow,
) -> Result<(Tally, usize), rayon::ThreadPoolBuildError> {
    let chunk = |range, list_cap| trace_chunk(scene, cfg.seed, range, list_cap, &mut ());
    run_part_with(scene, cfg, tally, progress, after_batch, &chunk)
}

/// Traces one photon chunk: photon indices and how many photon details to keep.
pub type ChunkTracer<'a> = &'a (dyn Fn(std::ops::Range<u64>, usize) -> Chunk + Sync);

/// As [`run_part`], each chunk traced by `chunk` (a study's own sources and
/// reflectivity tables through [`trace_chunk_from`]): the one loop over
/// photon chunks, for runs and for the studies' points alike.
pub fn run_part_with(
    scene: &Scene,
    cfg: &RunConfig,
    mut tally: Tally,
    progress: &dyn Progress,
    after_batch: &mut dyn FnMut(&Tally) -> Flow,
    chunk: ChunkTracer,
) -> Result<(Tally, usize), rayon::ThreadPoolBuildError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(cfg.threads)
        .build()?;
    let threads = pool.current_num_threads();
    let n_chunks = cfg.photons.div_ceil(CHUNK);
    let mut next = tally.traced.div_ceil(CHUNK);
    while next < n_chunks {
        let end = (next + CHUNKS_PER_BATCH).min(n_chunks);
        // Each chunk keeps up to as many photon details as the list still needs.
        let list_cap = cfg.photon_list.saturating_sub(tally.photons.len());
        // Each worker adds its chunk's records to the shared tally itself (exact
        // sums: the order does not matter), so that no core waits for a serial
        // merge; only the photon list is joined in photon order afterwards.
        let shared = std::sync::Mutex::new(tally);
        let listed: Vec<Vec<RecordedPhoton>> = pool.install(|| {
            (next..end)
                .into_par_iter()
                .map(|c| {
                    let range = chunk_range(cfg.first_photon, c, cfg.photons);
                    let n = range.end - range.start;
                    let r = chunk(range, list_cap);
                    shared
                        .lock()
                        .expect("no worker panics while holding the tally")
                        .add_records(scene, &r);
                    progress.advance(n);
                    r.listed
                })
                .collect()
        });
        tally = shared
            .into_inner()
            .expect("no worker panics while holding the tally");
        for l in listed {
            tally.add_listed(l, cfg.photon_list);
        }
        tally.traced = (end * CHUNK).min(cfg.photons);
        next = end;
        if after_batch(&tally) == Flow::Stop {
            break;
        }
    }
    Ok((tally, threads))
}

/// The parallel loop over the chunks of photons [first, first + photons) in the
/// current thread pool, for studies that keep per photon what a run's tally
/// does not (the effective area each path's steps, the sky calibration each
/// photon's position): `chunk` traces a chunk's photon indices and returns what
/// it keeps, and the results come back in chunk order, whatever the threads.
pub fn map_chunks<T: Send>(
    first: u64,
    photons: u64,
    progress: &dyn Progress,
    chunk: &(dyn Fn(std::ops::Range<u64>) -> T + Sync),
) -> Vec<T> {
    (0..photons.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let range = chunk_range(first, c, photons);
            let n = range.end - range.start;
            let kept = chunk(range);
            progress.advance(n);
            kept
        })
        .collect()
}

/// What one chunk of photons gave.
pub struct Chunk {
    pub records: Vec<Record>,
    /// With a magnet's mass scan, each record's weight factor per mass
    /// (record-major; [`crate::magnet::Magnet::convert`]); else empty.
    pub mass_factors: Vec<f64>,
    /// With a magnet's campaign, the chunk's tallies per sensor; else empty.
    pub campaign: Vec<CampaignTally>,
    /// Details of the first recorded photons (at most the cap asked for).
    pub listed: Vec<RecordedPhoton>,
    pub stats: Statistics,
}

/// The magnet as a step on a recorded Sun photon's path: the record's weight
/// (and the weight it entered a gas detector with) times P / P_max of its
/// axion (`axion`: its start, direction and energy), the mass scan's factors
/// appended to `scan`. The one place where P meets a photon.
#[inline]
pub fn convert_in_magnet(
    magnet: &crate::magnet::Magnet,
    ((origin, dir), energy): ((glam::DVec3, glam::DVec3), f64),
    record: &mut Record,
    scan: &mut Vec<f64>,
) -> crate::magnet::ConversionPath {
    let path = magnet.path_of(origin, dir);
    let converted = magnet.convert(&path, energy, scan);
    record.weight *= converted;
    if let Some(c) = record.conversion.as_mut() {
        c.entered *= converted;
    }
    path
}

/// The largest weight a recorded photon may carry into the tallies: 2³²
/// (traxer's weights are at most ~1: reflectivities, P / P_max), far inside
/// the exact sums' range (2⁴⁸ in all, [`crate::sensor::WeightSum`]).
pub const LARGEST_WEIGHT: f64 = 4294967296.0;

/// Whether `w` can be tallied: a number from 0 to [`LARGEST_WEIGHT`] (NaN
/// fails both comparisons).
#[inline]
pub fn tallied_weight(w: f64) -> bool {
    (0.0..=LARGEST_WEIGHT).contains(&w)
}

/// A recorded photon's part in the magnet's campaign: its axion weight
/// (`axion_weight`, before P) times each (setting, mass) pair's P / P_max,
/// in the bin of its energy and its position `local` on the sensor.
fn record_campaign(
    magnet: &crate::magnet::Magnet,
    (path, axion_weight): (&crate::magnet::ConversionPath, f64),
    (record, local): (&Record, glam::DVec3),
    (tallies, factors): (&mut [CampaignTally], &mut Vec<f64>),
) {
    let Some(c) = magnet.campaign.as_deref() else {
        return;
    };
    factors.clear();
    if let Some(bin) = c.bin([local.x, local.y], record.energy) {
        c.factors(magnet, path, record.energy, factors);
        tallies[record.sensor as usize].record(bin, axion_weight, factors);
    }
}

/// The sums of each sensor's campaign tally in `scene` (none without a
/// campaign).
fn campaign_sizes(scene: &Scene) -> Vec<usize> {
    match scene.magnet.as_deref().and_then(|m| m.campaign.as_deref()) {
        Some(c) => vec![c.pairs.len() * c.bins(); scene.sensors.len()],
        None => Vec::new(),
    }
}

/// Zeroed campaign tallies for `scene`'s sensors (none without a campaign).
pub fn campaign_tallies(scene: &Scene) -> Vec<CampaignTally> {
    match scene.magnet.as_deref().and_then(|m| m.campaign.as_deref()) {
        Some(c) => scene
            .sensors
            .iter()
            .map(|_| CampaignTally::new(c.pairs.len(), c.bins()))
            .collect(),
        None => Vec::new(),
    }
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
    let c = trace_chunk(scene, seed, lo..hi, 0, hook);
    (c.records, c.stats)
}

/// Traces the photons of `range`, keeping the details of the first `list_cap`
/// recorded ones.
pub fn trace_chunk<H: QueryHook>(
    scene: &Scene,
    seed: u64,
    range: std::ops::Range<u64>,
    list_cap: usize,
    hook: &mut H,
) -> Chunk {
    let sources = &scene.sources;
    trace_chunk_from(
        scene,
        (sources, &mut AtItsEnergy),
        seed,
        range,
        list_cap,
        hook,
    )
}

/// As [`trace_chunk`], with `sources` in place of the scene's and weights by
/// `att` (a study's beam tilted or at another energy, with reflectivity tables
/// for it): photon i comes from source i mod n.
pub fn trace_chunk_from<H: QueryHook, A: Attenuation>(
    scene: &Scene,
    (sources, att): (&[crate::source::Source], &mut A),
    seed: u64,
    range: std::ops::Range<u64>,
    list_cap: usize,
    hook: &mut H,
) -> Chunk {
    let mut stats = Statistics::new(scene.objects.len(), scene.sensors.len());
    let mut records = Vec::new();
    let mut mass_factors = Vec::new();
    let mut listed = Vec::new();
    let (mut campaign, mut campaign_factors) = (Vec::new(), Vec::new());
    let n_sources = sources.len() as u64;
    if n_sources == 0 {
        // A scene for visible-light renders only: nothing is emitted.
        return Chunk {
            records,
            mass_factors,
            campaign,
            listed,
            stats,
        };
    }
    // The scene's magnet converts the Sun's axions: one place where P meets
    // the photon, when it is recorded (P depends only on the axion's path
    // and energy), with the mass scan's factors from the same path.
    let magnet = match sources {
        [crate::source::Source::Sun(_)] => scene.magnet.as_deref(),
        _ => None,
    };
    if magnet.is_some() {
        campaign = campaign_tallies(scene);
    }
    for i in range {
        let mut rng = PhotonRng::new(seed, i);
        let photon = sources[(i % n_sources) as usize].emit(&mut rng);
        let axion = ((photon.origin, photon.dir), photon.energy);
        if let Some((mut record, local, dir)) =
            trace_photon(scene, photon, &mut rng, &mut stats, hook, att)
        {
            let scan = mass_factors.len();
            if let Some(m) = magnet {
                let axion_weight = record.weight;
                let path = convert_in_magnet(m, axion, &mut record, &mut mass_factors);
                record_campaign(
                    m,
                    (&path, axion_weight),
                    (&record, local),
                    (&mut campaign, &mut campaign_factors),
                );
                if !campaign_factors
                    .iter()
                    .all(|f| tallied_weight(axion_weight * f))
                {
                    stats.unusable_weights += 1;
                }
            }
            let w = record.weight;
            if !tallied_weight(w) || !mass_factors[scan..].iter().all(|f| tallied_weight(w * f)) {
                stats.unusable_weights += 1;
            }
            if listed.len() < list_cap {
                listed.push(RecordedPhoton {
                    index: i,
                    record,
                    local,
                    dir,
                });
            }
            records.push(record);
        }
    }
    Chunk {
        records,
        mass_factors,
        campaign,
        listed,
        stats,
    }
}
