//! Progress bars on stderr, drawn from the library's progress reports: only on a
//! terminal, never with `--quiet`.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

/// A bar over `total` units (`unit`: "photons", "rows", ...), hidden when
/// `quiet` or when stderr is not a terminal. Feed it with `&|n| bar.inc(n)`.
pub fn bar(total: u64, unit: &str, quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::new(total);
    b.set_style(
        ProgressStyle::with_template(&format!(
            "{{elapsed_precise}} [{{bar:40}}] {{human_pos}}/{{human_len}} {unit} ({{per_sec}}, eta {{eta}})"
        ))
        .expect("static template")
        .progress_chars("=> "),
    );
    b
}
