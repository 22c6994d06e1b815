//! Everything traxer writes to disk: atomic file writes, `.npy` arrays, PNG colour
//! maps and JSON sidecars with provenance.
//!
//! Data flow: `trace` produces merged sensor images and statistics; the CLI passes
//! them here to be written into the `--out` folder.

mod image_png;
mod montage;
mod npy;
mod plot;
mod provenance;
mod run_files;

pub use image_png::{write_png, Scale};
pub use montage::{write_montage, Tile};
pub use npy::{write_npy_f64, write_npy_u64};
pub use plot::{line_plot, Series};
pub use provenance::{git_hash, sha256_hex, Provenance};
pub use run_files::{file_stem, write_json, write_run};

use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` through a temporary file in the same folder and a
/// rename, so that readers never see a half-written file.
pub fn atomic_write(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "no file name"))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", path.display())))
}
