//! The Opacity Project's monochromatic photon cross sections of the solar plasma's
//! elements (OP: Seaton et al., MNRAS 266 (1994) 805; Badnell et al., MNRAS 360
//! (2005) 458; the OPCD 3.3 files as redistributed by the SolarAxionFlux
//! repository of Hoof, Jaeckel and Thormaehlen, JCAP 09 (2021) 006), read from a
//! folder in that layout:
//!
//! - `opacity/opacity_table_EL_ITE_JNE.dat`: element EL at the OP grid point
//!   ITE = 40·log10(T/K), JNE = 4·log10(n_e/cm⁻³); two columns, ln u with
//!   u = ħω/(k_B T) at the grid point's own T, and the cross section per atom of
//!   EL in Bohr radii squared, stimulated emission not removed;
//! - `ionisation/ionisation_table_ITE_JNE.dat`: per atomic number, the mean
//!   number of free electrons per atom ⟨Z⟩ and its square's mean ⟨Z²⟩.
//!
//! What traxer does with them: for a solar radius with temperature T and electron
//! density n_e, the cross section at photon energy ω is interpolated bilinearly in
//! (log T, log n_e) between the four grid points around it, each evaluated at the
//! same ω (u = ω/T_grid, linearly in ln u): the lines stay at their energies
//! instead of moving with the ratio of the local T to the grid's.
//!
//! Data flow: `traxer solar-flux --opacities DIR` and the table-making script read
//! the folder here; [`super::abc`] turns the cross sections into the atomic
//! (free–bound, bound–bound and metal free–free) axion emission.

use super::model::SolarDataError;
use crate::constants::BOHR_RADIUS_CM;
use crate::constants::K_B_KEV_PER_K;
use std::collections::BTreeMap;
use std::path::Path;

/// The 17 elements of the OP tables, with their atomic numbers.
pub const OP_ELEMENTS: [(&str, u32); 17] = [
    ("H", 1),
    ("He", 2),
    ("C", 6),
    ("N", 7),
    ("O", 8),
    ("Ne", 10),
    ("Na", 11),
    ("Mg", 12),
    ("Al", 13),
    ("Si", 14),
    ("S", 16),
    ("Ar", 18),
    ("Ca", 20),
    ("Cr", 24),
    ("Mn", 25),
    ("Fe", 26),
    ("Ni", 28),
];

/// OP's grid step in ITE and in JNE.
const GRID_STEP: i32 = 2;

/// One element's cross section at one grid point: ln u ascending, σ in a₀².
#[derive(Clone, Debug)]
struct CrossSection {
    ln_u: Vec<f64>,
    sigma: Vec<f64>,
}

impl CrossSection {
    /// σ at ln u (linear between the table's points, 0 outside them).
    fn at(&self, ln_u: f64) -> f64 {
        let x = &self.ln_u;
        if !(ln_u >= x[0] && ln_u <= x[x.len() - 1]) {
            return 0.0;
        }
        let k = x.partition_point(|&v| v <= ln_u).clamp(1, x.len() - 1);
        let t = (ln_u - x[k - 1]) / (x[k] - x[k - 1]);
        self.sigma[k - 1] + t * (self.sigma[k] - self.sigma[k - 1])
    }

    /// σ at each of the increasing `ln_u` values, by one walk through the table.
    fn at_sorted(&self, ln_u: &[f64], out: &mut [f64]) {
        let x = &self.ln_u;
        let mut k = 1;
        for (o, &v) in out.iter_mut().zip(ln_u) {
            if !(v >= x[0] && v <= x[x.len() - 1]) {
                *o = 0.0;
                continue;
            }
            while k < x.len() - 1 && x[k] < v {
                k += 1;
            }
            let t = (v - x[k - 1]) / (x[k] - x[k - 1]);
            *o = self.sigma[k - 1] + t * (self.sigma[k] - self.sigma[k - 1]);
        }
    }
}

/// The tables of one OP grid point.
#[derive(Clone, Debug)]
struct GridPoint {
    /// Temperature in keV.
    temperature_kev: f64,
    /// Per element of [`OP_ELEMENTS`].
    cross_sections: Vec<CrossSection>,
    /// ⟨Z²⟩ per element of [`OP_ELEMENTS`].
    mean_charge2: Vec<f64>,
}

/// The OP tables of a folder, by grid point (ITE, JNE).
#[derive(Clone, Debug)]
pub struct OpacityTables {
    points: BTreeMap<(i32, i32), GridPoint>,
}

/// Where a plasma lies in the OP grid: four corners and their bilinear weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridCell {
    pub corners: [(i32, i32); 4],
    pub weights: [f64; 4],
}

impl OpacityTables {
    /// Reads every grid point of `dir` (see the module documentation).
    pub fn read(dir: &Path) -> Result<OpacityTables, SolarDataError> {
        let ion_dir = dir.join("ionisation");
        let entries = std::fs::read_dir(&ion_dir).map_err(|e| {
            SolarDataError(format!(
                "{}: cannot read the OP ionisation folder: {e} (expected the layout of ../shared/solar/op/: ionisation/ and opacity/)",
                ion_dir.display()
            ))
        })?;
        let mut points = BTreeMap::new();
        for entry in entries {
            let entry = entry.map_err(|e| SolarDataError(format!("{}: {e}", ion_dir.display())))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            let Some(grid) = parse_grid_name(&name, "ionisation_table_") else {
                continue;
            };
            let mean_charge2 = read_ionisation(&entry.path())?;
            let mut cross_sections = Vec::with_capacity(OP_ELEMENTS.len());
            for (element, _) in OP_ELEMENTS {
                let path = dir
                    .join("opacity")
                    .join(format!("opacity_table_{element}_{}_{}.dat", grid.0, grid.1));
                cross_sections.push(read_cross_section(&path)?);
            }
            points.insert(
                grid,
                GridPoint {
                    temperature_kev: 10f64.powf(grid.0 as f64 / 40.0) * K_B_KEV_PER_K,
                    cross_sections,
                    mean_charge2,
                },
            );
        }
        if points.is_empty() {
            return Err(SolarDataError(format!(
                "{}: no files ionisation_table_ITE_JNE.dat",
                ion_dir.display()
            )));
        }
        Ok(OpacityTables { points })
    }

    /// The grid points read, as (ITE, JNE).
    pub fn grid_points(&self) -> Vec<(i32, i32)> {
        self.points.keys().copied().collect()
    }

    /// The grid cell around temperature `t_k` (K) and free-electron density
    /// `n_e` (cm⁻³), or what is missing.
    pub fn cell(&self, t_k: f64, n_e: f64) -> Result<GridCell, SolarDataError> {
        let ite = 40.0 * t_k.log10();
        let jne = 4.0 * n_e.log10();
        let i0 = GRID_STEP * (ite / GRID_STEP as f64).floor() as i32;
        let j0 = GRID_STEP * (jne / GRID_STEP as f64).floor() as i32;
        let (ti, tj) = (
            (ite - i0 as f64) / GRID_STEP as f64,
            (jne - j0 as f64) / GRID_STEP as f64,
        );
        let corners = [
            (i0, j0),
            (i0 + GRID_STEP, j0),
            (i0, j0 + GRID_STEP),
            (i0 + GRID_STEP, j0 + GRID_STEP),
        ];
        for c in corners {
            if !self.points.contains_key(&c) {
                return Err(SolarDataError(format!(
                    "the OP tables have no grid point ITE = {}, JNE = {} needed for T = {t_k:.4e} K, n_e = {n_e:.4e} cm⁻³ (ITE = {ite:.2}, JNE = {jne:.2})",
                    c.0, c.1
                )));
            }
        }
        Ok(GridCell {
            corners,
            weights: [
                (1.0 - ti) * (1.0 - tj),
                ti * (1.0 - tj),
                (1.0 - ti) * tj,
                ti * tj,
            ],
        })
    }

    /// Σ_k n_k σ_k(ω) over `elements` (indices into [`OP_ELEMENTS`] with their
    /// number densities in cm⁻³) at each increasing photon energy `omega_kev`,
    /// in cm⁻¹: the absorption coefficient without stimulated emission removed.
    pub fn absorption_per_cm(
        &self,
        cell: &GridCell,
        elements: &[(usize, f64)],
        omega_kev: &[f64],
    ) -> Vec<f64> {
        let mut total = vec![0.0; omega_kev.len()];
        let mut ln_u = vec![0.0; omega_kev.len()];
        let mut sigma = vec![0.0; omega_kev.len()];
        for (corner, &weight) in cell.corners.iter().zip(&cell.weights) {
            if weight == 0.0 {
                continue;
            }
            let point = &self.points[corner];
            for (l, w) in ln_u.iter_mut().zip(omega_kev) {
                *l = (w / point.temperature_kev).ln();
            }
            for &(element, density) in elements {
                point.cross_sections[element].at_sorted(&ln_u, &mut sigma);
                let factor = weight * density * BOHR_RADIUS_CM * BOHR_RADIUS_CM;
                for (t, s) in total.iter_mut().zip(&sigma) {
                    *t += factor * s;
                }
            }
        }
        total
    }

    /// One element's cross section (a₀²) at ω in the cell, for tests and plots.
    pub fn cross_section(&self, cell: &GridCell, element: usize, omega_kev: f64) -> f64 {
        cell.corners
            .iter()
            .zip(&cell.weights)
            .map(|(c, w)| {
                let p = &self.points[c];
                w * p.cross_sections[element].at((omega_kev / p.temperature_kev).ln())
            })
            .sum()
    }

    /// ⟨Z²⟩ of an element in the cell (bilinear like the cross sections).
    pub fn mean_charge2(&self, cell: &GridCell, element: usize) -> f64 {
        cell.corners
            .iter()
            .zip(&cell.weights)
            .map(|(c, w)| w * self.points[c].mean_charge2[element])
            .sum()
    }
}

/// (ITE, JNE) from a name `PREFIX{ITE}_{JNE}.dat`.
fn parse_grid_name(name: &str, prefix: &str) -> Option<(i32, i32)> {
    let rest = name.strip_prefix(prefix)?.strip_suffix(".dat")?;
    let (a, b) = rest.split_once('_')?;
    Some((a.parse().ok()?, b.parse().ok()?))
}

/// Lines of numbers of a table file, `#` lines skipped, with their line numbers.
fn numeric_rows(path: &Path) -> Result<Vec<(usize, Vec<f64>)>, SolarDataError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| SolarDataError(format!("{}: cannot read: {e}", path.display())))?;
    let mut rows = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let values: Result<Vec<f64>, _> = line.split_whitespace().map(str::parse).collect();
        match values {
            Ok(v) if v.iter().all(|x| x.is_finite()) => rows.push((k + 1, v)),
            _ => {
                return Err(SolarDataError(format!(
                    "{}:{}: expected numbers separated by spaces",
                    path.display(),
                    k + 1
                )))
            }
        }
    }
    Ok(rows)
}

fn read_cross_section(path: &Path) -> Result<CrossSection, SolarDataError> {
    let rows = numeric_rows(path)?;
    let mut ln_u = Vec::with_capacity(rows.len());
    let mut sigma = Vec::with_capacity(rows.len());
    for (line, v) in rows {
        let at = |m: &str| SolarDataError(format!("{}:{line}: {m}", path.display()));
        if v.len() != 2 {
            return Err(at("expected two columns: ln u and the cross section (a₀²)"));
        }
        if ln_u.last().is_some_and(|&l| v[0] <= l) {
            return Err(at("ln u must increase from row to row"));
        }
        if v[1] < 0.0 {
            return Err(at("a cross section must be ≥ 0"));
        }
        ln_u.push(v[0]);
        sigma.push(v[1]);
    }
    if ln_u.len() < 2 {
        return Err(SolarDataError(format!(
            "{}: fewer than two rows",
            path.display()
        )));
    }
    Ok(CrossSection { ln_u, sigma })
}

/// ⟨Z²⟩ per element of [`OP_ELEMENTS`] from an ionisation table.
fn read_ionisation(path: &Path) -> Result<Vec<f64>, SolarDataError> {
    let rows = numeric_rows(path)?;
    OP_ELEMENTS
        .iter()
        .map(|&(name, z)| {
            rows.iter()
                .find(|(_, v)| v.len() == 3 && v[0] == z as f64)
                .map(|(_, v)| v[2])
                .ok_or_else(|| {
                    SolarDataError(format!(
                        "{}: no row for {name} (atomic number {z}; columns: Z, ⟨Z⟩, ⟨Z²⟩)",
                        path.display()
                    ))
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_names_are_read() {
        assert_eq!(
            parse_grid_name("ionisation_table_254_92.dat", "ionisation_table_"),
            Some((254, 92))
        );
        assert_eq!(parse_grid_name("other.dat", "ionisation_table_"), None);
    }

    #[test]
    fn interpolation_is_linear_in_ln_u_and_zero_outside() {
        let c = CrossSection {
            ln_u: vec![0.0, 1.0, 2.0],
            sigma: vec![1.0, 3.0, 2.0],
        };
        assert_eq!(c.at(0.5), 2.0);
        assert_eq!(c.at(1.5), 2.5);
        assert_eq!(c.at(-0.1), 0.0);
        assert_eq!(c.at(2.1), 0.0);
        let mut out = vec![0.0; 4];
        c.at_sorted(&[-1.0, 0.5, 1.5, 3.0], &mut out);
        assert_eq!(out, vec![0.0, 2.0, 2.5, 0.0]);
    }
}
