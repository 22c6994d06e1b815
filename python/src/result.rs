//! `traxer.TraceResult` and `traxer.SensorImage`: a finished trace as numpy
//! arrays and dicts, in the units of the CLI's files (the same library calls
//! make both), and `TraceResult.save`, which writes the CLI's output set.

use crate::convert::{array, json, to_json};
use crate::errors::lib;
use crate::scene::Loaded;
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyDict};
use std::path::PathBuf;
use std::sync::Arc;
use traxer::analysis::FinishedImage;
use traxer::history::PathClass;
use traxer::output::{flux_unit, photon_list_npy, statistics_json, Provenance};
use traxer::run::{save_results, StateHeader};
use traxer::sensor::SensorSpec;
use traxer::source::sources_json;
use traxer::trace::Tally;

/// One sensor's image of a trace.
///
/// In the units of the CLI's files: `flux` equals NAME.npy, `counts`
/// NAME_counts.npy, `quality` the image quality of NAME.json. Pixel (0, 0) has
/// its corner at (-size_x/2, -size_y/2) of the sensor's local frame; ix runs
/// along local x. With a `pixel_grid`, `grid` is the image on the detector's
/// pixels (NAME_grid.npy); with `history_images`, `by_class` splits it by
/// photon path.
#[pyclass(module = "traxer", frozen, get_all)]
#[allow(non_snake_case)]
pub struct SensorImage {
    /// The sensor's name in the scene.
    pub name: String,
    /// [iy, ix], or [band, iy, ix] with energy bins; ix along the sensor's local
    /// x. The sum of photon weights per pixel, or axions per second with a Sun
    /// source — X-rays per second with a magnet (see `unit`). Equal to NAME.npy.
    pub flux: Py<PyAny>,
    /// Photons per pixel, the shape of `flux`. Equal to NAME_counts.npy.
    pub counts: Py<PyAny>,
    /// "ph" (weighted photons per pixel) or "s-1" (axions per second per pixel;
    /// with a magnet, X-rays per second).
    pub unit: String,
    /// (x, y) extent of the sensor, mm.
    pub size_mm: (f64, f64),
    /// (nx, ny).
    pub pixels: (u32, u32),
    /// (x, y) pixel pitch, mm.
    pub pixel_pitch_mm: (f64, f64),
    /// The sensor's focal length (mm) for angular diameters, or None.
    pub focal_length_mm: Option<f64>,
    /// The energy bands' edges (keV) of a [band, iy, ix] image, or None.
    pub energy_band_edges_keV: Option<Vec<f64>>,
    /// Pixel-centre positions along local x (mm); pixel (0, 0) has its corner at
    /// (-size_x/2, -size_y/2).
    pub x_mm: Py<PyAny>,
    /// Pixel-centre positions along local y (mm).
    pub y_mm: Py<PyAny>,
    /// centroid_mm, total_flux, hpd_mm, d80_mm, d90_mm and, with a focal length,
    /// hpd_arcsec, d80_arcsec, d90_arcsec, of the image summed over bands; None
    /// without flux. The d* are diameters around the centroid.
    pub quality: Py<PyAny>,
    /// The encircled-energy curve: radius (mm) around the centroid …
    pub eef_radius_mm: Py<PyAny>,
    /// … and the fraction of the flux within it.
    pub eef_fraction: Py<PyAny>,
    /// The sum of `flux`, in `unit`.
    pub total_flux: f64,
    /// The sum of `counts`.
    pub total_counts: u64,
    /// For a gas detector, where its X-rays converted (None otherwise): a dict
    /// with the numbers of NAME.json → conversion (`mean_depth_mm`,
    /// `quantiles_mm` [(q, depth)], `converted_fraction`, `entered_flux`,
    /// `converted_flux`, in the image's unit), `depth_edges_mm` and `depth_flux`
    /// (the histogram below the gas entrance), and `spectrum` [slice, energy bin]
    /// with `spectrum_depth_edges_mm` and `spectrum_energy_edges_keV`.
    pub conversion: Py<PyAny>,
    /// The image on the sensor's detector pixel grid (`pixel_grid` in the
    /// scene; the GridPix's 256 × 256 pixels of 55 µm) as a `traxer.GridImage`,
    /// equal to NAME_grid.npy; None for a sensor without one.
    pub grid: Option<Py<crate::grid::GridImage>>,
    /// With `history_images = true` on the sensor: {class: flux [iy, ix]} for
    /// each photon-path class of `TraceResult.classes` (direct, front_rear,
    /// front_only, rear_only, other), equal to NAME_CLASS.npy; None otherwise.
    pub by_class: Option<Py<PyDict>>,
    /// With a Sun emitting Primakoff and ABC: {process: flux [iy, ix]} for
    /// "primakoff" and "abc", from the same photons as `flux` (they add up to
    /// its sum over bands), and ABC's four processes ("atomic", "electron_ion",
    /// "electron_electron", "compton", adding up to "abc"), equal to
    /// NAME_PROCESS.npy; ABC alone has the four; None for a source of one
    /// process. Each scales as its coupling squared (g_aγ², g_ae²; with a magnet g_aγ⁴ and g_ae² g_aγ²): the image
    /// for other couplings is their sum so scaled, equal to a trace with them.
    pub by_process: Option<Py<PyDict>>,
    /// With a magnet's mass scan (`masses_ev`, `--masses`): {axion mass (eV):
    /// flux} in the shape and units of `flux`, from the same photons (each
    /// weight times its path's P(m) / P at the scene's mass), equal to the
    /// slices of NAME_by_mass.npy; None without a scan.
    pub by_mass: Option<Py<PyDict>>,
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
        (absolute, counted): (Option<f64>, traxer::scene::Counted),
    ) -> PyResult<SensorImage> {
        let (nx, ny) = (spec.pixels[0] as usize, spec.pixels[1] as usize);
        let finished = FinishedImage::of(spec, image, absolute);
        let total_flux = finished.total_flux();
        let [x_mm, y_mm] = finished.pixel_centres_mm();
        let grid = match finished.on_grid(spec) {
            Some((g, r)) => Some(Py::new(py, crate::grid::GridImage::new(py, &g, r)?)?),
            None => None,
        };
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
        let by_class = match image.paths.class_images() {
            Some(images) => {
                let d = PyDict::new(py);
                let scale = absolute.unwrap_or(1.0);
                for (class, img) in PathClass::ALL.iter().zip(images) {
                    let flux = img.iter().map(|v| v * scale).collect();
                    d.set_item(class.name(), array(py, &[ny, nx], flux)?)?;
                }
                Some(d.unbind())
            }
            None => None,
        };
        let by_process = match spec.processes.is_empty() {
            true => None,
            false => {
                let d = PyDict::new(py);
                let scale = absolute.unwrap_or(1.0);
                for (name, img) in traxer::output::process_images(spec, image, scale) {
                    d.set_item(name, array(py, &[ny, nx], img)?)?;
                }
                Some(d.unbind())
            }
        };
        Ok(SensorImage {
            by_mass: by_mass(py, spec, image, (&shape, absolute.unwrap_or(1.0)))?,
            conversion,
            grid,
            by_class,
            by_process,
            name: spec.name.clone(),
            total_flux,
            total_counts: image.total_counts(),
            flux: array(py, &shape, flux)?.unbind(),
            counts: array(py, &shape, image.counts.to_vec())?.unbind(),
            unit: flux_unit(counted).bunit.to_string(),
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

/// The mass scan's images as a dict (see `SensorImage.by_mass`).
fn by_mass(
    py: Python<'_>,
    spec: &SensorSpec,
    image: &traxer::sensor::SensorImage,
    (shape, scale): (&[usize], f64),
) -> PyResult<Option<Py<PyDict>>> {
    if spec.masses.is_empty() {
        return Ok(None);
    }
    let d = PyDict::new(py);
    for (m, img) in spec.masses.iter().zip(&image.masses.images) {
        let flux = img.flux_sum.iter().map(|s| s.value() * scale).collect();
        d.set_item(*m, array(py, shape, flux)?)?;
    }
    Ok(Some(d.unbind()))
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
    let edges = t.depth_edges_mm();
    d.set_item("depth_edges_mm", array(py, &[edges.len()], edges)?)?;
    d.set_item("depth_flux", array(py, &[hist.len()], hist)?)?;
    let (z, e) = (t.spectrum_depth_edges_mm(), t.spectrum_energy_edges_kev());
    let spectrum: Vec<f64> = t.spectrum().iter().map(|f| f * scale).collect();
    d.set_item(
        "spectrum",
        array(py, &[z.len() - 1, e.len() - 1], spectrum)?,
    )?;
    d.set_item("spectrum_energy_edges_keV", array(py, &[e.len()], e)?)?;
    d.set_item("spectrum_depth_edges_mm", array(py, &[z.len()], z)?)?;
    Ok(d)
}

/// A finished trace: each sensor's image, the statistics, the sources, the
/// provenance and the photon list; `save(folder)` writes the CLI's files.
///
/// `result["name"]` is `result.sensors["name"]`.
#[pyclass(module = "traxer", frozen)]
pub struct TraceResult {
    loaded: Arc<Loaded>,
    header: StateHeader,
    tally: Tally,
    threads: usize,
    provenance: Provenance,
    /// Each sensor's image, {name: SensorImage}, in the scene's order.
    #[pyo3(get)]
    sensors: Py<PyDict>,
    /// Photon fates and counters, as summary.json's "statistics".
    #[pyo3(get)]
    statistics: Py<PyAny>,
    /// The sources, as summary.json's "sources".
    #[pyo3(get)]
    sources: Py<PyAny>,
    /// The photon list (`photon_list=N`): a read-only structured array like
    /// photons.npy (index, sensor, x_mm, y_mm, dir_x, dir_y, dir_z, energy_keV,
    /// weight, reflections, first_mirror, last_mirror, class); None without one.
    #[pyo3(get)]
    photons: Py<PyAny>,
    /// The photon-path classes by index, as `photons["class"]` and the class
    /// images number them: direct (no reflection), front_rear (a front then a
    /// rear mirror: the focus), front_only, rear_only, other.
    #[pyo3(get)]
    classes: Vec<&'static str>,
    /// With a magnet's campaign ([magnet.campaign]): campaign.json's content
    /// (settings with their tracking hours, masses_ev, pairs [setting, mass],
    /// energy_edges_kev, ring_edges_mm, centre_mm, the planner and the
    /// allocation) and `tallies` {sensor: X-rays per second [pair, energy,
    /// ring]}, equal to NAME_campaign.npy; None without a campaign.
    #[pyo3(get)]
    campaign: Py<PyAny>,
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
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        for (spec, image) in scene.sensors.iter().zip(&tally.images) {
            let units = (absolute, scene.counted());
            sensors.set_item(&spec.name, SensorImage::new(py, spec, image, units)?)?;
            // The CLI's warnings on setups that are hardly what was meant.
            let finished = traxer::analysis::FinishedImage::of(spec, image, absolute);
            for d in traxer::analysis::doubts(spec, image, &finished, scene.has_mirrors()) {
                let message = std::ffi::CString::new(d).unwrap_or_default();
                PyErr::warn(py, &category, &message, 1)?;
            }
            if image.total_counts() == 0 {
                // As loud as the CLI's warning: an all-zero image is rarely meant.
                let message = std::ffi::CString::new(format!(
                    "no photon reached sensor `{}` ({emitted} photons traced): its images are empty. Check that the source points at the telescope (a sun's `direction` points towards the Sun, a beam's is its direction of travel) and where the sensor sits.",
                    spec.name
                ))
                .unwrap_or_default();
                PyErr::warn(py, &category, &message, 1)?;
            }
        }
        let result =
            tally
                .clone()
                .into_result(header.identity.photon_list, header.seconds, threads);
        let statistics = json(py, &statistics_json(scene, &result))?;
        let sources = json(
            py,
            &sources_json(&scene.sources, emitted, scene.magnet.as_deref()),
        )?;
        let photons = if header.identity.photon_list > 0 {
            let bytes = photon_list_npy(&result.photons, absolute.unwrap_or(1.0)).map_err(lib)?;
            let buffer = py.import("io")?.call_method1("BytesIO", (bytes,))?;
            let photons = py.import("numpy")?.call_method1("load", (buffer,))?;
            // Read-only like every other array the result hands out.
            photons.call_method("setflags", (), Some(&[("write", false)].into_py_dict(py)?))?;
            photons
        } else {
            py.None().into_bound(py)
        };
        let campaign = campaign_dict(py, scene, &tally, absolute.unwrap_or(1.0))?;
        Ok(TraceResult {
            campaign,
            loaded,
            header,
            tally,
            threads,
            provenance,
            sensors: sensors.unbind(),
            statistics: statistics.unbind(),
            sources: sources.unbind(),
            photons: photons.unbind(),
            classes: PathClass::ALL.iter().map(|c| c.name()).collect(),
        })
    }
}

/// `TraceResult.campaign` (see there): the tables the CLI writes.
fn campaign_dict(
    py: Python<'_>,
    scene: &traxer::scene::Scene,
    tally: &Tally,
    rate: f64,
) -> PyResult<Py<PyAny>> {
    let Some(t) = traxer::output::campaign::campaign_tables(scene, &tally.campaign, rate) else {
        return Ok(py.None());
    };
    let d = json(py, &t.doc)?;
    let tallies = PyDict::new(py);
    for (name, values) in t.sensors {
        tallies.set_item(name, array(py, &t.shape, values)?)?;
    }
    d.set_item("tallies", tallies)?;
    Ok(d.unbind())
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
    /// (a folder of other files is refused, and so is one holding the results of
    /// a run with other inputs unless `replace=True`). Returns the number of
    /// files written.
    #[pyo3(signature = (folder, fits = false, replace = false))]
    fn save(&self, py: Python<'_>, folder: PathBuf, fits: bool, replace: bool) -> PyResult<usize> {
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
                replace,
            )
        })
        .map_err(lib)
    }
}
