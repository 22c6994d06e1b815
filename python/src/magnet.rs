//! `traxer.conversion_probability`: P(a→γ) of a magnet for energies × masses,
//! as `traxer conversion` prints it (the same library calls).

use crate::convert::array;
use crate::errors::input;
use crate::units::{numbers, optional, Unit};
use pyo3::prelude::*;
use traxer::magnet::buffer_gas::BufferGasDesc;
use traxer::magnet::probe::{self, Where};
use traxer::scene::magnet::{check_probe_masses, standalone, MagnetDesc};

/// conversion_probability(energies_keV, masses_eV=None, field_t=None, length_m=None, field_map=None, gas=None, pressure_mbar=None, temperature_k=None, g_agamma=1e-10, at=(0.0, 0.0), bore_average=False, step_mm=None)
///
/// The axion–photon conversion probability P(a→γ) of a magnet, as
/// `traxer conversion`: a uniform field (`field_t` in T over `length_m`) or a
/// field map (`field_map`: a shipped one such as "bykovskiy_201906",
/// BabyIAXO's, or a file of rows x y z Bx By Bz in mm and T), with an optional
/// buffer gas (`gas` a formula, "He" for helium-3 or -4, with `pressure_mbar`
/// and `temperature_k`), at `g_agamma` (GeV⁻¹), along the axial line through
/// `at` (mm) or averaged over the bore (`bore_average`). `masses_eV`: a list
/// (default [0]). Returns a float64 array [energy, mass].
#[pyfunction]
#[pyo3(signature = (energies_keV, masses_eV = None, field_t = None, length_m = None, field_map = None, gas = None, pressure_mbar = None, temperature_k = None, g_agamma = None, at = None, bore_average = false, step_mm = None), text_signature = "(energies_keV, masses_eV=None, field_t=None, length_m=None, field_map=None, gas=None, pressure_mbar=None, temperature_k=None, g_agamma=1e-10, at=(0.0, 0.0), bore_average=False, step_mm=None)")]
#[allow(non_snake_case, clippy::too_many_arguments)]
pub fn conversion_probability<'py>(
    py: Python<'py>,
    energies_keV: &Bound<'py, PyAny>,
    masses_eV: Option<&Bound<'py, PyAny>>,
    field_t: Option<&Bound<'py, PyAny>>,
    length_m: Option<&Bound<'py, PyAny>>,
    field_map: Option<String>,
    gas: Option<String>,
    pressure_mbar: Option<&Bound<'py, PyAny>>,
    temperature_k: Option<&Bound<'py, PyAny>>,
    g_agamma: Option<&Bound<'py, PyAny>>,
    at: Option<&Bound<'py, PyAny>>,
    bore_average: bool,
    step_mm: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    // Plain numbers in the documented units, or astropy Quantities.
    let field_t = optional("field_t", field_t, Unit::Tesla)?;
    let length_m = optional("length_m", length_m, Unit::Metre)?;
    let pressure_mbar = optional("pressure_mbar", pressure_mbar, Unit::Mbar)?;
    let temperature_k = optional("temperature_k", temperature_k, Unit::Kelvin)?;
    let g_agamma = optional("g_agamma", g_agamma, Unit::PerGeV)?.unwrap_or(1e-10);
    let step_mm = optional("step_mm", step_mm, Unit::Mm)?;
    let at = match at.filter(|a| !a.is_none()) {
        None => (0.0, 0.0),
        Some(a) => match numbers("at", a, Unit::Mm)?.as_slice() {
            [x, y] => (*x, *y),
            _ => return Err(input("at: two coordinates (x, y) in mm")),
        },
    };
    let energies = numbers("energies_keV", energies_keV, Unit::KeV)?;
    if let Some(e) = energies.iter().find(|e| !(0.03..=30.0).contains(*e)) {
        return Err(input(format!(
            "energies_keV: {e} keV is outside 0.03–30 keV (the X-ray tables' range)"
        )));
    }
    let masses = match masses_eV {
        None => vec![0.0],
        Some(m) => numbers("masses_eV", m, Unit::Ev)?,
    };
    if field_t.is_some() == field_map.is_some() {
        return Err(input(
            "give the field: field_t (with length_m) or field_map, one of them",
        ));
    }
    let gas = match (gas, pressure_mbar, temperature_k) {
        (None, None, None) => None,
        (Some(f), Some(p), Some(t)) => Some(BufferGasDesc {
            mixture: [(f, 1.0)].into(),
            pressure_mbar: p,
            temperature_k: t,
        }),
        _ => {
            return Err(input(
                "a buffer gas needs gas, pressure_mbar and temperature_k together",
            ))
        }
    };
    let desc = MagnetDesc {
        enabled: true,
        bore: "bore".into(),
        field_t,
        field_direction: None,
        field_map,
        field_map_transform: Vec::new(),
        step_mm,
        axion_mass_ev: 0.0,
        masses_ev: Vec::new(),
        g_agamma,
        gas,
        campaign: None,
    };
    let magnet = standalone(&desc, length_m.map(|l| l * 1000.0)).map_err(input)?;
    check_probe_masses(&magnet, "masses_eV", &masses).map_err(input)?;
    if bore_average && at != (0.0, 0.0) {
        return Err(input(
            "at= places one axial line; bore_average=True averages over the whole bore: give one of them",
        ));
    }
    let place = match bore_average {
        true => Where::BoreAverage {
            rings: traxer::magnet::probe::BORE_AVERAGE_RINGS,
        },
        false => Where::Line([at.0, at.1]),
    };
    let rows = py.detach(|| probe::table(&magnet, place, &energies, &masses));
    array(
        py,
        &[energies.len(), masses.len()],
        rows.iter().map(|r| r.probability).collect(),
    )
}
