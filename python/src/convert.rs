//! Conversions at the border: Python values into the library's settings (scene
//! variables, thread counts, paths) and the library's results into Python (JSON
//! reports as dicts, vectors as numpy arrays that take over the Rust buffer
//! without a copy), and the optional progress bar.

use crate::errors::input;
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyDict, PyList, PyString, PyTuple};

/// Checks a thread count: 0 (one per core) to `traxer::run::MAX_THREADS`.
pub fn threads(n: usize) -> PyResult<usize> {
    traxer::run::check_threads(n, traxer::run::FrontEnd::Python).map_err(|e| input(e.0))
}

/// Scene variables as the CLI's `-D name=value`: from a mapping {name: value} or
/// from a sequence of "name=value" strings. Values become TOML: booleans,
/// integers and floats as such, strings quoted (so "1.5" stays a string), lists
/// and tuples as arrays.
pub fn defines(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(Vec::new());
    };
    if let Ok(map) = obj.cast::<PyDict>() {
        let mut out = Vec::new();
        for (k, v) in map.iter() {
            let name: String = k
                .extract()
                .map_err(|_| input(format!("defines: the key {k} is not a variable name (str)")))?;
            out.push(format!("{name}={}", toml_value(&name, &v)?));
        }
        return Ok(out);
    }
    if obj.is_instance_of::<PyString>() {
        return Err(input(
            "defines: expected a dict {name: value} or a list of \"name=value\" strings, not one string",
        ));
    }
    let items: Vec<String> = obj.extract().map_err(|_| {
        input("defines: expected a dict {name: value} or a list of \"name=value\" strings")
    })?;
    for d in &items {
        match d.split_once('=') {
            Some((k, _)) if !k.trim().is_empty() => {}
            _ => return Err(input(format!("defines: expected name=value, got `{d}`"))),
        }
    }
    Ok(items)
}

/// A Python value as TOML text for the variable `name`.
fn toml_value(name: &str, v: &Bound<'_, PyAny>) -> PyResult<String> {
    // A scene variable has no unit of its own: the scene file decides what a
    // number means (mm, keV, degrees), so a Quantity is refused, not guessed.
    if v.hasattr("unit").unwrap_or(false) && v.hasattr("to_value").unwrap_or(false) {
        return Err(input(format!(
            "defines: `{name}` = {v} is an astropy Quantity; scene variables take plain numbers in the units the scene file uses them in (mm, keV, degrees: see its [vars] comments), e.g. {{\"{name}\": q.to_value(\"mm\")}}"
        )));
    }
    if let Ok(b) = v.extract::<bool>() {
        return Ok(b.to_string());
    }
    if v.is_instance_of::<PyString>() {
        let s: String = v.extract()?;
        // A JSON string is a TOML basic string (the same escapes).
        return Ok(serde_json::to_string(&s).expect("a string is JSON"));
    }
    if let Ok(i) = v.extract::<i64>() {
        return Ok(i.to_string());
    }
    if let Ok(f) = v.extract::<f64>() {
        return Ok(match f {
            f if f.is_nan() => "nan".into(),
            f if f.is_infinite() => if f > 0.0 { "inf" } else { "-inf" }.into(),
            // Debug prints the shortest text that reads back as the same f64.
            f => format!("{f:?}"),
        });
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = v.extract()?;
        let parts = items
            .iter()
            .map(|i| toml_value(name, i))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(format!("[{}]", parts.join(", ")));
    }
    if let Ok(map) = v.cast::<PyDict>() {
        // An inline table, e.g. a mirror's roughness PSD or figure errors.
        let bare = |k: &str| {
            !k.is_empty()
                && k.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        };
        let mut parts = Vec::new();
        for (k, item) in map.iter() {
            let key: String = k.extract().map_err(|_| {
                input(format!(
                    "defines: `{name}`: a table's keys are strings, not {k}"
                ))
            })?;
            if !bare(&key) {
                return Err(input(format!(
                    "defines: `{name}`: key {key:?} is not a name (letters, digits, _ and -)"
                )));
            }
            parts.push(format!("{key} = {}", toml_value(name, &item)?));
        }
        return Ok(format!("{{ {} }}", parts.join(", ")));
    }
    Err(input(format!(
        "defines: `{name}` = {v}: expected a bool, number, string, or a list or dict of them"
    )))
}

/// A JSON value as the Python object `json.loads` makes of it.
pub fn json<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(v).expect("JSON of plain values");
    py.import("json")?.call_method1("loads", (text,))
}

/// Anything serialisable as the Python object of its JSON.
pub fn to_json<'py, T: serde::Serialize>(py: Python<'py>, v: &T) -> PyResult<Bound<'py, PyAny>> {
    json(py, &serde_json::to_value(v).expect("JSON of plain values"))
}

/// A numpy array of `shape` that owns `data` (no copy).
pub fn array<'py, T: numpy::Element>(
    py: Python<'py>,
    shape: &[usize],
    data: Vec<T>,
) -> PyResult<Bound<'py, PyAny>> {
    let a = ArrayD::from_shape_vec(IxDyn(shape), data)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    // Read-only: `flux *= 2` must not leave a result disagreeing with its own
    // quality and with what `save()` writes (copy the array to change it).
    let array = a.into_pyarray(py).into_any();
    array.call_method("setflags", (), Some(&[("write", false)].into_py_dict(py)?))?;
    Ok(array)
}

/// A progress bar on stderr when asked for (and stderr is a terminal), else none.
pub fn progress_bar(total: u64, show: bool) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {human_pos}/{human_len} photons, {per_sec}, {eta} left",
        )
        .expect("a valid template"),
    );
    bar
}

/// A count of photons (or any whole number of things) given as a Python int or
/// an integral float (`1e6`), at least `min`; the message names the argument
/// instead of Python's "can't convert negative int to unsigned".
pub fn count(name: &str, value: &Bound<'_, PyAny>, min: u64) -> PyResult<u64> {
    let n: Option<i128> = if let Ok(i) = value.extract::<i128>() {
        Some(i)
    } else if let Ok(f) = value.extract::<f64>() {
        (f.is_finite() && f.fract() == 0.0 && f.abs() < 1.9e19).then_some(f as i128)
    } else {
        None
    };
    match n {
        Some(n) if n >= min as i128 && n <= u64::MAX as i128 => Ok(n as u64),
        Some(n) => Err(input(format!("{name}={n}: {name} must be ≥ {min}"))),
        None => Err(input(format!(
            "{name}={}: expected a whole number ≥ {min}",
            value.repr().map_or("?".into(), |r| r.to_string())
        ))),
    }
}
