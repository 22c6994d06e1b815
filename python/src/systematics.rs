//! `Scene.systematics` and `traxer.Systematics`: the study of `traxer
//! systematics` (same variations, same photons, same numbers) with its table
//! as a dict, its maps as numpy arrays, and `Systematics.save`, which writes
//! the CLI's files.

use crate::convert::{array, json};
use crate::errors::{lib, to_py};
use crate::scene::Loaded;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;
use traxer::output::{systematics_description, write_systematics, Provenance, SYSTEMATICS_FILES};
use traxer::scene::Scene;
use traxer::studies::systematics::{
    self, Request, Settings, Systematics as Study, SystematicsStudy,
};
use traxer::studies::StudyError;

/// Plans and traces the study with the GIL released (into `out` when given,
/// as the CLI): the scene is loaded again for each variation that sets
/// variables (and once, to vary its mirrors, for the figure draws).
pub fn run(
    py: Python<'_>,
    loaded: Arc<Loaded>,
    (req, settings): (Request, Settings),
    place: (Option<PathBuf>, bool),
    progress: bool,
) -> PyResult<Systematics> {
    let shown = &loaded.scene;
    traxer::studies::require_sources(shown).map_err(lib)?;
    systematics::check(&settings).map_err(lib)?;
    let plan = systematics::plan(shown, &req).map_err(lib)?;
    let load = |extra: &[String]| -> Result<Scene, StudyError> {
        let defines = traxer::scene::merged_overrides(&shown.overrides, extra);
        Ok(Scene::load(&loaded.device, &shown.path, &defines)?)
    };
    let study = SystematicsStudy {
        settings,
        plan: &plan,
        load: &load,
        scene_name: shown.name_for_people(),
    };
    let (result, provenance) =
        crate::run::run_study(py, &loaded, (&study, "systematics"), place, progress)?;
    Systematics::new(py, result, provenance, shown.name_for_people())
}

/// The image's systematic uncertainty: the scene traced under each source of
/// uncertainty with the same photons.
///
/// `summary`: each source's σ and mean shift of the flux, the flux in the
/// central square, HPD / 80 % / 90 % and the centroid, the nominal values and
/// the total in quadrature (as systematics.json); `table`: one dict per traced
/// variation (as systematics.csv); the maps [iy, ix] on the sensor's detector
/// grid (or its binned image): `nominal`, `mean`, `sigma` (total),
/// `sigma_by_source` (a dict) and `variations` [variation, iy, ix].
#[pyclass(module = "traxer", frozen)]
pub struct Systematics {
    /// The nominal scene's map, [iy, ix], on the sensor's detector grid (or its
    /// image binned to at most 256 pixels a side).
    #[pyo3(get)]
    pub nominal: Py<PyAny>,
    /// The nominal map plus each source's mean shift.
    #[pyo3(get)]
    pub mean: Py<PyAny>,
    /// The total systematic σ per map pixel (the sources in quadrature).
    #[pyo3(get)]
    pub sigma: Py<PyAny>,
    /// Each source's σ map, by source name.
    #[pyo3(get)]
    pub sigma_by_source: Py<PyAny>,
    /// The total σ over the mean map, per pixel (NaN where the mean is not
    /// positive).
    #[pyo3(get)]
    pub sigma_relative: Py<PyAny>,
    /// The Monte Carlo noise of `sigma`, per pixel, from the two halves of the
    /// photons.
    #[pyo3(get)]
    pub sigma_noise: Py<PyAny>,
    /// Every traced variation's map, [variation, iy, ix], in the order of `table`.
    #[pyo3(get)]
    pub variations: Py<PyAny>,
    /// Seconds spent tracing.
    #[pyo3(get)]
    pub seconds: f64,
    study: Study,
    provenance: Provenance,
    scene_name: String,
}

impl Systematics {
    fn new(
        py: Python<'_>,
        s: Study,
        provenance: Provenance,
        scene_name: String,
    ) -> PyResult<Systematics> {
        let [nx, ny] = s.frame.pixels;
        let by = PyDict::new(py);
        for (e, m) in s.sources.iter().zip(&s.sigma_maps) {
            by.set_item(&e.name, array(py, &[ny, nx], m.clone())?)?;
        }
        let all: Vec<f64> = s
            .outcomes
            .iter()
            .flat_map(|o| o.map.iter().copied())
            .collect();
        Ok(Systematics {
            nominal: array(py, &[ny, nx], s.nominal_map.clone())?.unbind(),
            mean: array(py, &[ny, nx], s.mean_map.clone())?.unbind(),
            sigma: array(py, &[ny, nx], s.sigma_map.clone())?.unbind(),
            sigma_by_source: by.into_any().unbind(),
            sigma_relative: array(py, &[ny, nx], s.relative_sigma_map.clone())?.unbind(),
            sigma_noise: array(
                py,
                &[ny, nx],
                s.noise_map
                    .clone()
                    .unwrap_or_else(|| vec![f64::NAN; nx * ny]),
            )?
            .unbind(),
            variations: array(py, &[s.outcomes.len(), ny, nx], all)?.unbind(),
            seconds: s.facts.seconds,
            study: s,
            provenance,
            scene_name,
        })
    }
}

#[pymethods]
impl Systematics {
    /// Each source's effect, the nominal values and the total (systematics.json).
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json(py, &systematics_description(&self.study, &self.provenance))
    }

    /// One dict per traced variation: source, variation, its settings and quantities.
    #[getter]
    fn table<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let rows: Vec<serde_json::Value> = self
            .study
            .outcomes
            .iter()
            .map(|o| {
                let mut row = serde_json::Map::new();
                row.insert("source".into(), o.source.clone().into());
                row.insert("variation".into(), o.label.clone().into());
                let m = systematics::summary::metrics(o);
                for (name, x) in systematics::METRICS.iter().zip(m) {
                    let v = if x.is_nan() {
                        serde_json::Value::Null
                    } else {
                        x.into()
                    };
                    row.insert(name.to_string(), v);
                }
                row.insert("photons_on_sensor".into(), o.photons_recorded.into());
                serde_json::Value::Object(row)
            })
            .collect();
        json(py, &serde_json::Value::Array(rows))
    }

    /// The provenance record of the study.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::convert::to_json(py, &self.provenance)
    }

    /// Writes the files of `traxer systematics` into `folder`: systematics.csv,
    /// systematics.json, systematics.fits, the map_*.npy and the PNGs, all at once.
    fn save(&self, py: Python<'_>, folder: PathBuf) -> PyResult<()> {
        py.detach(|| -> anyhow::Result<()> {
            let out = traxer::run::results_folder(&folder, &SYSTEMATICS_FILES.all())?;
            traxer::run::write_results_folder(out, |dir| {
                write_systematics(dir, &self.study, &self.scene_name, &self.provenance)
            })?;
            Ok(())
        })
        .map_err(to_py)
    }

    fn __repr__(&self) -> String {
        let names: Vec<&str> = self.study.sources.iter().map(|e| e.name.as_str()).collect();
        format!(
            "traxer.Systematics(sensor {:?}: {} variations of {})",
            self.study.facts.sensor,
            self.study.outcomes.len(),
            names.join(", ")
        )
    }
}
