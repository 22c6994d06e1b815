//! Emission tables: the axion production rate per phase-space mode w(r, E) on a
//! grid of solar radii and energies, in the CSV format of the predecessor's
//! generator (columns `Radius` as a fraction of R_sun, `Energy [keV]`, `emRates`
//! = w in keV, natural units; one row per (radius, energy), rows sorted by radius,
//! then energy). Other columns are ignored; `#` starts a comment line.
//!
//! Convention (see [`super::primakoff`]): axions emitted per volume, time and
//! energy are d³N/(dV dt dE) = w · E²/(2π²) in natural units, i.e.
//! w · E² / (2π² (ħc)³ ħ) in cm⁻³ s⁻¹ keV⁻¹. A user checks a table with
//! `traxer solar-flux --table FILE`: its spectrum at Earth must be the flux the
//! table is meant for (for Primakoff at g_aγ = 1e-10 GeV⁻¹, ~3.6e11 cm⁻² s⁻¹ and the
//! CAST 2007 shape dΦ/dE = 6.02e10 E^2.481 e^(−E/1.205) cm⁻² s⁻¹ keV⁻¹).
//!
//! Quadrature: grid point i of the radius (j of the energy) stands for the cell
//! between the midpoints to its neighbours; the first radial cell starts at the
//! centre, the last ends half a step beyond the last radius (at most at 1), and the
//! energy cells likewise (within the Henke range 0.03–30 keV). The axion rate of cell (i, j)
//! is d³N/(dV dt dE)(r_i, E_j) · 4π r_i² Δr_i R_sun³ · ΔE_j — the predecessor's
//! "emRates·E_j²·r_i²·Δr_i" — so the grid need not be uniform.

use super::model::SolarDataError;
use crate::constants::HBAR_C_KEV_CM;
use crate::constants::{HBAR_KEV_S, R_SUN_CM};
use crate::xray::elements::{HENKE_MAX_KEV, HENKE_MIN_KEV};
use std::path::Path;

/// The column names of the CSV format.
pub const RADIUS_COLUMN: &str = "Radius";
pub const ENERGY_COLUMN: &str = "Energy [keV]";
pub const RATE_COLUMN: &str = "emRates";

/// An emission table on a (radius × energy) grid.
#[derive(Clone, Debug, PartialEq)]
pub struct EmissionTable {
    /// Fractions of R_sun, increasing, in (0, 1].
    pub radii: Vec<f64>,
    /// keV, increasing.
    pub energies: Vec<f64>,
    /// w(r_i, E_j) in keV at `i * energies.len() + j`.
    pub rates: Vec<f64>,
}

/// d³N/(dV dt dE) in cm⁻³ s⁻¹ keV⁻¹ from the rate per mode `w` (keV) at `e_kev`.
pub fn differential_rate_cgs(w: f64, e_kev: f64) -> f64 {
    w * e_kev * e_kev / (2.0 * std::f64::consts::PI.powi(2)) / (HBAR_C_KEV_CM.powi(3) * HBAR_KEV_S)
}

/// Cell edges around increasing grid points: midpoints, the first edge at
/// max(`floor`, x₀ − (x₁ − x₀)/2) (or `floor` itself if `from_floor`), the last
/// at min(`ceiling`, x_n + (x_n − x_{n−1})/2). One point: ±1 % around it.
fn edges(x: &[f64], floor: f64, from_floor: bool, ceiling: f64) -> Vec<f64> {
    let n = x.len();
    if n == 1 {
        return vec![x[0] * 0.99, (x[0] * 1.01).min(ceiling)];
    }
    let mut e = Vec::with_capacity(n + 1);
    e.push(if from_floor {
        floor
    } else {
        (x[0] - (x[1] - x[0]) / 2.0).max(floor)
    });
    e.extend(x.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    e.push((x[n - 1] + (x[n - 1] - x[n - 2]) / 2.0).min(ceiling));
    e
}

/// The edges of the energy cells around increasing grid energies (keV): the
/// midpoints, and half a step beyond the ends (within the Henke range).
pub fn energy_cell_edges(energies: &[f64]) -> Vec<f64> {
    edges(energies, HENKE_MIN_KEV, false, HENKE_MAX_KEV)
}

impl EmissionTable {
    /// A table from its grid and rates, checked: radii in (0, 1] and energies in
    /// the Henke range, both strictly increasing; rates finite and ≥ 0.
    /// The most (radius, energy) points a table may have: 2^24 rates are 134 MB,
    /// and the ABC emission costs about a millisecond per point.
    pub const MAX_POINTS: u64 = 1 << 24;

    pub fn new(
        radii: Vec<f64>,
        energies: Vec<f64>,
        rates: Vec<f64>,
    ) -> Result<EmissionTable, SolarDataError> {
        EmissionTable::check_grid(&radii, &energies)?;
        if rates.len() != radii.len() * energies.len() {
            return Err("an emission table needs a rate for each (radius, energy) pair".into());
        }
        if !rates.iter().all(|w| w.is_finite() && *w >= 0.0) {
            return Err("emission rates must be finite and ≥ 0".into());
        }
        if rates.iter().all(|w| *w == 0.0) {
            return Err("every emission rate is 0: nothing is emitted".into());
        }
        Ok(EmissionTable {
            radii,
            energies,
            rates,
        })
    }

    /// Checks a grid: at least two radii and one energy, radii in (0, 1] and energies
    /// in the Henke range, both strictly increasing, at most
    /// [`EmissionTable::MAX_POINTS`] points.
    pub fn check_grid(radii: &[f64], energies: &[f64]) -> Result<(), SolarDataError> {
        let increasing = |v: &[f64]| v.windows(2).all(|w| w[0] < w[1]);
        if radii.is_empty() || energies.is_empty() {
            return Err("an emission table needs at least one radius and one energy".into());
        }
        // One radius would be one radial cell from the centre to the surface,
        // all its axions emitted at that radius: a shell (at r = 1, a ring at
        // the limb) standing for the whole Sun, with 3× a sphere's volume.
        if radii.len() < 2 {
            return Err(format!(
                "the table has one radius ({}): a radial profile needs at least 2 radii (fractions of R_sun from near the centre outwards; the built-in tables have hundreds), or the one radius would stand for the whole Sun",
                radii[0]
            )
            .into());
        }
        let points = radii.len() as u64 * energies.len() as u64;
        if points > Self::MAX_POINTS {
            return Err(format!(
                "{} radii × {} energies = {points} points: at most {} (2^24; the built-in tables have under 100 000)",
                radii.len(),
                energies.len(),
                Self::MAX_POINTS
            )
            .into());
        }
        if !increasing(radii) || !radii.iter().all(|r| *r > 0.0 && *r <= 1.0) {
            return Err("radii must increase and lie in (0, 1] (fractions of R_sun)".into());
        }
        if !increasing(energies)
            || !energies
                .iter()
                .all(|e| (HENKE_MIN_KEV..=HENKE_MAX_KEV).contains(e))
        {
            return Err(format!("energies must increase and lie in the Henke range {HENKE_MIN_KEV}–{HENKE_MAX_KEV} keV").into());
        }
        Ok(())
    }

    pub fn read_csv(path: &Path) -> Result<EmissionTable, SolarDataError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SolarDataError(format!("{}: cannot read: {e}", path.display())))?;
        EmissionTable::parse_csv(&text, path)
    }

    /// Parses the CSV text (`path` only names it in messages).
    pub fn parse_csv(text: &str, path: &Path) -> Result<EmissionTable, SolarDataError> {
        let mut reader = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let fail =
            |line: u64, what: String| SolarDataError(format!("{}:{line}: {what}", path.display()));
        let headers = reader
            .headers()
            .map_err(|e| fail(1, format!("cannot read the header: {e}")))?
            .clone();
        let header_line = text
            .lines()
            .position(|l| !l.trim().is_empty() && !l.starts_with('#'))
            .map_or(1, |k| k as u64 + 1);
        let column = |name: &str| {
            headers.iter().position(|h| h == name).ok_or_else(|| {
                fail(
                    header_line,
                    format!("no column `{name}` (an emission table has the columns `{RADIUS_COLUMN}`, `{ENERGY_COLUMN}` and `{RATE_COLUMN}`; found {:?})", headers.iter().collect::<Vec<_>>()),
                )
            })
        };
        let (ir, ie, iw) = (
            column(RADIUS_COLUMN)?,
            column(ENERGY_COLUMN)?,
            column(RATE_COLUMN)?,
        );
        let mut radii: Vec<f64> = Vec::new();
        let mut energies: Vec<f64> = Vec::new();
        let mut rates = Vec::new();
        // Energies of the radius being read.
        let mut row_energies: Vec<f64> = Vec::new();
        for record in reader.records() {
            let record = record.map_err(|e| {
                let line = e.position().map_or(0, |p| p.line());
                fail(line, format!("not a CSV row: {e}"))
            })?;
            let line = record.position().map_or(0, |p| p.line());
            let number = |i: usize, what: &str| -> Result<f64, SolarDataError> {
                let v = record.get(i).unwrap_or("");
                v.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| fail(line, format!("{what} `{v}` is not a number")))
            };
            let (r, e, w) = (
                number(ir, RADIUS_COLUMN)?,
                number(ie, ENERGY_COLUMN)?,
                number(iw, RATE_COLUMN)?,
            );
            if !(r > 0.0 && r <= 1.0) {
                return Err(fail(
                    line,
                    format!("radius {r}: expected a fraction of the solar radius in (0, 1]"),
                ));
            }
            if !(HENKE_MIN_KEV..=HENKE_MAX_KEV).contains(&e) {
                return Err(fail(line, format!("energy {e} keV: outside the Henke range {HENKE_MIN_KEV}–{HENKE_MAX_KEV} keV that traxer can trace")));
            }
            if w < 0.0 {
                return Err(fail(line, format!("emission rate {w}: expected ≥ 0")));
            }
            match radii.last() {
                Some(&last) if r == last => {
                    if row_energies.last().is_some_and(|&p| e <= p) {
                        return Err(fail(line, format!("energy {e} keV at radius {r} repeats or is out of order (rows: sorted by radius, then by increasing energy)")));
                    }
                }
                Some(&last) if r < last => {
                    return Err(fail(line, format!("radius {r} after {last}: rows must be sorted by increasing radius, each radius once with all its energies")));
                }
                _ => {
                    if let Some(&last) = radii.last() {
                        check_energy_grid(&mut energies, &row_energies, last)
                            .map_err(|m| fail(line - 1, m))?;
                    }
                    radii.push(r);
                    row_energies.clear();
                }
            }
            row_energies.push(e);
            rates.push(w);
        }
        let Some(&last) = radii.last() else {
            return Err(fail(
                header_line,
                "no rows: an emission table needs rows of radius, energy and rate".into(),
            ));
        };
        let end = text.lines().count() as u64;
        check_energy_grid(&mut energies, &row_energies, last).map_err(|m| fail(end, m))?;
        EmissionTable::new(radii, energies, rates)
            .map_err(|e| SolarDataError(format!("{}: {e}", path.display())))
    }

    /// The table as CSV, after `comment` (each line prefixed with `# `).
    pub fn to_csv(&self, comment: &str) -> String {
        let mut out = String::new();
        for l in comment.lines() {
            out.push_str(&format!("# {l}\n"));
        }
        out.push_str(&format!("{RADIUS_COLUMN},{ENERGY_COLUMN},{RATE_COLUMN}\n"));
        for (i, r) in self.radii.iter().enumerate() {
            for (j, e) in self.energies.iter().enumerate() {
                // Grid values to 1e-9: no float noise from a start:stop:step grid.
                let tidy = |x: f64| (x * 1e9).round() / 1e9;
                out.push_str(&format!(
                    "{},{},{:.6e}\n",
                    tidy(*r),
                    tidy(*e),
                    self.rate(i, j)
                ));
            }
        }
        out
    }

    /// w(r_i, E_j), keV.
    #[inline]
    pub fn rate(&self, i: usize, j: usize) -> f64 {
        self.rates[i * self.energies.len() + j]
    }

    /// Radial cell edges (fractions of R_sun): 0, midpoints, end.
    pub fn radius_edges(&self) -> Vec<f64> {
        edges(&self.radii, 0.0, true, 1.0)
    }

    /// Energy cell edges (keV).
    pub fn energy_edges(&self) -> Vec<f64> {
        energy_cell_edges(&self.energies)
    }

    /// Axions per second emitted by each cell (i, j), at `i * energies.len() + j`,
    /// counting only the part of each energy cell inside [e_min, e_max].
    pub fn cell_rates(&self, e_min: f64, e_max: f64) -> Vec<f64> {
        let re = self.radius_edges();
        let ee = self.energy_edges();
        let mut out = Vec::with_capacity(self.rates.len());
        for (i, &r) in self.radii.iter().enumerate() {
            let volume_cm3 =
                4.0 * std::f64::consts::PI * r * r * (re[i + 1] - re[i]) * R_SUN_CM.powi(3);
            for (j, &e) in self.energies.iter().enumerate() {
                let width = (ee[j + 1].min(e_max) - ee[j].max(e_min)).max(0.0);
                out.push(differential_rate_cgs(self.rate(i, j), e) * volume_cm3 * width);
            }
        }
        out
    }

    /// dΦ/dE at each grid energy, cm⁻² s⁻¹ keV⁻¹, at `distance_cm` from the Sun.
    pub fn spectrum_at(&self, distance_cm: f64) -> Vec<f64> {
        let re = self.radius_edges();
        let area = 4.0 * std::f64::consts::PI * distance_cm * distance_cm;
        (0..self.energies.len())
            .map(|j| {
                let e = self.energies[j];
                self.radii
                    .iter()
                    .enumerate()
                    .map(|(i, &r)| {
                        differential_rate_cgs(self.rate(i, j), e)
                            * 4.0
                            * std::f64::consts::PI
                            * r
                            * r
                            * (re[i + 1] - re[i])
                            * R_SUN_CM.powi(3)
                    })
                    .sum::<f64>()
                    / area
            })
            .collect()
    }

    /// Axions per second emitted with energies in [e_min, e_max] (keV).
    pub fn luminosity(&self, e_min: f64, e_max: f64) -> f64 {
        self.cell_rates(e_min, e_max).iter().sum()
    }

    /// The table with every rate multiplied by `factor` (a coupling's square).
    pub fn scaled(&self, factor: f64) -> EmissionTable {
        EmissionTable {
            rates: self.rates.iter().map(|w| w * factor).collect(),
            ..self.clone()
        }
    }

    /// The same emission on the energy cells of `energies` (same radii): the
    /// emission per energy is constant over each of this table's cells (the
    /// quadrature used everywhere), and each new cell gets the overlap, so that
    /// every shell's rate between any two edges common to both grids is kept.
    pub fn resampled(&self, energies: &[f64]) -> Result<EmissionTable, SolarDataError> {
        EmissionTable::check_grid(&self.radii, energies)?;
        let old = self.energy_edges();
        let new = energy_cell_edges(energies);
        let mut rates = Vec::with_capacity(self.radii.len() * energies.len());
        for i in 0..self.radii.len() {
            for (k, &e) in energies.iter().enumerate() {
                let (a, b) = (new[k], new[k + 1]);
                let mut sum = 0.0;
                for (j, &ej) in self.energies.iter().enumerate() {
                    let overlap = old[j + 1].min(b) - old[j].max(a);
                    if overlap > 0.0 {
                        sum += self.rate(i, j) * ej * ej * overlap;
                    }
                }
                rates.push(sum / (e * e * (b - a)));
            }
        }
        Ok(EmissionTable {
            radii: self.radii.clone(),
            energies: energies.to_vec(),
            rates,
        })
    }

    /// The sum of tables on one grid.
    pub fn sum(tables: &[EmissionTable]) -> Result<EmissionTable, SolarDataError> {
        let first = tables.first().ok_or("no tables to add")?;
        if tables
            .iter()
            .any(|t| t.radii != first.radii || t.energies != first.energies)
        {
            return Err("emission tables to be added need the same radii and energies".into());
        }
        let rates = (0..first.rates.len())
            .map(|k| tables.iter().map(|t| t.rates[k]).sum())
            .collect();
        Ok(EmissionTable {
            rates,
            ..first.clone()
        })
    }
}

/// The energies of every radius must be those of the first.
fn check_energy_grid(grid: &mut Vec<f64>, row: &[f64], radius: f64) -> Result<(), String> {
    if grid.is_empty() {
        grid.extend_from_slice(row);
        return Ok(());
    }
    if grid.as_slice() != row {
        return Err(format!(
            "radius {radius} has {} energies, not the {} of the first radius (every radius needs the same energy grid)",
            row.len(),
            grid.len()
        ));
    }
    Ok(())
}
