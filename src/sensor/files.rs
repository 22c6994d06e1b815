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

/// The files of one sensor named `name`: flux, counts, linear and log figures,
/// the JSON sidecar, the EEF plot, the projections, the bare pixel image.
pub fn sensor_file_names(name: &str) -> [String; 8] {
    let stem = file_stem(name);
    [
        format!("{stem}.npy"),
        format!("{stem}_counts.npy"),
        format!("{stem}.png"),
        format!("{stem}_log.png"),
        format!("{stem}.json"),
        format!("{stem}_eef.png"),
        format!("{stem}_projections.csv"),
        format!("{stem}_pixels.png"),
    ]
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
pub fn grid_file_names(name: &str) -> [String; 3] {
    let stem = file_stem(name);
    [
        format!("{stem}_grid.npy"),
        format!("{stem}_grid.csv"),
        format!("{stem}_grid.png"),
    ]
}

/// The files of a gas detector's conversions: the depth histogram (CSV and
/// plot) and the depth-resolved spectrum.
pub fn conversion_file_names(name: &str) -> [String; 3] {
    let stem = file_stem(name);
    [
        format!("{stem}_conversion_depth.csv"),
        format!("{stem}_conversion_depth.png"),
        format!("{stem}_conversion_spectrum.csv"),
    ]
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
    let longest = sensor_file_names(name)
        .into_iter()
        .chain(conversion_file_names(name))
        .chain(grid_file_names(name))
        .chain(class_file_names(name))
        .chain(process_file_names(name, &[LONGEST_PROCESS.to_string()]))
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
