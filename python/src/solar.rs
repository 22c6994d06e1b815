//! `traxer.SolarEmission`: a solar axion emission table (the built-in one, one
//! computed from a standard solar model, or one read from a CSV), as `traxer
//! solar-flux` makes and reads them, with its spectrum and flux at a distance.

use crate::convert::array;
use crate::errors::{input, lib};
use crate::units::{numbers, optional, Unit};
use pyo3::prelude::*;
use std::path::PathBuf;
use traxer::constants::AU_CM;
use traxer::files::atomic_write;
use traxer::source::sun::builtin::{
    self, builtin_emission_of, model_emission, AxionEmission, BuiltinModel, EmissionPart,
};
use traxer::source::sun::opacity_project::OpacityTables;
use traxer::source::sun::{EmissionTable, SolarModel};

/// A solar axion emission table w(r, E) on a radius × energy grid.
///
/// `radii`: fractions of the solar radius; `energies_keV`; `rates` [radius,
/// energy]: the rate per axion phase-space mode w (keV), as in the emission CSV
/// that a Sun source's `emission = "FILE.csv"` reads. Make one with
/// `SolarEmission.builtin(emission="primakoff"|"abc"|"primakoff+abc", g_agamma=,
/// g_ae=)`, `.from_model(path, energies_keV, ...)` or `.from_csv(path)`;
/// `process_spectra()` gives dΦ/dE per process (Primakoff, atomic, electron–ion,
/// electron–electron, Compton, ABC).
#[pyclass(module = "traxer", frozen)]
pub struct SolarEmission {
    table: EmissionTable,
    parts: Vec<EmissionPart>,
    /// Where the table comes from.
    #[pyo3(get)]
    description: String,
    /// The couplings it is for.
    #[pyo3(get)]
    coupling: String,
}

impl From<AxionEmission> for SolarEmission {
    fn from(e: AxionEmission) -> SolarEmission {
        SolarEmission {
            table: e.table,
            parts: e.parts,
            description: e.description,
            coupling: e.coupling,
        }
    }
}

/// (g_aγ, g_ae) for the processes that `emission` names, checked as the CLI and
/// scenes check them (`builtin::checked_couplings`): a coupling for a process
/// the emission lacks is refused, never ignored.
fn couplings(
    emission: &str,
    g_agamma: Option<&Bound<'_, PyAny>>,
    g_ae: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Option<f64>, Option<f64>)> {
    let g_agamma = optional("g_agamma", g_agamma, Unit::PerGeV)?;
    let g_ae = optional("g_ae", g_ae, Unit::Dimensionless)?;
    let names = builtin::CouplingNames {
        assign: " = ",
        emission: "emission",
        g_agamma: "g_agamma",
        g_ae: "g_ae",
    };
    builtin::checked_couplings(emission, g_agamma, g_ae, &names).map_err(input)
}

/// A distance from the Sun (AU, or a length Quantity) checked, in cm.
fn au(distance_au: Option<&Bound<'_, PyAny>>) -> PyResult<f64> {
    let distance_au = optional("distance_au", distance_au, Unit::Au)?.unwrap_or(1.0);
    traxer::source::sun::check_distance_au("distance_au =", distance_au).map_err(input)?;
    Ok(distance_au * AU_CM)
}

#[pymethods]
impl SolarEmission {
    /// The built-in emission of the B16-AGSS09met standard solar model (or
    /// `solar_model="b16_gs98"`): "primakoff" (g_aγ in GeV⁻¹), "abc" (the
    /// axion–electron processes, g_ae) or "primakoff+abc"; fluxes scale as the
    /// couplings squared. `g_agamma` may be a Quantity in 1/GeV.
    #[staticmethod]
    #[pyo3(signature = (emission = "primakoff", g_agamma = None, g_ae = None, solar_model = "b16_agss09met"), text_signature = "(emission=\"primakoff\", g_agamma=1e-10, g_ae=1e-13, solar_model=\"b16_agss09met\")")]
    fn builtin(
        emission: &str,
        g_agamma: Option<&Bound<'_, PyAny>>,
        g_ae: Option<&Bound<'_, PyAny>>,
        solar_model: &str,
    ) -> PyResult<SolarEmission> {
        let (p, a) = couplings(emission, g_agamma, g_ae)?;
        let model =
            BuiltinModel::parse(solar_model).map_err(|e| input(format!("solar_model = {e}")))?;
        Ok(builtin_emission_of(model, p, a).map_err(lib)?.into())
    }

    /// The emission of a standard solar model file in the B16 format, on
    /// `energies_keV` (cell centres) and `radii` (fractions of R_sun; None: every
    /// shell of the model file). ABC needs `opacities`, the folder of the Opacity
    /// Project tables (e.g. ../shared/solar/op).
    #[staticmethod]
    #[pyo3(signature = (path, energies_keV, radii = None, emission = "primakoff", opacities = None, g_agamma = None, g_ae = None), text_signature = "(path, energies_keV, radii=None, emission=\"primakoff\", opacities=None, g_agamma=1e-10, g_ae=1e-13)")]
    #[allow(non_snake_case, clippy::too_many_arguments)]
    fn from_model(
        py: Python<'_>,
        path: PathBuf,
        energies_keV: &Bound<'_, PyAny>,
        radii: Option<&Bound<'_, PyAny>>,
        emission: &str,
        opacities: Option<PathBuf>,
        g_agamma: Option<&Bound<'_, PyAny>>,
        g_ae: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<SolarEmission> {
        let (p, a) = couplings(emission, g_agamma, g_ae)?;
        let energies_keV = numbers("energies_keV", energies_keV, Unit::KeV)?;
        let radii = radii
            .filter(|r| !r.is_none())
            .map(|r| numbers("radii", r, Unit::FractionOfRsun))
            .transpose()?;
        let model = SolarModel::read(&path).map_err(lib)?;
        let radii = radii.unwrap_or_else(|| model.shells.iter().map(|s| s.radius).collect());
        EmissionTable::check_grid(&radii, &energies_keV)
            .map_err(|e| input(format!("radii/energies_keV: {e}")))?;
        let op = match (opacities, a) {
            (Some(dir), Some(_)) => Some(OpacityTables::read(&dir).map_err(lib)?),
            (None, Some(_)) => {
                return Err(input(
                    "the ABC emission needs opacities= (the Opacity Project tables' folder)",
                ))
            }
            _ => None,
        };
        let name = path.display().to_string();
        let e = py
            .detach(|| model_emission(&model, &name, op.as_ref(), &radii, &energies_keV, p, a))
            .map_err(lib)?;
        Ok(e.into())
    }

    /// dΦ/dE per process at the grid's energies (axions cm⁻² s⁻¹ keV⁻¹ at
    /// `distance_au`): a dict with "primakoff", "atomic", "electron_ion",
    /// "electron_electron", "compton" and "abc" as the emission has them (empty
    /// for a table read from a CSV).
    #[pyo3(signature = (distance_au = None), text_signature = "($self, distance_au=1.0)")]
    fn process_spectra<'py>(
        &self,
        py: Python<'py>,
        distance_au: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let scale = (AU_CM / au(distance_au)?).powi(2);
        let d = pyo3::types::PyDict::new(py);
        for p in &self.parts {
            let s: Vec<f64> = p.spectrum_1au.iter().map(|x| x * scale).collect();
            d.set_item(&p.name, array(py, &[s.len()], s)?)?;
        }
        Ok(d)
    }

    /// An emission table CSV (columns Radius, Energy [keV], emRates).
    #[staticmethod]
    fn from_csv(path: PathBuf) -> PyResult<SolarEmission> {
        Ok(SolarEmission {
            table: EmissionTable::read_csv(&path).map_err(lib)?,
            parts: Vec::new(),
            description: path.display().to_string(),
            coupling: "the table's coupling".into(),
        })
    }

    /// Radii of the grid, fractions of R_sun.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(py, &[self.table.radii.len()], self.table.radii.clone())
    }

    /// Energies of the grid, keV.
    #[getter]
    #[allow(non_snake_case)]
    fn energies_keV<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(
            py,
            &[self.table.energies.len()],
            self.table.energies.clone(),
        )
    }

    /// w(r, E) in keV, [radius, energy].
    #[getter]
    fn rates<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let t = &self.table;
        array(py, &[t.radii.len(), t.energies.len()], t.rates.clone())
    }

    /// dΦ/dE at the grid's energies, axions cm⁻² s⁻¹ keV⁻¹, at `distance_au`.
    #[pyo3(signature = (distance_au = None), text_signature = "($self, distance_au=1.0)")]
    fn spectrum<'py>(
        &self,
        py: Python<'py>,
        distance_au: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let s = self.table.spectrum_at(au(distance_au)?);
        array(py, &[s.len()], s)
    }

    /// Axions per second emitted by the Sun with energies in [e_min_keV,
    /// e_max_keV] (None: no upper limit). Energies may be astropy Quantities.
    #[pyo3(signature = (e_min_keV = None, e_max_keV = None), text_signature = "($self, e_min_keV=0.0, e_max_keV=None)")]
    #[allow(non_snake_case)]
    fn luminosity(
        &self,
        e_min_keV: Option<&Bound<'_, PyAny>>,
        e_max_keV: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<f64> {
        let e_min_keV = optional("e_min_keV", e_min_keV, Unit::KeV)?.unwrap_or(0.0);
        let e_max_keV = optional("e_max_keV", e_max_keV, Unit::KeV)?.unwrap_or(f64::INFINITY);
        if e_min_keV.is_nan() || e_max_keV.is_nan() || e_min_keV > e_max_keV {
            return Err(input("expected e_min_keV ≤ e_max_keV"));
        }
        Ok(self.table.luminosity(e_min_keV, e_max_keV))
    }

    /// Axion flux, cm⁻² s⁻¹, at `distance_au` with energies in [e_min_keV,
    /// e_max_keV] (None: no upper limit). The distance and energies may be
    /// astropy Quantities.
    #[pyo3(signature = (distance_au = None, e_min_keV = None, e_max_keV = None), text_signature = "($self, distance_au=1.0, e_min_keV=0.0, e_max_keV=None)")]
    #[allow(non_snake_case)]
    fn flux(
        &self,
        distance_au: Option<&Bound<'_, PyAny>>,
        e_min_keV: Option<&Bound<'_, PyAny>>,
        e_max_keV: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<f64> {
        let d = au(distance_au)?;
        Ok(self.luminosity(e_min_keV, e_max_keV)? / (4.0 * std::f64::consts::PI * d * d))
    }

    /// Writes the table as an emission CSV (atomically), for a Sun source's
    /// `emission = "FILE.csv"`.
    fn save_csv(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let csv = self.table.to_csv(&format!(
            "{} (written by traxer {} from Python)",
            self.description,
            env!("CARGO_PKG_VERSION")
        ));
        py.detach(|| atomic_write(&path, csv.as_bytes()))
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(format!("{}: {e}", path.display())))
    }

    fn __repr__(&self) -> String {
        format!(
            "traxer.SolarEmission({}: {} radii × {} energies)",
            self.description,
            self.table.radii.len(),
            self.table.energies.len()
        )
    }
}
