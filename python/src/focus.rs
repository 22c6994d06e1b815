//! `Scene.focus` and `traxer.FocusScan`: the focus scan of `traxer focus`
//! (same positions, same photons, same diameters) with its diameters as numpy
//! arrays, the defocus fits as dicts, and `FocusScan.save`, which writes the
//! CLI's files.

use crate::convert::{array, json};
use crate::errors::to_py;
use crate::scene::Loaded;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;
use traxer::output::{write_focus, Provenance, FOCUS_FILES};
use traxer::scene::Scene;
use traxer::studies::focus::{FocusScan as Scan, FocusStudy, FocusSweep};
use traxer::studies::StudyError;

/// Traces the scan with the GIL released (into `out` when given, as the CLI):
/// the scene loaded again at each value of the variable.
pub fn run(
    py: Python<'_>,
    loaded: Arc<Loaded>,
    (sweep, cfg): (FocusSweep, traxer::trace::RunConfig),
    place: (Option<PathBuf>, bool),
    progress: bool,
) -> PyResult<FocusScan> {
    let shown = &loaded.scene;
    let load = |extra: &[String]| -> Result<Scene, StudyError> {
        let defines = traxer::scene::merged_overrides(&shown.overrides, extra);
        Ok(Scene::load(&loaded.device, &shown.path, &defines)?)
    };
    let study = FocusStudy::new(sweep, cfg, &load).map_err(crate::errors::lib)?;
    let (scan, provenance) =
        crate::run::run_study(py, &loaded, (&study, "focus"), place, progress)?;
    FocusScan::new(py, scan, &study, provenance)
}

/// A focus scan: the image's diameters at each value of the scene variable
/// that places the sensor (`Scene.focus`).
///
/// `values` the variable's values; `hpd_mm`, `d80_mm`, `d90_mm` the
/// diameters there (NaN where no photon reached the sensor);
/// `photons_on_sensor`; `fits` the defocus fit of each diameter,
/// D(z)² = d0² + slope² (z − z0)², as a dict (`z0`: the best focus, with
/// `z0_std_error`), or {"error": …} where it failed; `clipped` the values where
/// fewer photons reached the sensor than elsewhere (the image larger than the
/// sensor there).
#[pyclass(module = "traxer", frozen)]
#[allow(non_snake_case)]
pub struct FocusScan {
    /// The scene variable swept.
    #[pyo3(get)]
    pub variable: String,
    /// The sensor measured.
    #[pyo3(get)]
    pub sensor: String,
    /// The variable's values.
    #[pyo3(get)]
    pub values: Py<PyAny>,
    /// Half-power diameter (mm) at each value (NaN without an image).
    #[pyo3(get)]
    pub hpd_mm: Py<PyAny>,
    /// 80 % diameter (mm) at each value.
    #[pyo3(get)]
    pub d80_mm: Py<PyAny>,
    /// 90 % diameter (mm) at each value.
    #[pyo3(get)]
    pub d90_mm: Py<PyAny>,
    /// Photons recorded on the sensor at each value.
    #[pyo3(get)]
    pub photons_on_sensor: Py<PyAny>,
    /// The values where the image is probably larger than the sensor.
    #[pyo3(get)]
    pub clipped: Vec<f64>,
    scan: Scan,
    range: (f64, f64),
    provenance: Provenance,
}

impl FocusScan {
    fn new(
        py: Python<'_>,
        scan: Scan,
        study: &FocusStudy,
        provenance: Provenance,
    ) -> PyResult<FocusScan> {
        let n = scan.steps.len();
        let column = |f: fn(&traxer::analysis::ImageQuality) -> f64| -> PyResult<Py<PyAny>> {
            let v = scan
                .steps
                .iter()
                .map(|s| s.quality.as_ref().map_or(f64::NAN, f))
                .collect();
            Ok(array(py, &[n], v)?.unbind())
        };
        let counts: Vec<u64> = scan.steps.iter().map(|s| s.on_sensor).collect();
        Ok(FocusScan {
            variable: study.var.clone(),
            sensor: scan.sensor.clone(),
            values: array(py, &[n], scan.steps.iter().map(|s| s.value).collect())?.unbind(),
            hpd_mm: column(|q| q.hpd_mm)?,
            d80_mm: column(|q| q.d80_mm)?,
            d90_mm: column(|q| q.d90_mm)?,
            photons_on_sensor: array(py, &[n], counts)?.unbind(),
            clipped: scan.clipped.clone(),
            range: (study.sweep.from, study.sweep.to),
            scan,
            provenance,
        })
    }
}

#[pymethods]
impl FocusScan {
    /// The defocus fit of each diameter ("hpd", "d80", "d90"): z0 (the best
    /// focus), z0_std_error, d0, slope, rms_relative_residual, ... (as
    /// focus.json's fit_*), or {"error": why} where the fit failed.
    #[getter]
    fn fits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let fit = |k: usize| match &self.scan.fits[k].1 {
            Ok(f) => serde_json::json!(f),
            Err(e) => serde_json::json!({ "error": e.to_string() }),
        };
        json(
            py,
            &serde_json::json!({ "hpd": fit(0), "d80": fit(1), "d90": fit(2) }),
        )
    }

    /// The provenance record of the scan.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::convert::to_json(py, &self.provenance)
    }

    /// Writes the files of `traxer focus` into `folder`: focus.csv, focus.json
    /// and focus.png, all at once.
    fn save(&self, py: Python<'_>, folder: PathBuf) -> PyResult<()> {
        py.detach(|| -> anyhow::Result<()> {
            let out = traxer::run::results_folder(&folder, &FOCUS_FILES)?;
            traxer::run::write_results_folder(out, |dir| {
                write_focus(
                    dir,
                    &self.scan,
                    &self.variable,
                    self.range,
                    &self.provenance,
                )
                .map(|_| ())
            })?;
            Ok(())
        })
        .map_err(to_py)
    }

    fn __repr__(&self) -> String {
        format!(
            "traxer.FocusScan({} over {} values on sensor {:?})",
            self.variable,
            self.scan.steps.len(),
            self.sensor
        )
    }
}
