//! `traxer.TraceResult` and `traxer.SensorImage`: a finished trace as numpy
//! arrays and dicts, in the units of the CLI's files (the same library calls
//! make both), and `TraceResult.save`, which writes the CLI's output set.

use crate::convert::{array, json, to_json};
use crate::errors::lib;
use crate::scene::Loaded;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;
use traxer::analysis::FinishedImage;
use traxer::output::{flux_unit, photon_list_npy, sources_json, statistics_json, Provenance};
use traxer::run::{save_results, StateHeader};
use traxer::sensor::SensorSpec;
use traxer::trace::Tally;

/// One sensor's image of a trace.
///
/// `flux` is the image as NAME.npy holds it (float64, [iy, ix], or [band, iy, ix]
/// with energy bins; ix along the sensor's local x): the sum of photon weights
/// per pixel, or axions per second with a Sun source (see `unit`). `counts`:
/// photons per pixel (uint64, same shape). `quality`: centroid and the 50/80/90 %
/// diameters (mm, and arcsec with a focal length) of the image summed over
/// bands, as in NAME.json; None without flux.
#[pyclass(module = "traxer", frozen, get_all)]
#[allow(non_snake_case)]
pub struct SensorImage {
    pub name: String,
    pub flux: Py<PyAny>,
    pub counts: Py<PyAny>,
    /// "ph" (weighted photons per pixel) or "s-1" (axions per second per pixel).
    pub unit: String,
    pub size_mm: (f64, f64),
    pub pixels: (u32, u32),
    pub pixel_pitch_mm: (f64, f64),
    pub focal_length_mm: Option<f64>,
    pub energy_band_edges_keV: Option<Vec<f64>>,
    /// Pixel-centre positions along local x and y (mm).
    pub x_mm: Py<PyAny>,
    pub y_mm: Py<PyAny>,
    pub quality: Py<PyAny>,
    /// The encircled-energy curve: radius (mm) and the fraction of flux within.
    pub eef_radius_mm: Py<PyAny>,
    pub eef_fraction: Py<PyAny>,
    pub total_flux: f64,
    pub total_counts: u64,
    /// For a gas detector, where its X-rays converted (None otherwise): a dict
    /// with the numbers of NAME.json → conversion (`mean_depth_mm`,
    /// `quantiles_mm` [(q, depth)], `converted_fraction`, `entered_flux`,
    /// `converted_flux`, in the image's unit), `depth_edges_mm` and `depth_flux`
    /// (the histogram below the gas entrance), and `spectrum` [slice, energy bin]
    /// with `spectrum_depth_edges_mm` and `spectrum_energy_edges_keV`.
    pub conversion: Py<PyAny>,
}

#[pymethods]
impl SensorImage {
    fn __repr__(&self) -> String {
        format!(
            "traxer.SensorImage({:?}: {}×{} pixels, {} photons, total flux {:.6e} {})",
            self.name, self.pixels.0, self.pixels.1, self.total_counts, self.total_flux, self.unit
        )
    }
}

impl SensorImage {
    fn new(
        py: Python<'_>,
        spec: &SensorSpec,
        image: &traxer::sensor::SensorImage,
        absolute: Option<f64>,
    ) -> PyResult<SensorImage> {
        let (nx, ny) = (spec.pixels[0] as usize, spec.pixels[1] as usize);
        let finished = FinishedImage::of(spec, image, absolute);
        let total_flux = finished.total_flux();
        let [x_mm, y_mm] = finished.pixel_centres_mm();
        let FinishedImage {
            shape,
            flux,
            quality,
            ..
        } = finished;
        let (quality, eef) = match quality {
            Some((q, e)) => (to_json(py, &q)?, Some(e)),
            None => (py.None().into_bound(py), None),
        };
        let (radius, fraction) =
            eef.map_or((Vec::new(), Vec::new()), |e| (e.radius_mm, e.fraction));
        let pitch = spec.pitch();
        let conversion = match &image.conversion {
            Some(t) => conversion_dict(py, t, absolute.unwrap_or(1.0))?
                .into_any()
                .unbind(),
            None => py.None(),
        };
        Ok(SensorImage {
            conversion,
            name: spec.name.clone(),
            total_flux,
            total_counts: image.total_counts(),
            flux: array(py, &shape, flux)?.unbind(),
            counts: array(py, &shape, image.counts.clone())?.unbind(),
            unit: flux_unit(absolute.is_some()).bunit.to_string(),
            size_mm: (spec.size[0], spec.size[1]),
            pixels: (spec.pixels[0], spec.pixels[1]),
            pixel_pitch_mm: (pitch[0], pitch[1]),
            focal_length_mm: spec.focal_length,
            energy_band_edges_keV: spec.band_edges(),
            x_mm: array(py, &[nx], x_mm)?.unbind(),
            y_mm: array(py, &[ny], y_mm)?.unbind(),
            quality: quality.unbind(),
            eef_radius_mm: array(py, &[radius.len()], radius)?.unbind(),
            eef_fraction: array(py, &[fraction.len()], fraction)?.unbind(),
        })
    }
}

/// The conversion tally of a gas detector as a dict (see `SensorImage.conversion`).
fn conversion_dict<'py>(
    py: Python<'py>,
    t: &traxer::sensor::conversion::ConversionTally,
    scale: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let s = t.summary();
    d.set_item("entered_flux", s.entered_flux * scale)?;
    d.set_item("converted_flux", s.converted_flux * scale)?;
    d.set_item("converted_fraction", s.converted_fraction)?;
    d.set_item("mean_depth_mm", s.mean_depth_mm)?;
    d.set_item("median_depth_mm", s.median_mm())?;
    d.set_item("quantiles_mm", s.quantiles_mm.to_vec())?;
    let hist: Vec<f64> = t.depth_histogram().iter().map(|f| f * scale).collect();
    let edges: Vec<f64> = (0..=hist.len())
        .map(|i| (i as f64 * t.step_mm).min(t.drift_mm))
        .collect();
    d.set_item("depth_edges_mm", array(py, &[edges.len()], edges)?)?;
    d.set_item("depth_flux", array(py, &[hist.len()], hist)?)?;
    let (lo, hi, n) = t.energy_bins;
    let slices = t.depth_slices as usize;
    let spectrum: Vec<f64> = t.spectrum().iter().map(|f| f * scale).collect();
    d.set_item("spectrum", array(py, &[slices, n as usize], spectrum)?)?;
    let e: Vec<f64> = (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect();
    d.set_item("spectrum_energy_edges_keV", array(py, &[e.len()], e)?)?;
    let z: Vec<f64> = (0..=slices)
        .map(|i| t.drift_mm * i as f64 / slices as f64)
        .collect();
    d.set_item("spectrum_depth_edges_mm", array(py, &[z.len()], z)?)?;
    Ok(d)
}

/// A finished trace: `sensors` ({name: SensorImage}, in the scene's order; also
/// `result["name"]`), `statistics` and `sources` (dicts as in summary.json),
/// `provenance` (dict), `photons` (the photon list as a numpy structured array
/// like photons.npy, or None), `seconds` and `threads`. `save(folder)` writes the
/// files of `traxer trace`.
#[pyclass(module = "traxer", frozen)]
pub struct TraceResult {
    loaded: Arc<Loaded>,
    header: StateHeader,
    tally: Tally,
    threads: usize,
    provenance: Provenance,
    #[pyo3(get)]
    sensors: Py<PyDict>,
    #[pyo3(get)]
    statistics: Py<PyAny>,
    #[pyo3(get)]
    sources: Py<PyAny>,
    #[pyo3(get)]
    photons: Py<PyAny>,
}

impl TraceResult {
    pub fn new(
        py: Python<'_>,
        loaded: Arc<Loaded>,
        header: StateHeader,
        tally: Tally,
        threads: usize,
        provenance: Provenance,
    ) -> PyResult<TraceResult> {
        let scene = &loaded.scene;
        let emitted = tally.stats.photons_emitted;
        let absolute = scene.rate_per_unit_weight(emitted);
        let sensors = PyDict::new(py);
        for (spec, image) in scene.sensors.iter().zip(&tally.images) {
            sensors.set_item(&spec.name, SensorImage::new(py, spec, image, absolute)?)?;
        }
        let result =
            tally
                .clone()
                .into_result(header.identity.photon_list, header.seconds, threads);
        let statistics = json(py, &statistics_json(scene, &result))?;
        let sources = json(py, &sources_json(scene, emitted))?;
        let photons = if header.identity.photon_list > 0 {
            let bytes = photon_list_npy(&result.photons, absolute.unwrap_or(1.0)).map_err(lib)?;
            let buffer = py.import("io")?.call_method1("BytesIO", (bytes,))?;
            py.import("numpy")?.call_method1("load", (buffer,))?
        } else {
            py.None().into_bound(py)
        };
        Ok(TraceResult {
            loaded,
            header,
            tally,
            threads,
            provenance,
            sensors: sensors.unbind(),
            statistics: statistics.unbind(),
            sources: sources.unbind(),
            photons: photons.unbind(),
        })
    }
}

impl TraceResult {
    /// The scene's sensors, "a, b, c".
    fn sensor_names(&self) -> String {
        let names: Vec<&str> = self
            .loaded
            .scene
            .sensors
            .iter()
            .map(|s| s.name.as_str())
            .collect();
        names.join(", ")
    }
}

#[pymethods]
impl TraceResult {
    /// The provenance record of the run (as in every JSON the CLI writes).
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_json(py, &self.provenance)
    }

    /// Seconds spent tracing.
    #[getter]
    fn seconds(&self) -> f64 {
        self.header.seconds
    }

    /// Worker threads used (the result does not depend on it).
    #[getter]
    fn threads(&self) -> usize {
        self.threads
    }

    /// Photons traced.
    #[getter]
    fn photons_traced(&self) -> u64 {
        self.tally.traced
    }

    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let sensors = self.sensors.bind(py);
        match sensors.get_item(name)? {
            Some(s) => Ok(s),
            None => Err(pyo3::exceptions::PyKeyError::new_err(format!(
                "{name}: no such sensor (have: {})",
                self.sensor_names()
            ))),
        }
    }

    fn __repr__(&self) -> String {
        let s = &self.tally.stats;
        format!(
            "traxer.TraceResult({} photons, {} reached a sensor, sensors: {})",
            s.photons_emitted,
            s.reached_sensor,
            self.sensor_names()
        )
    }

    /// Writes the files of `traxer trace` into `folder` (created if needed): per
    /// sensor NAME.npy, NAME_counts.npy, PNGs, NAME.json, ..., summary.json,
    /// run_state.bin (for `traxer merge`), the photon list if one was kept, and
    /// with `fits=True` each sensor's image as NAME.fits. All files appear at once
    /// (a folder of other files is refused). Returns the number of files written.
    #[pyo3(signature = (folder, fits = false))]
    fn save(&self, py: Python<'_>, folder: PathBuf, fits: bool) -> PyResult<usize> {
        let scene = &self.loaded.scene;
        py.detach(|| {
            save_results(
                &folder,
                scene,
                &self.header,
                self.tally.clone(),
                self.threads,
                &self.provenance,
                fits,
            )
        })
        .map_err(lib)
    }
}
