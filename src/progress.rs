//! Progress of long computations, reported by the library through a callback so
//! that the library never prints: `trace` reports photons, `render` rows, the
//! studies (focus scans, comparisons, fits) the photons of all their runs; the
//! binary draws bars from it (or nothing, for `--quiet` or when not on a terminal),
//! and one-line notices of slow first-time work.
//! A leaf module.

/// Something told how much work has been finished, as it finishes. Called from
/// worker threads, a few times per thousand photons (never per photon).
pub trait Progress: Sync {
    /// `done` more units (photons, rows, ...) are finished.
    fn advance(&self, done: u64);
    /// Whether the work should stop at its next point (a study checks between
    /// its points; Python's Ctrl-C).
    fn stop_requested(&self) -> bool {
        false
    }
}

/// Where notices go: one line each about slow work the user should know is
/// happening (a reflectivity table built for the first time). The binary sends
/// them to stderr unless `--quiet`; the Python module to stderr; by default
/// they go nowhere, so the library stays silent.
static NOTICES: std::sync::OnceLock<fn(&str)> = std::sync::OnceLock::new();

/// Sends notices to `sink` from now on (the first call wins).
pub fn set_notice_sink(sink: fn(&str)) {
    let _ = NOTICES.set(sink);
}

/// Tells the user about slow work, if someone listens.
pub fn notice(message: &str) {
    if let Some(sink) = NOTICES.get() {
        sink(message);
    }
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
