//! Everything traxer writes to disk: `.npy` arrays, PNG colour maps, plots, CSV
//! tables and JSON with one provenance record (each file written atomically by
//! `crate::files`).
//!
//! Data flow: `trace` produces merged sensor images and statistics, the studies
//! their scans, comparisons and fits; the CLI passes them here to be written into
//! the `--out` folder: a trace's files ([`write_run`]), [`write_focus`],
//! [`write_compare`], [`write_fit`]; renders and plots get a sidecar
//! ([`write_sidecar`]).

mod arf;
pub mod campaign;
mod campaign_reach;
pub mod campaign_read;
pub use campaign_reach::{campaign_reach_json, write_campaign_reach, CAMPAIGN_REACH_FILES};
mod compare;
mod conversion;
mod csv_table;
mod eef_plot;
mod effective_area;
mod fit;
mod fits;
mod fits_maps;
mod fits_read;
mod focus;
mod history;
mod image_plot;
mod labels;
mod masses;
pub use masses::mass_images;
mod montage;
mod npy;
mod plot;
mod png;
mod processes;
mod psf;
pub use processes::process_images;
pub use psf::{normalised as normalised_psf, write_psf_library, PSF_FILES};
pub use sensor_figure::stopped_by_part;
mod provenance;
mod reach;
pub mod reference_curve;
mod study_files;
pub use study_files::StudyFiles;
mod run_files;
pub mod run_read;
pub use reach::{write_reach, REACH_FILES};
mod signal;
pub use signal::{write_signal, SIGNAL_FILES};
mod sensor_figure;
mod solar_flux;
mod systematics;
pub use systematics::{
    description as systematics_description, write_systematics, SYSTEMATICS_FILES,
};

pub use crate::colormap::Scale;
pub use crate::sensor::{class_file_names, file_stem, SensorFiles};
pub use arf::{arf_name, energy_bins, sixte_vignetting_refused, SIXTE_VIGNETTING};
pub use compare::{compare_markdown, compare_rows_json, write_compare, COMPARE_FILES};
pub use csv_table::{csv_text, write_csv};
pub use eef_plot::write_eef_plot;
pub use effective_area::{effective_area_files, write_effective_area, EFFECTIVE_AREA_FILES};
pub use fit::{fit_json, fit_preset_toml, write_fit, FitReport, FIT_FILES};
pub use fits::{write_grid_fits, write_sensor_fits, FluxUnit, SensorFits};
pub use fits_read::{read_fits_image, FitsImage};
pub use focus::{plotted_diameter, write_focus, FOCUS_FILES};
pub use history::{
    history_json, photon_list_npy, write_class_images, write_photon_list, PHOTON_LIST_FILES,
};
pub use image_plot::{write_image_figure, ImageFigure, Overlay};
pub use labels::{draw_labels, place_labels};
pub use montage::{write_montage, Tile};
pub use npy::{read_image, read_npy, write_npy_f64, write_npy_u64, NpyError, NpyImage};
pub use plot::{line_plot, Series};
pub use png::{write_png, write_rgb_png};
pub use provenance::{sidecar_path, write_sidecar, Provenance};
pub use run_files::{flux_unit, run_file_names, statistics_json, write_json, write_run, Outputs};
pub use solar_flux::{cast2007_flux, write_solar_flux, SolarFluxInfo, SOLAR_FLUX_FILES};
