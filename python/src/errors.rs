//! traxer's errors as Python exceptions: `InputError` (a `ValueError`) for what
//! the user can fix, `SceneError` (an `InputError`) for a scene file with its
//! `file`, `line`, `key` and `message`, `OSError` for files that cannot be written or
//! read, `RuntimeError` for the rest. Never a crash: every library error passes
//! through [`to_py`].

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    traxer,
    InputError,
    PyValueError,
    "Bad input: a setting, a data file, an output folder. The message says which and what is expected."
);
pyo3::create_exception!(
    traxer,
    SceneError,
    InputError,
    "A scene file that cannot be loaded. Attributes: file (path), line (1-based, or None), key (the dotted key of the value at fault, or None), message."
);

/// Adds the exception types to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    Ok(())
}

/// An `InputError` with `message`.
pub fn input(message: impl Into<String>) -> PyErr {
    InputError::new_err(message.into())
}

/// A scene error with its place as attributes.
fn scene_error(py: Python<'_>, e: &traxer::scene::SceneError) -> PyErr {
    let err = SceneError::new_err(e.to_string());
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("file", e.file.display().to_string())?;
        value.setattr("line", e.line)?;
        value.setattr("message", e.message.clone())?;
        value.setattr("key", e.key.clone())
    };
    if let Err(e) = set() {
        return e;
    }
    err
}

/// Converts a library error (with its context) into the matching exception.
pub fn to_py(e: anyhow::Error) -> PyErr {
    Python::attach(|py| {
        if let Some(s) = e
            .chain()
            .find_map(|c| c.downcast_ref::<traxer::scene::SceneError>())
        {
            if e.chain().count() == 1 {
                return scene_error(py, s);
            }
        }
        let message = format!("{e:#}");
        if e.chain().any(traxer::is_bad_input) {
            InputError::new_err(message)
        } else if e.chain().any(|c| c.is::<std::io::Error>()) {
            PyOSError::new_err(message)
        } else {
            PyRuntimeError::new_err(message)
        }
    })
}

/// `to_py` for any error type of the library.
pub fn lib<E: std::error::Error + Send + Sync + 'static>(e: E) -> PyErr {
    to_py(anyhow::Error::new(e))
}
