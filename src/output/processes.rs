//! A sensor's image per emission process (`NAME_primakoff.npy`, `NAME_abc.npy`
//! for a Sun with both couplings; `NAME_atomic.npy`, `NAME_electron_ion.npy`,
//! `NAME_electron_electron.npy`, `NAME_compton.npy` for ABC's four processes)
//! and its summary: each process's flux and photons, and how to build the
//! image for other couplings from them.
//!
//! Data flow: `run_files` asks [`process_images`] for the scaled images (also
//! written into the FITS file as extensions) and [`write_process_images`] for
//! the files and the JSON entry.

use super::npy::write_npy_f64;
use crate::sensor::{process_file_names, SensorImage, SensorSpec};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Each process's image ([iy][ix], summed over bands) times `scale` (axions/s
/// per unit weight for a Sun), with its name; empty for a one-process source.
pub fn process_images(
    spec: &SensorSpec,
    image: &SensorImage,
    scale: f64,
) -> Vec<(String, Vec<f64>)> {
    spec.processes
        .iter()
        .enumerate()
        .map(|(k, name)| (name.clone(), process_image(image, k, scale)))
        .collect()
}

/// Process `k`'s image times `scale`.
fn process_image(image: &SensorImage, k: usize, scale: f64) -> Vec<f64> {
    let mut img = image.processes.image(k);
    img.iter_mut().for_each(|v| *v *= scale);
    img
}

/// How each built-in process's image scales with the couplings: its
/// production's coupling squared, times g_aγ² with a magnet (the conversion).
fn scales_as(process: &str, magnet: bool) -> Option<&'static str> {
    match (process, magnet) {
        ("primakoff", false) => Some("g_agamma²"),
        ("primakoff", true) => Some("g_agamma⁴"),
        ("abc" | "atomic" | "electron_ion" | "electron_electron" | "compton", false) => {
            Some("g_ae²")
        }
        ("abc" | "atomic" | "electron_ion" | "electron_electron" | "compton", true) => {
            Some("g_ae² g_agamma²")
        }
        _ => None,
    }
}

/// Writes the per-process images as `.npy`, one at a time (a sensor's
/// images together would double a large run's peak memory); returns the JSON
/// entry (`null` without processes) and adds the paths to `written`.
/// `magnet`: the scene converts the axions (the images scale with g_aγ² more).
pub fn write_process_images(
    dir: &Path,
    (spec, image, magnet): (&SensorSpec, &SensorImage, bool),
    scale: f64,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<Value> {
    if spec.processes.is_empty() {
        return Ok(Value::Null);
    }
    let shape = [spec.pixels[1] as u64, spec.pixels[0] as u64];
    let files = process_file_names(&spec.name, &spec.processes);
    let totals = image.processes.totals();
    let all = image.total_flux();
    let mut entries = Vec::new();
    for (k, (name, file)) in spec.processes.iter().zip(&files).enumerate() {
        let p = dir.join(file);
        write_npy_f64(&p, &shape, &process_image(image, k, scale))?;
        written.push(p);
        entries.push(json!({
            "name": name,
            "file": file,
            "total_flux": totals[k] * scale,
            "fraction_of_total_flux": if all > 0.0 { totals[k] / all } else { 0.0 },
            "photons": image.processes.counts[k],
            "scales_as": scales_as(name, magnet),
        }));
    }
    Ok(json!({
        "what": "the image of each emission process, from the same photons as the total, summed over energy bands: primakoff and abc (with both couplings) add up to the total, and ABC's four processes (atomic, electron_ion, electron_electron, compton) add up to abc, each photon's weight split by its emission cell's shares (data/solar/abc_b16_agss09met_process_shares.csv, to 1e-4); with both couplings each coupling's table was drawn for half the photons, so each image has the statistics of half the run whatever the couplings, and the photons' paths do not depend on the couplings",
        "recombine": if magnet {
            "the image for other couplings is (g_agamma/g_agamma_run)⁴ × primakoff + (g_ae/g_ae_run)² (g_agamma/g_agamma_run)² × abc (production times conversion), the couplings of this run in sources[].coupling and sources[].magnet.g_agamma_per_gev (keep them equal); ABC's four processes scale like abc"
        } else {
            "the image for other couplings is (g_agamma/g_agamma_run)² × primakoff + (g_ae/g_ae_run)² × abc, the couplings of this run in sources[].coupling; it equals a trace with those couplings to rounding; ABC's four processes scale as g_ae² like abc"
        },
        "processes": entries,
    }))
}
