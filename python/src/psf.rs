//! `Scene.psf_library` and `traxer.PsfLibrary`: the PSF library of `traxer psf`
//! (same photons, same images) as a numpy array over [angle, azimuth, energy,
//! iy, ix], and `PsfLibrary.save`, which writes the CLI's files.

use crate::convert::{array, to_json};
use crate::errors::to_py;
use crate::scene::Loaded;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;
use traxer::output::Provenance;
use traxer::studies::psf::{PsfGrid, PsfLibrary as Library};

/// Traces the library with the GIL released (into `out` when given, as the
/// CLI).
pub fn run(
    py: Python<'_>,
    loaded: Arc<Loaded>,
    g: PsfGrid,
    place: (Option<PathBuf>, bool),
    progress: bool,
) -> PyResult<PsfLibrary> {
    let (result, provenance) =
        crate::run::run_study(py, &loaded, (&g, "psf_library"), place, progress)?;
    PsfLibrary::new(py, result, g, provenance)
}

/// A PSF library: the telescope's image of a source at infinity over energies,
/// off-axis angles and azimuths.
///
/// `images` [angle, azimuth, energy, iy, ix]: each a window of `window` pixels
/// around the image's centroid, normalised to a sum of 1 (equal to psf.npy);
/// `corner` [angle, azimuth, energy, 2]: the window's first pixel (ix, iy) on
/// the sensor; `fraction_in_window` the window's share of the sensor's flux;
/// `centroid_mm` the image centroid on the sensor (local mm).
#[pyclass(module = "traxer", frozen)]
#[allow(non_snake_case)]
pub struct PsfLibrary {
    /// The sensor imaged on.
    #[pyo3(get)]
    pub sensor: String,
    /// The energies, keV.
    #[pyo3(get)]
    pub energies_keV: Py<PyAny>,
    /// The off-axis angles, arcmin.
    #[pyo3(get)]
    pub angles_arcmin: Py<PyAny>,
    /// The azimuths of the tilt, degrees.
    #[pyo3(get)]
    pub azimuths_deg: Py<PyAny>,
    /// The normalised images, [angle, azimuth, energy, iy, ix] (equal to psf.npy).
    #[pyo3(get)]
    pub images: Py<PyAny>,
    /// Each window's first sensor pixel (ix, iy), [angle, azimuth, energy, 2].
    #[pyo3(get)]
    pub corner: Py<PyAny>,
    /// Each window's share of the flux on the sensor, [angle, azimuth, energy].
    #[pyo3(get)]
    pub fraction_in_window: Py<PyAny>,
    /// Each image's centroid on the sensor (local mm), [angle, azimuth, energy, 2].
    #[pyo3(get)]
    pub centroid_mm: Py<PyAny>,
    /// The sensor's pixel pitch (x, y), mm.
    #[pyo3(get)]
    pub pixel_pitch_mm: (f64, f64),
    /// The sensor's focal length, mm.
    #[pyo3(get)]
    pub focal_length_mm: f64,
    /// Pixels per side of each window.
    #[pyo3(get)]
    pub window: u32,
    /// Seconds spent tracing.
    #[pyo3(get)]
    pub seconds: f64,
    result: Library,
    grid: PsfGrid,
    provenance: Provenance,
}

impl PsfLibrary {
    fn new(py: Python<'_>, r: Library, g: PsfGrid, provenance: Provenance) -> PyResult<PsfLibrary> {
        let dims = [
            g.angles_arcmin.len(),
            g.azimuths_deg.len(),
            g.energies.len(),
        ];
        let w = r.window as usize;
        let images = r
            .images
            .iter()
            .flat_map(traxer::output::normalised_psf)
            .collect();
        let corner = r
            .images
            .iter()
            .flat_map(|i| i.corner.map(f64::from))
            .collect();
        let centroid = r.images.iter().flat_map(|i| i.centroid_mm).collect();
        let fraction = r.images.iter().map(|i| i.enclosed()).collect();
        let with = |extra: &[usize]| [&dims[..], extra].concat();
        Ok(PsfLibrary {
            sensor: r.sensor.clone(),
            energies_keV: array(py, &[dims[2]], g.energies.clone())?.unbind(),
            angles_arcmin: array(py, &[dims[0]], g.angles_arcmin.clone())?.unbind(),
            azimuths_deg: array(py, &[dims[1]], g.azimuths_deg.clone())?.unbind(),
            images: array(py, &with(&[w, w]), images)?.unbind(),
            corner: array(py, &with(&[2]), corner)?.unbind(),
            fraction_in_window: array(py, &dims, fraction)?.unbind(),
            centroid_mm: array(py, &with(&[2]), centroid)?.unbind(),
            pixel_pitch_mm: (r.pitch_mm[0], r.pitch_mm[1]),
            focal_length_mm: r.focal_length_mm,
            window: r.window,
            seconds: r.seconds,
            result: r,
            grid: g,
            provenance,
        })
    }
}

#[pymethods]
impl PsfLibrary {
    /// The provenance record of the library.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_json(py, &self.provenance)
    }

    /// Writes the files of `traxer psf` into `folder`: psf.fits (one image per
    /// HDU, the layout SIXTE reads), psf.npy and psf.json, all at once.
    fn save(&self, py: Python<'_>, folder: PathBuf) -> PyResult<()> {
        py.detach(|| traxer::run::save_study(&self.grid, &folder, &self.result, &self.provenance))
            .map_err(|e| to_py(e.into()))
    }

    fn __repr__(&self) -> String {
        format!(
            "traxer.PsfLibrary(sensor {:?}: {} angles × {} azimuths × {} energies, {w} × {w} pixels)",
            self.sensor,
            self.grid.angles_arcmin.len(),
            self.grid.azimuths_deg.len(),
            self.grid.energies.len(),
            w = self.window
        )
    }
}
