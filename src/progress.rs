//! Progress of long computations, reported by the library through a callback so
//! that the library never prints: `trace` reports photons, `render` rows, the
//! studies (focus scans, comparisons, fits) the photons of all their runs; the
//! binary draws bars from it (or nothing, for `--quiet` or when not on a terminal).
//! A leaf module.

/// Something told how much work has been finished, as it finishes. Called from
/// worker threads, a few times per thousand photons (never per photon).
pub trait Progress: Sync {
    /// `done` more units (photons, rows, ...) are finished.
    fn advance(&self, done: u64);
}

/// No one is watching.
impl Progress for () {
    fn advance(&self, _: u64) {}
}

/// Any thread-safe closure, e.g. `&|n| bar.inc(n)`.
impl<F: Fn(u64) + Sync> Progress for F {
    fn advance(&self, done: u64) {
        self(done)
    }
}
