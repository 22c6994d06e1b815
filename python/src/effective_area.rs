//! `Scene.effective_area` and `traxer.EffectiveArea`: the sweep of `traxer
//! effective-area` (same photons, same numbers) as numpy arrays over
//! [angle, energy], and `EffectiveArea.save`, which writes the CLI's files.

use crate::convert::{array, to_json};
use crate::errors::to_py;
use crate::scene::Loaded;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;
use traxer::history::PathClass;
use traxer::output::Provenance;
use traxer::studies::effective_area::{AreaResult, AreaSweep};

/// Runs the sweep with the GIL released (into `out` when given, as the CLI).
pub fn run(
    py: Python<'_>,
    loaded: Arc<Loaded>,
    s: AreaSweep,
    place: (Option<PathBuf>, bool),
    progress: bool,
) -> PyResult<EffectiveArea> {
    let (result, provenance) =
        crate::run::run_study(py, &loaded, (&s, "effective_area"), place, progress)?;
    EffectiveArea::new(py, result, s, provenance)
}

/// The effective area of a telescope over energies and off-axis angles.
///
/// Arrays over [angle, energy]: `area_cm2` and its Monte Carlo standard error
/// `error_cm2`; `by_class_cm2` [angle, energy, class] split by photon path
/// (`classes`: direct, front_rear, front_only, rear_only, other). Per angle:
/// `geometric_area_cm2` (every reflectivity and transmission 1), `quality` (a
/// dict of centroid and 50/80/90 % diameters, or None), `on_sensor` and
/// `counted` photons. `aperture_cm2`: the beam's cross-section on axis.
#[pyclass(module = "traxer", frozen)]
#[allow(non_snake_case)]
pub struct EffectiveArea {
    /// The sensor counted on.
    #[pyo3(get)]
    pub sensor: String,
    /// The energies, keV.
    #[pyo3(get)]
    pub energies_keV: Py<PyAny>,
    /// The off-axis angles, arcmin.
    #[pyo3(get)]
    pub angles_arcmin: Py<PyAny>,
    /// The effective area, cm², [angle, energy].
    #[pyo3(get)]
    pub area_cm2: Py<PyAny>,
    /// The Monte Carlo standard error of `area_cm2`, cm².
    #[pyo3(get)]
    pub error_cm2: Py<PyAny>,
    /// The area split by photon path, cm², [angle, energy, class], classes as in `classes`.
    #[pyo3(get)]
    pub by_class_cm2: Py<PyAny>,
    /// The photon-path classes: direct, front_rear, front_only, rear_only, other.
    #[pyo3(get)]
    pub classes: Vec<&'static str>,
    /// Per angle: the area with every reflectivity and transmission 1, cm².
    #[pyo3(get)]
    pub geometric_area_cm2: Py<PyAny>,
    /// Per angle: the image's centroid and 50/80/90 % diameters (a dict), or None.
    #[pyo3(get)]
    pub quality: Vec<Py<PyAny>>,
    /// Per angle: photons that reached the sensor.
    #[pyo3(get)]
    pub on_sensor: Vec<u64>,
    /// Per angle: photons counted (within `radius_mm` if given).
    #[pyo3(get)]
    pub counted: Vec<u64>,
    /// What the area counts, in words: X-rays reaching the sensor, or on a
    /// gas detector X-rays converting in its gas (the trace's rate).
    #[pyo3(get)]
    pub counts: String,
    /// The beam's cross-section on axis, cm².
    #[pyo3(get)]
    pub aperture_cm2: f64,
    /// The counting radius around the image centroid (mm), or None.
    #[pyo3(get)]
    pub radius_mm: Option<f64>,
    /// Seconds spent tracing.
    #[pyo3(get)]
    pub seconds: f64,
    /// Worker threads used (the result does not depend on them).
    #[pyo3(get)]
    pub threads: usize,
    result: AreaResult,
    sweep: AreaSweep,
    provenance: Provenance,
}

impl EffectiveArea {
    fn new(
        py: Python<'_>,
        r: AreaResult,
        s: AreaSweep,
        provenance: Provenance,
    ) -> PyResult<EffectiveArea> {
        let (na, ne) = (r.angles.len(), s.energies.len());
        let points = || r.angles.iter().flat_map(|a| a.points.iter());
        let area = points().map(|p| p.area_cm2).collect();
        let error = points().map(|p| p.error_cm2).collect();
        let by_class = points().flat_map(|p| p.by_class_cm2).collect();
        let quality = r
            .angles
            .iter()
            .map(|a| to_json(py, &a.quality).map(Bound::unbind))
            .collect::<PyResult<_>>()?;
        Ok(EffectiveArea {
            sensor: r.sensor.clone(),
            energies_keV: array(py, &[ne], s.energies.clone())?.unbind(),
            angles_arcmin: array(py, &[na], s.angles_arcmin.clone())?.unbind(),
            area_cm2: array(py, &[na, ne], area)?.unbind(),
            error_cm2: array(py, &[na, ne], error)?.unbind(),
            by_class_cm2: array(py, &[na, ne, PathClass::ALL.len()], by_class)?.unbind(),
            classes: PathClass::ALL.iter().map(|c| c.name()).collect(),
            geometric_area_cm2: array(
                py,
                &[na],
                r.angles.iter().map(|a| a.geometric_area_cm2).collect(),
            )?
            .unbind(),
            quality,
            on_sensor: r.angles.iter().map(|a| a.on_sensor).collect(),
            counted: r.angles.iter().map(|a| a.counted).collect(),
            counts: r.counts.clone(),
            aperture_cm2: r.aperture_cm2,
            radius_mm: s.radius_mm,
            seconds: r.seconds,
            threads: r.threads,
            result: r,
            sweep: s,
            provenance,
        })
    }
}

#[pymethods]
impl EffectiveArea {
    /// The provenance record of the sweep.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_json(py, &self.provenance)
    }

    /// Writes the files of `traxer effective-area` into `folder`:
    /// effective_area.csv, off_axis.csv, effective_area.json, the plots
    /// effective_area.png, vignetting.png and off_axis.png, and (with two
    /// energies or more) one OGIP ARF per angle, all at once.
    fn save(&self, py: Python<'_>, folder: PathBuf) -> PyResult<()> {
        py.detach(|| traxer::run::save_study(&self.sweep, &folder, &self.result, &self.provenance))
            .map_err(|e| to_py(e.into()))
    }

    fn __repr__(&self) -> String {
        format!(
            "traxer.EffectiveArea(sensor {:?}: {} angles × {} energies)",
            self.sensor,
            self.result.angles.len(),
            self.result.angles.first().map_or(0, |a| a.points.len())
        )
    }
}
