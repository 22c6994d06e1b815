//! `traxer.SolarEmission`: a solar axion emission table (the built-in one, one
//! computed from a standard solar model, or one read from a CSV), as `traxer
//! solar-flux` makes and reads them, with its spectrum and flux at a distance.

use crate::convert::array;
use crate::errors::{input, lib};
use pyo3::prelude::*;
use std::path::PathBuf;
use traxer::files::atomic_write;
use traxer::source::sun::primakoff::emission_table;
use traxer::source::sun::{
    builtin_table, EmissionTable, SolarModel, AU_CM, BUILTIN_COUPLING, BUILTIN_DESCRIPTION,
};

/// A solar axion emission table w(r, E) on a radius × energy grid.
///
/// `radii`: fractions of the solar radius; `energies_keV`; `rates` [radius,
/// energy]: the rate per axion phase-space mode w (keV), as in the emission CSV
/// that a Sun source's `emission = "FILE.csv"` reads. Make one with
/// `SolarEmission.builtin()`, `.from_model(path, energies_keV)` or
/// `.from_csv(path)`.
#[pyclass(module = "traxer", frozen)]
pub struct SolarEmission {
    table: EmissionTable,
    /// Where the table comes from.
    #[pyo3(get)]
    description: String,
}

fn au(distance_au: f64) -> PyResult<f64> {
    if !(distance_au.is_finite() && distance_au > 0.0) {
        return Err(input(format!(
            "distance_au={distance_au}: expected a positive distance"
        )));
    }
    Ok(distance_au * AU_CM)
}

#[pymethods]
impl SolarEmission {
    /// The built-in table: Primakoff emission of the B16-AGSS09met standard
    /// solar model for g_aγ = 1e-10 GeV⁻¹.
    #[staticmethod]
    fn builtin() -> SolarEmission {
        SolarEmission {
            table: builtin_table().clone(),
            description: format!("{BUILTIN_DESCRIPTION} ({BUILTIN_COUPLING})"),
        }
    }

    /// The Primakoff emission (g_aγ = 1e-10 GeV⁻¹, Debye–Hückel screening) of a
    /// standard solar model file in the B16 format, on `energies_keV` and `radii`
    /// (fractions of R_sun; None: every shell of the model file).
    #[staticmethod]
    #[pyo3(signature = (path, energies_keV, radii = None))]
    #[allow(non_snake_case)]
    fn from_model(
        py: Python<'_>,
        path: PathBuf,
        energies_keV: Vec<f64>,
        radii: Option<Vec<f64>>,
    ) -> PyResult<SolarEmission> {
        let model = SolarModel::read(&path).map_err(lib)?;
        let radii = radii.unwrap_or_else(|| model.shells.iter().map(|s| s.radius).collect());
        EmissionTable::check_grid(&radii, &energies_keV)
            .map_err(|e| input(format!("radii/energies_keV: {e}")))?;
        let table = py.detach(|| emission_table(&model, &radii, &energies_keV));
        Ok(SolarEmission {
            table,
            description: format!(
                "Primakoff emission of {} ({BUILTIN_COUPLING})",
                path.display()
            ),
        })
    }

    /// An emission table CSV (columns Radius, Energy [keV], emRates).
    #[staticmethod]
    fn from_csv(path: PathBuf) -> PyResult<SolarEmission> {
        Ok(SolarEmission {
            table: EmissionTable::read_csv(&path).map_err(lib)?,
            description: path.display().to_string(),
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
    #[pyo3(signature = (distance_au = 1.0))]
    fn spectrum<'py>(&self, py: Python<'py>, distance_au: f64) -> PyResult<Bound<'py, PyAny>> {
        let s = self.table.spectrum_at(au(distance_au)?);
        array(py, &[s.len()], s)
    }

    /// Axions per second emitted by the Sun with energies in [e_min_keV, e_max_keV].
    #[pyo3(signature = (e_min_keV = 0.0, e_max_keV = f64::INFINITY))]
    #[allow(non_snake_case)]
    fn luminosity(&self, e_min_keV: f64, e_max_keV: f64) -> PyResult<f64> {
        if e_min_keV.is_nan() || e_max_keV.is_nan() || e_min_keV > e_max_keV {
            return Err(input("expected e_min_keV ≤ e_max_keV"));
        }
        Ok(self.table.luminosity(e_min_keV, e_max_keV))
    }

    /// Axion flux, cm⁻² s⁻¹, at `distance_au` with energies in [e_min_keV, e_max_keV].
    #[pyo3(signature = (distance_au = 1.0, e_min_keV = 0.0, e_max_keV = f64::INFINITY))]
    #[allow(non_snake_case)]
    fn flux(&self, distance_au: f64, e_min_keV: f64, e_max_keV: f64) -> PyResult<f64> {
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
