//! Everything traxer writes to disk: `.npy` arrays, PNG colour maps, plots and
//! JSON sidecars with provenance (each file written atomically by `crate::files`).
//!
//! Data flow: `trace` produces merged sensor images and statistics; the CLI passes
//! them here to be written into the `--out` folder.

mod eef_plot;
mod image_png;
mod montage;
mod npy;
mod plot;
mod provenance;
mod run_files;

pub use eef_plot::write_eef_plot;
pub use image_png::{write_png, Scale};
pub use montage::{write_montage, Tile};
pub use npy::{write_npy_f64, write_npy_u64};
pub use plot::{line_plot, Series};
pub use provenance::{git_hash, Provenance};
pub use run_files::{file_stem, write_json, write_run};
