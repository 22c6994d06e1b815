//! `Scene.compare` and `traxer.Comparison`: the analytic scene against meshes
//! of it, as `traxer compare` (same photons, same rows), with the rows as
//! dicts, the CLI's Markdown table, and `Comparison.save`, which writes the
//! CLI's files.

use crate::convert::json;
use crate::errors::to_py;
use crate::scene::Loaded;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use traxer::output::{
    compare_markdown, compare_rows_json, write_compare, Provenance, COMPARE_FILES,
};
use traxer::scene::{Representation, Scene};
use traxer::studies::compare::{variants, CompareStudy, Row};
use traxer::studies::StudyError;

/// What a comparison traces: tessellations and other scene files.
pub struct Variants {
    pub resolutions: Vec<traxer::geometry::Resolution>,
    pub also: Vec<PathBuf>,
}

/// Traces the comparison with the GIL released (into `out` when given, as
/// the CLI). Each variant is loaded with the scene's variables.
pub fn run(
    py: Python<'_>,
    loaded: Arc<Loaded>,
    runs: Variants,
    sampling: traxer::studies::Sampling,
    place: (Option<PathBuf>, bool),
    progress: bool,
) -> PyResult<Comparison> {
    let shown = &loaded.scene;
    let load = |path: &Path, repr: Representation| -> Result<Scene, StudyError> {
        Ok(Scene::load_as(
            &loaded.device,
            path,
            &shown.overrides,
            repr,
        )?)
    };
    let study = CompareStudy::new(
        variants(&shown.path, &runs.resolutions, &runs.also),
        sampling,
        &load,
    );
    let (rows, provenance) =
        crate::run::run_study(py, &loaded, (&study, "compare"), place, progress)?;
    Ok(Comparison { rows, provenance })
}

/// The analytic scene against meshes of it (`Scene.compare`).
///
/// `rows`: each row's representation, triangles, image quality
/// (`image_quality`: centroid and 50/80/90 % diameters), the diameters' and
/// photons' differences to the analytic row (per cent), photons per second
/// and seconds — the rows of compare.json. `markdown` is the table `traxer
/// compare` prints.
#[pyclass(module = "traxer", frozen)]
pub struct Comparison {
    rows: Vec<Row>,
    provenance: Provenance,
}

#[pymethods]
impl Comparison {
    /// One dict per traced variant, the analytic scene first.
    #[getter]
    fn rows<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json(py, &serde_json::Value::Array(compare_rows_json(&self.rows)))
    }

    /// The table `traxer compare` prints.
    #[getter]
    fn markdown(&self) -> String {
        compare_markdown(&self.rows)
    }

    /// The provenance record of the comparison.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::convert::to_json(py, &self.provenance)
    }

    /// Writes the files of `traxer compare` into `folder`: compare.csv and
    /// compare.json, both at once.
    fn save(&self, py: Python<'_>, folder: PathBuf) -> PyResult<()> {
        py.detach(|| -> anyhow::Result<()> {
            let out = traxer::run::results_folder(&folder, &COMPARE_FILES)?;
            traxer::run::write_results_folder(out, |dir| {
                write_compare(dir, &self.rows, &self.provenance).map(|_| ())
            })?;
            Ok(())
        })
        .map_err(to_py)
    }

    fn __repr__(&self) -> String {
        let labels: Vec<&str> = self.rows.iter().map(|r| r.label.as_str()).collect();
        format!("traxer.Comparison({})", labels.join(", "))
    }
}
