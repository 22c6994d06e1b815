//! X-rays traced continuously for a live view (`traxer view`): one background
//! thread traces chunk after chunk of photons in photon order and publishes a
//! copy of its tally every so often; the window shows it on the sensors while
//! it grows. Because the chunks go in photon order from photon 0, the tally after
//! N photons (a multiple of `trace::CHUNK`, or where a limit stops it) is the
//! bit-identical tally of `traxer trace -n N` with the same seed.
//!
//! Data flow: `scene` → [`feed`] (here, with [`super::trace_chunk`]) → the shared
//! [`Published`] tally → the window (sensor textures, live HPD, saving through
//! `output`).

use super::{trace_chunk, Tally, CHUNK};
use crate::scene::Scene;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The latest published tally and how often it has been published.
pub struct Published {
    pub tally: Tally,
    pub version: u64,
    /// The feed stopped (limit reached or asked to stop).
    pub finished: bool,
}

impl Published {
    pub fn new(scene: &Scene) -> Published {
        Published {
            tally: Tally::new(scene),
            version: 0,
            finished: false,
        }
    }
}

/// Traces photons 0, 1, ... of the run with `seed` until `stop` is set or
/// `limit` photons are traced, publishing the tally into `out` at most every
/// `every` (and at the end).
pub fn feed(
    scene: &Scene,
    seed: u64,
    limit: Option<u64>,
    every: Duration,
    stop: &AtomicBool,
    out: &Mutex<Published>,
) {
    let mut tally = Tally::new(scene);
    let limit = limit.unwrap_or(u64::MAX);
    let mut last = Instant::now();
    let publish = |tally: &Tally, finished: bool| {
        if let Ok(mut p) = out.lock() {
            p.tally.clone_from(tally);
            p.version += 1;
            p.finished = finished;
        }
    };
    while !stop.load(Ordering::Relaxed) && tally.traced < limit && !scene.sources.is_empty() {
        let hi = tally.traced.saturating_add(CHUNK).min(limit);
        let chunk = trace_chunk(scene, seed, tally.traced..hi, 0, &mut ());
        tally.add_chunk(scene, chunk, 0);
        tally.traced = hi;
        if last.elapsed() >= every {
            publish(&tally, false);
            last = Instant::now();
        }
    }
    publish(&tally, true);
}
