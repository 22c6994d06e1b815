//! A sensor's images for a magnet's mass scan: `NAME_by_mass.npy` (a stack
//! [mass, (band,) iy, ix] in the units of the total image) and, for a source of
//! several processes, `NAME_by_mass_and_process.npy` ([mass, process, iy, ix]);
//! and the JSON entry with each mass's total.
//!
//! Data flow: `run_files` calls [`write_mass_images`] for every sensor.

use super::npy::write_npy_f64;
use crate::sensor::{exact, mass_file_names, SensorImage, SensorSpec};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Writes the mass scan's stacks (scaled by `scale`: X-rays/s per unit
/// weight); returns the JSON entry (`null` without a scan) and adds the paths
/// to `written`.
pub fn write_mass_images(
    dir: &Path,
    spec: &SensorSpec,
    image: &SensorImage,
    scale: f64,
    written: &mut Vec<PathBuf>,
) -> std::io::Result<Value> {
    if spec.masses.is_empty() {
        return Ok(Value::Null);
    }
    let files = mass_file_names(&spec.name, !spec.processes.is_empty());
    let (nx, ny) = (spec.pixels[0] as u64, spec.pixels[1] as u64);
    let images = &image.masses.images;
    let mut shape = vec![spec.masses.len() as u64];
    if spec.energy_bins.is_some() {
        shape.push(spec.bands() as u64);
    }
    shape.extend([ny, nx]);
    let stack: Vec<f64> = images
        .iter()
        .flat_map(|m| m.flux_sum.iter().map(|s| s.value() * scale))
        .collect();
    let p = dir.join(&files[0]);
    write_npy_f64(&p, &shape, &stack)?;
    written.push(p);
    if let Some(file) = files.get(1) {
        let shape = [
            spec.masses.len() as u64,
            spec.processes.len() as u64,
            ny,
            nx,
        ];
        let stack: Vec<f64> = images
            .iter()
            .flat_map(|m| m.processes.images.iter().flatten())
            .map(|s| s.value() * scale)
            .collect();
        let p = dir.join(file);
        write_npy_f64(&p, &shape, &stack)?;
        written.push(p);
    }
    let totals = image.masses.totals();
    let entries: Vec<Value> = spec
        .masses
        .iter()
        .zip(images)
        .zip(&totals)
        .map(|((m, img), total)| {
            let by_process: Vec<Value> = spec
                .processes
                .iter()
                .zip(img.processes.totals())
                .map(|(name, t)| json!({"name": name, "total_flux": t * scale}))
                .collect();
            json!({
                "axion_mass_ev": m,
                "total_flux": total * scale,
                "x_rays_per_hour_of_tracking": total * scale * 3600.0,
                "by_process": by_process,
            })
        })
        .collect();
    Ok(json!({
        "what": "one image per axion mass from the same photons: each recorded photon's weight times P(a→γ) of its own axion path at that mass over P at the scene's axion_mass_ev (the optics and the detector do not depend on the mass); each mass's processes add up to its total",
        "files": files,
        "layout": "by_mass[mass, iy, ix] (or [mass, band, iy, ix] with energy bins), in the units of the total image; by_mass_and_process[mass, process, iy, ix] summed over bands, processes in by_process order",
        "masses": entries,
    }))
}

/// Each mass's image summed over bands ([iy][ix]) in X-rays/s, for figures
/// and Python.
pub fn mass_images(spec: &SensorSpec, image: &SensorImage, scale: f64) -> Vec<Vec<f64>> {
    image
        .masses
        .images
        .iter()
        .map(|m| {
            let flux: Vec<f64> = exact::values(&m.flux_sum)
                .iter()
                .map(|v| v * scale)
                .collect();
            crate::sensor::sum_bands(&flux, spec.pixel_count())
        })
        .collect()
}
