//! astropy Quantities at the border. Every physical argument of the Python API
//! takes a plain number in its documented unit (keV, degrees, arcmin, mm, s, AU,
//! GeV⁻¹) or an astropy `Quantity`, converted here before the library sees it;
//! a Quantity of the wrong kind is refused by name, never read as a bare number.
//! astropy is only touched when a Quantity arrives, so it stays optional.

use crate::errors::input;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

/// The unit a plain number of an argument is in.
#[derive(Clone, Copy, Debug)]
pub enum Unit {
    /// Photon or axion energy; a wavelength or frequency Quantity converts too.
    KeV,
    /// Grazing angles.
    Degree,
    /// Off-axis angles.
    Arcmin,
    Mm,
    Second,
    Au,
    /// The axion–photon coupling g_aγ.
    PerGeV,
    /// A pure number (the axion–electron coupling g_ae).
    Dimensionless,
    /// An axion mass (eV); a mass Quantity converts by E = m c².
    Ev,
    Tesla,
    Metre,
    Mbar,
    /// A temperature; °C converts too.
    Kelvin,
    /// Tracking time.
    Hour,
    /// A background rate, counts per keV per cm² per second.
    BackgroundRate,
    /// Solar radii as fractions of the model's R_sun: a length is refused,
    /// because the model's own R_sun, not astropy's, defines the fraction.
    FractionOfRsun,
}

impl Unit {
    /// The unit as astropy parses it.
    fn astropy(self) -> &'static str {
        match self {
            Unit::KeV => "keV",
            Unit::Degree => "deg",
            Unit::Arcmin => "arcmin",
            Unit::Mm => "mm",
            Unit::Second => "s",
            Unit::Au => "AU",
            Unit::PerGeV => "1 / GeV",
            Unit::Ev => "eV",
            Unit::Tesla => "T",
            Unit::Metre => "m",
            Unit::Mbar => "mbar",
            Unit::Kelvin => "K",
            Unit::Hour => "h",
            Unit::BackgroundRate => "1 / (keV cm2 s)",
            Unit::Dimensionless | Unit::FractionOfRsun => "",
        }
    }

    /// What the argument expects, for messages.
    fn expected(self) -> &'static str {
        match self {
            Unit::KeV => "an energy (a plain number is keV; a wavelength Quantity converts too)",
            Unit::Degree => "an angle (a plain number is degrees)",
            Unit::Arcmin => "an angle (a plain number is arcmin)",
            Unit::Mm => "a length (a plain number is mm)",
            Unit::Second => "a time (a plain number is seconds)",
            Unit::Au => "a distance (a plain number is AU)",
            Unit::PerGeV => "a coupling in GeV⁻¹ (a plain number is GeV⁻¹)",
            Unit::Ev => "an axion mass (a plain number is eV; a mass Quantity converts by m c²)",
            Unit::Tesla => "a magnetic field (a plain number is T)",
            Unit::Metre => "a length (a plain number is m)",
            Unit::Mbar => "a pressure (a plain number is mbar)",
            Unit::Kelvin => "a temperature (a plain number is K)",
            Unit::Hour => "a time (a plain number is hours)",
            Unit::BackgroundRate => "a background rate (a plain number is counts keV⁻¹ cm⁻² s⁻¹)",
            Unit::Dimensionless => "a pure number",
            Unit::FractionOfRsun => {
                "fractions of R_sun (pure numbers: divide a length by the solar model's R_sun)"
            }
        }
    }
}

/// True for an astropy `Quantity` (anything with a unit that converts by
/// `to_value`), without importing astropy.
fn is_quantity(v: &Bound<'_, PyAny>) -> bool {
    v.hasattr("unit").unwrap_or(false) && v.hasattr("to_value").unwrap_or(false)
}

/// `v` as plain numbers in `unit`: a Quantity converted, anything else as given.
pub fn plain<'py>(name: &str, v: &Bound<'py, PyAny>, unit: Unit) -> PyResult<Bound<'py, PyAny>> {
    if !is_quantity(v) {
        return Ok(v.clone());
    }
    let py = v.py();
    let kwargs = PyDict::new(py);
    let equivalence = match unit {
        Unit::KeV => Some("spectral"),
        Unit::Ev => Some("mass_energy"),
        Unit::Kelvin => Some("temperature"),
        _ => None,
    };
    if let Some(e) = equivalence {
        let e = py.import("astropy.units")?.call_method0(e)?;
        kwargs.set_item("equivalencies", e)?;
    }
    v.call_method("to_value", (unit.astropy(),), Some(&kwargs))
        .map_err(|_| {
            let given = v
                .getattr("unit")
                .and_then(|u| u.str().map(|s| s.to_string()))
                .unwrap_or_default();
            let given = if given.is_empty() {
                "no unit".into()
            } else {
                given
            };
            input(format!(
                "{name}: a Quantity in {given} is not {}",
                unit.expected()
            ))
        })
}

/// One number in `unit` (a float, an int, a 0-d array or a scalar Quantity).
pub fn number(name: &str, v: &Bound<'_, PyAny>, unit: Unit) -> PyResult<f64> {
    plain(name, v, unit)?.extract::<f64>().map_err(|_| {
        input(format!(
            "{name}={}: expected one number, {}, or an astropy Quantity",
            repr(v),
            unit.expected()
        ))
    })
}

/// `number` for an optional argument (None stays None).
pub fn optional(name: &str, v: Option<&Bound<'_, PyAny>>, unit: Unit) -> PyResult<Option<f64>> {
    v.filter(|v| !v.is_none())
        .map(|v| number(name, v, unit))
        .transpose()
}

/// A 1-D list of numbers in `unit`: a sequence (of numbers or Quantities), an
/// array, an array Quantity, or one number (a list of one).
pub fn numbers(name: &str, v: &Bound<'_, PyAny>, unit: Unit) -> PyResult<Vec<f64>> {
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = v.extract()?;
        return items.iter().map(|i| number(name, i, unit)).collect();
    }
    let p = plain(name, v, unit)?;
    if let Ok(x) = p.extract::<f64>() {
        return Ok(vec![x]);
    }
    let numpy = v.py().import("numpy")?;
    let a = numpy
        .call_method1("asarray", (&p, "float64"))
        .ok()
        .filter(|a| a.getattr("ndim").and_then(|n| n.extract::<usize>()).ok() == Some(1));
    a.and_then(|a| a.extract::<Vec<f64>>().ok()).ok_or_else(|| {
        input(format!(
            "{name}={}: expected a 1-D sequence of numbers, {}",
            repr(v),
            unit.expected()
        ))
    })
}

/// Python's repr of a value, for messages.
fn repr(v: &Bound<'_, PyAny>) -> String {
    v.repr().map_or("?".into(), |r| r.to_string())
}
