//! The names of a sensor's output files, decided here — where sensors are defined
//! — so that the scene build can refuse names that collide or that no file
//! system takes before any photon is traced, and `output` writes exactly these.

/// The run's own file beside the sensors' files.
pub const SUMMARY_FILE: &str = "summary.json";

/// The longest file name (bytes) common file systems (ext4, XFS, Btrfs, APFS,
/// NTFS) take.
pub const MAX_FILE_NAME_BYTES: usize = 255;

use crate::files::TEMPORARY_NAME_EXTRA_BYTES;
use crate::history::PathClass;

/// Object names may hold anything; file names get letters, digits, '-', '_', '.'.
pub fn file_stem(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The files every sensor writes, by what they hold.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorFiles {
    /// The flux image (`NAME.npy`).
    pub flux_npy: String,
    /// Photons per pixel (`NAME_counts.npy`).
    pub counts_npy: String,
    /// The figure, linear (`NAME.png`) and log (`NAME_log.png`).
    pub figure_png: String,
    pub figure_log_png: String,
    /// The sensor's record (`NAME.json`).
    pub json: String,
    /// The encircled-energy plot (`NAME_eef.png`; only when flux arrived).
    pub eef_png: String,
    /// The x and y projections (`NAME_projections.csv`).
    pub projections_csv: String,
    /// The bare pixel image (`NAME_pixels.png`).
    pub pixels_png: String,
}

impl SensorFiles {
    /// The files of sensor `name`.
    pub fn of(name: &str) -> SensorFiles {
        let stem = file_stem(name);
        SensorFiles {
            flux_npy: format!("{stem}.npy"),
            counts_npy: format!("{stem}_counts.npy"),
            figure_png: format!("{stem}.png"),
            figure_log_png: format!("{stem}_log.png"),
            json: format!("{stem}.json"),
            eef_png: format!("{stem}_eef.png"),
            projections_csv: format!("{stem}_projections.csv"),
            pixels_png: format!("{stem}_pixels.png"),
        }
    }

    /// Every name, the EEF plot's included.
    pub fn all(&self) -> [&str; 8] {
        [
            &self.flux_npy,
            &self.counts_npy,
            &self.figure_png,
            &self.figure_log_png,
            &self.json,
            &self.eef_png,
            &self.projections_csv,
            &self.pixels_png,
        ]
    }
}

/// The FITS file of a sensor's image (`trace --fits`).
pub fn fits_file_name(name: &str) -> String {
    format!("{}.fits", file_stem(name))
}

/// The FITS file of a sensor's image on its detector pixel grid (`trace
/// --fits`, sensors with a `pixel_grid`).
pub fn grid_fits_file_name(name: &str) -> String {
    format!("{}_grid.fits", file_stem(name))
}

/// The files of a sensor's image on its detector pixel grid: flux as `.npy` and
/// as CSV for the limit code, and its figure.
#[derive(Clone, Debug, PartialEq)]
pub struct GridFiles {
    pub npy: String,
    pub csv: String,
    pub png: String,
}

impl GridFiles {
    pub fn of(name: &str) -> GridFiles {
        let stem = file_stem(name);
        GridFiles {
            npy: format!("{stem}_grid.npy"),
            csv: format!("{stem}_grid.csv"),
            png: format!("{stem}_grid.png"),
        }
    }

    pub fn all(&self) -> [&str; 3] {
        [&self.npy, &self.csv, &self.png]
    }
}

/// The files of a gas detector's conversions: the depth histogram (CSV and
/// plot) and the depth-resolved spectrum.
#[derive(Clone, Debug, PartialEq)]
pub struct ConversionFiles {
    pub depth_csv: String,
    pub depth_png: String,
    pub spectrum_csv: String,
}

impl ConversionFiles {
    pub fn of(name: &str) -> ConversionFiles {
        let stem = file_stem(name);
        ConversionFiles {
            depth_csv: format!("{stem}_conversion_depth.csv"),
            depth_png: format!("{stem}_conversion_depth.png"),
            spectrum_csv: format!("{stem}_conversion_spectrum.csv"),
        }
    }

    pub fn all(&self) -> [&str; 3] {
        [&self.depth_csv, &self.depth_png, &self.spectrum_csv]
    }
}

/// The per-class image files of sensor `name` (`history_images`), in
/// [`PathClass::ALL`] order.
pub fn class_file_names(name: &str) -> Vec<String> {
    let stem = file_stem(name);
    PathClass::ALL
        .iter()
        .map(|c| format!("{stem}_{}.npy", c.name()))
        .collect()
}

/// The per-process image files of sensor `name`, one per process of the
/// source ([`super::SensorSpec::processes`]).
pub fn process_file_names(name: &str, processes: &[String]) -> Vec<String> {
    let stem = file_stem(name);
    processes
        .iter()
        .map(|p| format!("{stem}_{p}.npy"))
        .collect()
}

/// The files of sensor `name`'s mass scan: the images of every mass
/// (`NAME_by_mass.npy`) and, for a source of several processes, each mass's
/// per-process images (`NAME_by_mass_and_process.npy`).
pub fn mass_file_names(name: &str, processes: bool) -> Vec<String> {
    let stem = file_stem(name);
    let mut names = vec![format!("{stem}_by_mass.npy")];
    if processes {
        names.push(format!("{stem}_by_mass_and_process.npy"));
    }
    names
}

/// The longest process name a source has ("electron_electron"), for the
/// file-name check made before the sources are known.
const LONGEST_PROCESS: &str = "electron_electron";

/// Why a sensor's name cannot name its files: every file it may write (the
/// FITS file, grid, conversion and class images included) must still be a
/// valid name with the temporary name's additions (`files::atomic_write`).
pub fn check_file_names(name: &str) -> Result<(), String> {
    let stem = file_stem(name);
    if stem.is_empty() || stem.chars().all(|c| c == '.') {
        return Err(format!(
            "sensor `{name}`: its files would be named `{stem}.npy` ...: give it a name with letters or digits"
        ));
    }
    let (files, conversion, grid) = (
        SensorFiles::of(name),
        ConversionFiles::of(name),
        GridFiles::of(name),
    );
    let longest = files
        .all()
        .into_iter()
        .chain(conversion.all())
        .chain(grid.all())
        .map(str::to_string)
        .chain(class_file_names(name))
        .chain(process_file_names(name, &[LONGEST_PROCESS.to_string()]))
        .chain(mass_file_names(name, true))
        .chain([fits_file_name(name), grid_fits_file_name(name)])
        .map(|f| f.len() + TEMPORARY_NAME_EXTRA_BYTES)
        .max()
        .unwrap_or(0);
    if longest > MAX_FILE_NAME_BYTES {
        return Err(format!(
            "sensor name of {} characters: its files' temporary names would be {longest} bytes long, more than the {MAX_FILE_NAME_BYTES} file systems take; shorten it",
            name.chars().count()
        ));
    }
    Ok(())
}
