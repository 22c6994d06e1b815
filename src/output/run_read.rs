//! Reads a finished magnet run back from its results folder for the studies
//! that follow a run (`traxer signal`, `traxer reach`): the sensor's images per
//! axion mass in X-rays per second, its geometry and energy bands, and the
//! run's couplings, from `summary.json`, `NAME.json`, `NAME.npy` and
//! `NAME_by_mass.npy`.
//!
//! Data flow: `cli::signal` and `cli::reach` call [`read_run_signal`];
//! `analysis::signal` measures what it returns.

use crate::analysis::signal::RunSignal;
use crate::analysis::ImageGeometry;
use crate::sensor::{mass_file_names, SensorFiles, SUMMARY_FILE};
use serde_json::Value;
use std::path::Path;

/// Why a folder is not a run the signal can be read from.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct RunReadError(pub String);

pub(super) fn read_json(path: &Path) -> Result<Value, RunReadError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        RunReadError(format!(
            "{}: {e} (give the results folder of a finished `traxer trace`)",
            path.display()
        ))
    })?;
    serde_json::from_str(&text).map_err(|e| {
        RunReadError(format!(
            "{}: not the JSON traxer writes: {e}",
            path.display()
        ))
    })
}

/// The sensor `sensor` (or the run's only sensor) of the run in `dir`.
pub fn read_run_signal(dir: &Path, sensor: Option<&str>) -> Result<RunSignal, RunReadError> {
    let summary_path = dir.join(SUMMARY_FILE);
    let summary = read_json(&summary_path)?;
    let bad = |what: &str| RunReadError(format!("{}: {what}", summary_path.display()));
    let source = &summary["sources"][0];
    if source["type"] != "sun" || source["magnet"].is_null() {
        return Err(bad("the run has no magnet: its images count axions before conversion, not X-rays (trace a Sun scene with its [magnet] on, as the shipped ones are unless -D magnet=false)"));
    }
    let magnet = &source["magnet"];
    let name = &sensor_name(&summary, sensor).map_err(|m| bad(&m))?;
    let files = SensorFiles::of(name);
    let doc = read_json(&dir.join(&files.json))?;
    let s = &doc["sensor"];
    let number = |v: &Value, what: &str| {
        v.as_f64()
            .ok_or_else(|| RunReadError(format!("{}: no {what}", files.json)))
    };
    let (size, pixels) = (
        [
            number(&s["size_mm"][0], "size_mm")?,
            number(&s["size_mm"][1], "size_mm")?,
        ],
        [
            number(&s["pixels"][0], "pixels")? as usize,
            number(&s["pixels"][1], "pixels")? as usize,
        ],
    );
    let geometry = ImageGeometry {
        nx: pixels[0],
        ny: pixels[1],
        pitch: [size[0] / pixels[0] as f64, size[1] / pixels[1] as f64],
        origin_mm: [-0.5 * size[0], -0.5 * size[1]],
    };
    let band_edges: Vec<f64> = match s["energy_band_edges_keV"].as_array() {
        Some(e) => e.iter().filter_map(Value::as_f64).collect(),
        None => vec![
            number(&source["energy_range_keV"][0], "energy range")?,
            number(&source["energy_range_keV"][1], "energy range")?,
        ],
    };
    let plane = geometry.nx * geometry.ny;
    let bands = band_edges.len() - 1;
    let read = |file: &str, count: usize| -> Result<Vec<f64>, RunReadError> {
        let (_, v) = super::read_npy(&dir.join(file)).map_err(|e| RunReadError(e.to_string()))?;
        if v.len() != count {
            return Err(RunReadError(format!(
                "{file}: {} values where the sensor's JSON promises {count}",
                v.len()
            )));
        }
        Ok(v)
    };
    let total = read(&files.flux_npy, plane * bands)?;
    let scan: Vec<f64> = s["by_mass"]["masses"]
        .as_array()
        .map(|m| {
            m.iter()
                .filter_map(|e| e["axion_mass_ev"].as_f64())
                .collect()
        })
        .unwrap_or_default();
    let (masses, images) = if scan.is_empty() {
        (
            vec![number(&magnet["axion_mass_ev"], "magnet.axion_mass_ev")?],
            vec![total],
        )
    } else {
        let stack = read(&mass_file_names(name, false)[0], scan.len() * plane * bands)?;
        let images = stack
            .chunks_exact(plane * bands)
            .map(<[f64]>::to_vec)
            .collect();
        (scan, images)
    };
    let (emission, g_ae) = emission_of(source);
    Ok(RunSignal {
        sensor: name.to_string(),
        geometry,
        band_edges,
        masses,
        images,
        g_agamma: number(&magnet["g_agamma_per_gev"], "magnet.g_agamma_per_gev")?,
        g_ae,
        emission: emission.to_string(),
        gas: gas_of(magnet),
    })
}

/// The sensor asked for, or the run's only one.
pub(super) fn sensor_name(summary: &Value, sensor: Option<&str>) -> Result<String, String> {
    let names: Vec<&str> = summary["sensors"]
        .as_array()
        .map(|a| a.iter().filter_map(|s| s["name"].as_str()).collect())
        .unwrap_or_default();
    match (sensor, names.as_slice()) {
        (Some(s), _) if names.contains(&s) => Ok(s.to_string()),
        (None, [one]) => Ok(one.to_string()),
        _ => Err(format!(
            "{} sensor{}: pick one of {} with --sensor",
            sensor.map_or("no".to_string(), |s| format!("no `{s}`")),
            if sensor.is_some() {
                ""
            } else {
                "s to choose from"
            },
            names.join(", ")
        )),
    }
}

/// The gas phase's description from the magnet's summary (`None`: vacuum).
fn gas_of(magnet: &Value) -> Option<String> {
    let number = |v: &Value| crate::text::number(v.as_f64().unwrap_or(f64::NAN));
    magnet["gas"].as_object().map(|g| {
        format!(
            "{} mbar at {} K (mᵧ = {:.4} eV)",
            number(&g["pressure_mbar"]),
            number(&g["temperature_k"]),
            g["photon_mass_ev"].as_f64().unwrap_or(0.0)
        )
    })
}

/// The run's emission ("primakoff", "abc", "primakoff+abc" or "a table
/// file") and its g_ae, from the source's productions.
pub(super) fn emission_of(source: &Value) -> (&'static str, Option<f64>) {
    let production = |p: &str| {
        source["productions"]
            .as_array()
            .and_then(|a| a.iter().find(|e| e["process"] == p))
            .and_then(|e| e["value"].as_f64())
    };
    let emission = match (production("primakoff"), production("abc")) {
        (Some(_), Some(_)) => "primakoff+abc",
        (Some(_), None) => "primakoff",
        (None, Some(_)) => "abc",
        (None, None) => "a table file",
    };
    (emission, production("abc"))
}
