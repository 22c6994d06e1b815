//! `Scene.fit_figure_error` and `traxer.FigureErrorFit`: the figure-error fit
//! of `traxer fit-figure-error` (same evaluations, same photons, same
//! numbers) with fit.json as a dict, the history as dicts, the preset as TOML
//! text, and `FigureErrorFit.save`, which writes the CLI's files.

use crate::convert::json;
use crate::errors::to_py;
use crate::scene::Loaded;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;
use traxer::output::{fit_json, fit_preset_toml, write_fit, FitReport, Provenance, FIT_FILES};
use traxer::scene::Scene;
use traxer::studies::fit::FitSettings;
use traxer::studies::fit_study::{AfterFit, FitOutput, FitStudy};
use traxer::studies::{pick_sensor, StudyError};

/// Runs the fit with the GIL released (into `out` when given, as the CLI);
/// each of `predict` is loaded with the scene's variables.
pub fn run(
    py: Python<'_>,
    loaded: Arc<Loaded>,
    (settings, after): (FitSettings, AfterFit),
    (predict, sensor): (Vec<PathBuf>, Option<String>),
    place: (Option<PathBuf>, bool),
    progress: bool,
) -> PyResult<FigureErrorFit> {
    let shown = &loaded.scene;
    let load = |extra: &[String]| -> Result<Scene, StudyError> {
        let defines = traxer::scene::merged_overrides(&shown.overrides, extra);
        Ok(Scene::load(&loaded.device, &shown.path, &defines)?)
    };
    let predicted = py
        .detach(|| {
            predict
                .iter()
                .map(|p| {
                    let s = Scene::load(&loaded.device, p, &shown.overrides)?;
                    let k = pick_sensor(&s, sensor.as_deref())
                        .map_err(|e| StudyError::Input(format!("predict {}: {e}", p.display())))?;
                    Ok((s, k))
                })
                .collect::<Result<Vec<_>, StudyError>>()
        })
        .map_err(crate::errors::lib)?;
    let study = py
        .detach(|| FitStudy::new(shown, settings, after, &load, predicted))
        .map_err(crate::errors::lib)?;
    let (output, provenance) =
        crate::run::run_study(py, &loaded, (&study, "fit_figure_error"), place, progress)?;
    Ok(FigureErrorFit {
        settings: study.settings.clone(),
        after: study.after.clone(),
        output,
        provenance,
    })
}

/// A figure-error fit (`Scene.fit_figure_error`).
///
/// `summary`: fit.json (the targets, the best evaluation, the seed check,
/// the parameters' errors with their covariance and the predictions);
/// `best`: the best parameters (arcsec, and the wide fraction); `history`:
/// every evaluation in order; `preset`: figure_error.toml's text, a preset
/// for data/figure_errors.toml or a scene's [figure_errors].
#[pyclass(module = "traxer", frozen)]
pub struct FigureErrorFit {
    settings: FitSettings,
    after: AfterFit,
    output: FitOutput,
    provenance: Provenance,
}

impl FigureErrorFit {
    fn report(&self) -> FitReport<'_> {
        FitReport {
            result: &self.output.result,
            settings: &self.settings,
            spread: &self.output.spread,
            extra_seeds: self.after.check_seeds,
            preset_name: &self.after.preset_name,
            fit_seconds: self.output.fit_seconds,
            errors: &self.output.errors,
            predictions: &self.output.predictions,
        }
    }
}

#[pymethods]
impl FigureErrorFit {
    /// fit.json as a dict.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json(py, &fit_json(&self.report(), &self.provenance))
    }

    /// The best parameters: in_plane_narrow, in_plane_wide, out_of_plane
    /// (arcsec) and wide_fraction.
    #[getter]
    fn best<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::convert::to_json(py, &self.output.result.best.parameters)
    }

    /// Every evaluation in order: its index, stage, parameters, diameters and
    /// error (history.csv as dicts).
    #[getter]
    fn history<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::convert::to_json(py, &self.output.result.history)
    }

    /// figure_error.toml's text.
    #[getter]
    fn preset(&self) -> String {
        fit_preset_toml(&self.report(), &self.provenance)
    }

    /// The provenance record of the fit.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::convert::to_json(py, &self.provenance)
    }

    /// Writes the files of `traxer fit-figure-error` into `folder`:
    /// history.csv, figure_error.toml and fit.json, all at once.
    fn save(&self, py: Python<'_>, folder: PathBuf) -> PyResult<()> {
        py.detach(|| -> anyhow::Result<()> {
            let out = traxer::run::results_folder(&folder, &FIT_FILES)?;
            traxer::run::write_results_folder(out, |dir| {
                write_fit(dir, &self.report(), &self.provenance).map(|_| ())
            })?;
            Ok(())
        })
        .map_err(to_py)
    }

    fn __repr__(&self) -> String {
        let p = &self.output.result.best.parameters;
        format!(
            "traxer.FigureErrorFit(in_plane_narrow {:.2}″, in_plane_wide {:.2}″, wide_fraction {:.4}, out_of_plane {:.2}″ after {} evaluations)",
            p.in_plane_narrow,
            p.in_plane_wide,
            p.wide_fraction,
            p.out_of_plane,
            self.output.result.history.len()
        )
    }
}
