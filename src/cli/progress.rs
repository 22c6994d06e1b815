//! Progress bars on stderr, drawn from the library's progress reports: only on a
//! terminal, never with `--quiet`. The rate reads as a physicist says it
//! (2.21 M photons/s), and a pause in the reports (a scene being built between
//! the steps of a scan) is left out of the rate and the ETA.

use indicatif::{ProgressBar, ProgressState, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// A bar over `total` units (`unit`: "photons", "rows", "evaluations"), hidden
/// when `quiet` or when stderr is not a terminal. Feed it through [`Bar::inc`].
pub fn bar(total: u64, unit: &str, quiet: bool) -> Bar {
    if quiet || !std::io::stderr().is_terminal() {
        return Bar::new(ProgressBar::hidden());
    }
    let b = ProgressBar::new(total);
    let unit_for_rate = unit.to_string();
    b.set_style(
        ProgressStyle::with_template(&format!(
            "{{elapsed_precise}} [{{bar:40}}] {{human_pos}}/{{human_len}} {unit} ({{rate}}, eta {{eta}})"
        ))
        .expect("static template")
        .with_key("rate", move |s: &ProgressState, w: &mut dyn std::fmt::Write| {
            let _ = write!(w, "{} {unit_for_rate}/s", readable(s.per_sec()));
        })
        .progress_chars("=> "),
    );
    Bar::new(b)
}

/// A rate with an SI prefix and three significant digits: 2.21 M, 850 k, 12.3.
pub fn readable(x: f64) -> String {
    let (v, prefix) = match x {
        x if x >= 1e9 => (x / 1e9, " G"),
        x if x >= 1e6 => (x / 1e6, " M"),
        x if x >= 1e3 => (x / 1e3, " k"),
        x => (x, ""),
    };
    let digits = if v >= 100.0 {
        0
    } else if v >= 10.0 {
        1
    } else {
        2
    };
    format!("{v:.digits$}{prefix}")
}

/// A progress bar that leaves pauses longer than [`PAUSE`] out of its rate and
/// ETA: the work is counted, the time spent building scenes is not.
pub struct Bar {
    bar: ProgressBar,
    last: Mutex<Option<Instant>>,
}

/// A gap between reports longer than this is a pause (reports come several
/// times a second while photons are traced).
const PAUSE: Duration = Duration::from_millis(700);

impl Bar {
    fn new(bar: ProgressBar) -> Bar {
        Bar {
            bar,
            last: Mutex::new(None),
        }
    }

    /// `n` more units are done.
    pub fn inc(&self, n: u64) {
        if let Ok(mut last) = self.last.lock() {
            let now = Instant::now();
            // The first report, or one after a pause: start the rate afresh.
            if last.is_none_or(|t| now - t > PAUSE) {
                self.bar.reset_eta();
            }
            *last = Some(now);
        }
        self.bar.inc(n);
    }

    /// Moves the bar to `pos` units.
    pub fn set_position(&self, pos: u64) {
        self.bar.set_position(pos);
    }

    /// Runs `f` with the bar hidden (for printing a line).
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }

    pub fn finish_and_clear(&self) {
        self.bar.finish_and_clear();
    }
}
