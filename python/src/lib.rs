//! The Python module `traxer`: the traxer library seen from Python, with no
//! second implementation of anything. Scenes load and trace through the same
//! calls as the `traxer` binary, so a result equals the CLI's bit for bit for the
//! same scene and seed; images come back as numpy arrays, reports as dicts, and
//! `save` writes the binary's output set.
//!
//! Data flow: Python arguments → checked and converted here ([`convert`], astropy Quantities by [`units`]) → the traxer library
//! (scene, trace, studies, analysis, output) with the GIL released while it
//! computes → numpy arrays and dicts; errors become the exceptions of [`errors`].
//! Built by maturin (python/pyproject.toml); its type hints are traxer.pyi.

#![deny(unsafe_code)]

mod analysis;
mod compare;
mod convert;
mod effective_area;
mod errors;
mod fit;
mod focus;
mod grid;
mod magnet;
mod psf;
mod result;
mod run;
mod scene;
mod signal;
mod solar;
mod systematics;
mod units;

use pyo3::prelude::*;

/// traxer: an X-ray raytracer for the grazing-incidence telescopes of axion
/// helioscopes, on Intel Embree.
///
/// Load a scene with `traxer.Scene(path, defines={...})` and trace it with
/// `scene.trace(photons, seed=1)`; the result holds each sensor's image as numpy
/// arrays and `result.save(folder)` writes the same files as `traxer trace`.
/// Also: `traxer.reflectivity`, `traxer.eef`, `Scene.effective_area`,
/// `Scene.psf_library`, `Scene.systematics` and `traxer.SolarEmission`.
#[pymodule]
#[pyo3(name = "traxer")]
fn traxer_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("embree_version", scene::embree_version()?)?;
    m.add("git_hash", traxer::run::git_hash())?;
    // Notes of slow first-time work (a reflectivity table built and cached) go
    // to Python's stderr, so a notebook shows them too.
    traxer::progress::set_notice_sink(|message| {
        Python::attach(|py| {
            let line = format!("traxer: {message}\n");
            let _ = py
                .import("sys")
                .and_then(|sys| sys.getattr("stderr"))
                .and_then(|err| err.call_method1("write", (line,)));
        })
    });
    errors::register(m)?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<result::TraceResult>()?;
    m.add_class::<result::SensorImage>()?;
    m.add_class::<grid::GridImage>()?;
    m.add_class::<effective_area::EffectiveArea>()?;
    m.add_class::<psf::PsfLibrary>()?;
    m.add_class::<systematics::Systematics>()?;
    m.add_class::<compare::Comparison>()?;
    m.add_class::<focus::FocusScan>()?;
    m.add_class::<fit::FigureErrorFit>()?;
    m.add_class::<solar::SolarEmission>()?;
    m.add_function(wrap_pyfunction!(run::resume, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::reflectivity, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::eef, m)?)?;
    m.add_function(wrap_pyfunction!(magnet::conversion_probability, m)?)?;
    m.add_function(wrap_pyfunction!(signal::signal, m)?)?;
    m.add_function(wrap_pyfunction!(signal::reach, m)?)?;
    Ok(())
}
