//! Photon energy distributions (keV) of the lab sources (parallel beam, point
//! source): a single line, a uniform band, or a table — SPEC's three forms. A
//! table (`energy = { table = "FILE.csv" }`, relative to the scene file) gives
//! the spectral density at listed energies, linear in between (an X-ray tube's
//! measured or modelled spectrum); photons are drawn from it by the exact
//! inverse of its cumulative distribution.

use crate::random::PhotonRng;
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Spectrum {
    /// One energy.
    Line(f64),
    /// Uniform in [min, max].
    Band(f64, f64),
    /// Tabulated density, linear between its energies.
    Table(SpectrumTable),
}

/// A spectral density dN/dE at ascending energies, linear in between; zero
/// outside. Only its shape matters (it is normalised).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SpectrumTable {
    /// The file it was read from, as the scene names it.
    pub file: String,
    pub energies_kev: Vec<f64>,
    pub density: Vec<f64>,
    /// ∫ density from the first energy to each energy (trapezoids: exact for a
    /// piecewise-linear density).
    #[serde(skip)]
    cumulative: Vec<f64>,
}

impl SpectrumTable {
    /// The table of (energy, density) points; what is wrong otherwise.
    pub fn new(file: String, points: Vec<(f64, f64)>) -> Result<SpectrumTable, String> {
        if points.len() < 2 {
            return Err("a spectrum table needs at least two rows".into());
        }
        for (k, w) in points.windows(2).enumerate() {
            if w[1].0 <= w[0].0 {
                return Err(format!(
                    "row {}: energies must increase ({} keV after {} keV)",
                    k + 2,
                    w[1].0,
                    w[0].0
                ));
            }
        }
        let (energies_kev, density): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
        let mut cumulative = vec![0.0];
        for k in 1..energies_kev.len() {
            let area =
                0.5 * (density[k] + density[k - 1]) * (energies_kev[k] - energies_kev[k - 1]);
            cumulative.push(cumulative[k - 1] + area);
        }
        let total = *cumulative.last().expect("two rows");
        if total.is_infinite() {
            let largest = density.iter().copied().fold(0.0, f64::max);
            return Err(format!(
                "the densities (up to {}) integrate beyond the largest number a double holds: only their shape matters (a parallel beam's photons weigh 1), so divide the column by a common factor",
                crate::text::number(largest)
            ));
        }
        if !(total.is_finite() && total > 0.0) {
            return Err("the spectrum holds no photons (all densities zero)".into());
        }
        Ok(SpectrumTable {
            file,
            energies_kev,
            density,
            cumulative,
        })
    }

    /// The energy below which a fraction `u` (0–1) of the photons lie.
    pub fn quantile(&self, u: f64) -> f64 {
        let (e, f, c) = (&self.energies_kev, &self.density, &self.cumulative);
        let target = u * c[c.len() - 1];
        let k = c.partition_point(|&x| x <= target).clamp(1, c.len() - 1);
        let (a, b, h) = (f[k - 1], f[k], e[k] - e[k - 1]);
        let r = (target - c[k - 1]).max(0.0);
        // a·t + (b − a)·t²/(2h) = r, solved in the form that stays exact for
        // a = 0 and for a flat segment (b = a).
        let root = (a * a + 2.0 * (b - a) * r / h).max(0.0).sqrt();
        let t = if a + root > 0.0 {
            2.0 * r / (a + root)
        } else {
            0.0
        };
        (e[k - 1] + t).min(e[k])
    }
}

impl Spectrum {
    /// Lowest and highest energy (keV).
    pub fn range(&self) -> (f64, f64) {
        match self {
            Spectrum::Line(e) => (*e, *e),
            Spectrum::Band(lo, hi) => (*lo, *hi),
            Spectrum::Table(t) => (t.energies_kev[0], t.energies_kev[t.energies_kev.len() - 1]),
        }
    }

    #[inline]
    pub fn sample(&self, rng: &mut PhotonRng) -> f64 {
        match self {
            Spectrum::Line(e) => *e,
            Spectrum::Band(lo, hi) => lo + (hi - lo) * rng.uniform(),
            Spectrum::Table(t) => t.quantile(rng.uniform()),
        }
    }
}

/// Photon energies in keV: `{ line = E }`, `{ band = [min, max] }` (uniform) or
/// `{ table = "FILE.csv" }` (columns `energy_keV` and `density`, any unit per
/// keV; `#` starts a comment line).
#[derive(Debug, Deserialize, Clone)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum EnergyDesc {
    Line(f64),
    Band([f64; 2]),
    Table(String),
}

impl EnergyDesc {
    /// The spectrum; a table's file is relative to `dir`.
    pub fn spectrum(&self, dir: &Path) -> Result<Spectrum, super::InvalidSource> {
        match self {
            EnergyDesc::Line(x) if x.is_finite() && *x > 0.0 => Ok(Spectrum::Line(*x)),
            EnergyDesc::Band([a, b]) if a.is_finite() && b.is_finite() && *a > 0.0 && b > a => {
                Ok(Spectrum::Band(*a, *b))
            }
            EnergyDesc::Table(file) => read_table(&dir.join(file), file)
                .map(Spectrum::Table)
                .map_err(|e| super::InvalidSource(format!("source energy table {file}: {e}"))),
            _ => Err("source energy: { line = E } with E > 0, { band = [min, max] } with 0 < min < max (keV), or { table = \"FILE.csv\" }".into()),
        }
    }

    /// The table file it reads, if any.
    pub fn file(&self, dir: &Path) -> Option<PathBuf> {
        match self {
            EnergyDesc::Table(f) => Some(dir.join(f)),
            _ => None,
        }
    }
}

/// Reads a spectrum CSV: a header naming `energy_keV` and `density` (other
/// columns ignored), then one row per energy.
fn read_table(path: &Path, name: &str) -> Result<SpectrumTable, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read it: {e}"))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (_, header) = lines
        .next()
        .ok_or("empty file: expected a header energy_keV,density")?;
    let columns: Vec<&str> = header.split(',').map(str::trim).collect();
    let col = |want: &str| {
        columns.iter().position(|c| *c == want).ok_or_else(|| {
            format!("the header `{header}` has no column `{want}` (expected energy_keV,density)")
        })
    };
    let (ce, cd) = (col("energy_keV")?, col("density")?);
    let mut points = Vec::new();
    for (i, line) in lines {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let value = |c: usize, what: &str| -> Result<f64, String> {
            let cell = cells.get(c).copied().unwrap_or("");
            match cell.parse::<f64>() {
                Ok(v) if v.is_finite() && v >= 0.0 && (what != "energy" || v > 0.0) => Ok(v),
                _ => Err(format!(
                    "line {}: {what} `{cell}` is not a {} number",
                    i + 1,
                    if what == "energy" {
                        "positive"
                    } else {
                        "non-negative"
                    }
                )),
            }
        };
        let point = (value(ce, "energy")?, value(cd, "density")?);
        // Checked here, where the file's line is known (the table's own check
        // can only count rows).
        if let Some(&(before, _)) = points.last() {
            if point.0 <= before {
                return Err(format!(
                    "line {}: energies must increase ({} keV after {before} keV)",
                    i + 1,
                    point.0
                ));
            }
        }
        points.push(point);
    }
    SpectrumTable::new(name.to_string(), points)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quantile inverts the cumulative distribution of a piecewise-linear
    /// density exactly: a triangle 1–2–3 keV of peak 1 has CDF (E−1)²/2 below
    /// its peak and 1 − (3−E)²/2 above.
    #[test]
    fn quantiles_of_a_triangle_spectrum() {
        let t = SpectrumTable::new("t".into(), vec![(1.0, 0.0), (2.0, 1.0), (3.0, 0.0)]).unwrap();
        for u in [0.0, 0.02, 0.125, 0.3, 0.5] {
            let e = t.quantile(u);
            assert!((0.5 * (e - 1.0) * (e - 1.0) - u).abs() < 1e-12, "{u} → {e}");
        }
        for u in [0.7, 0.875, 1.0] {
            let e = t.quantile(u);
            assert!(
                (1.0 - 0.5 * (3.0 - e) * (3.0 - e) - u).abs() < 1e-12,
                "{u} → {e}"
            );
        }
        // A flat table is the uniform band.
        let flat = SpectrumTable::new("f".into(), vec![(2.0, 5.0), (6.0, 5.0)]).unwrap();
        assert!((flat.quantile(0.25) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn bad_tables_are_refused() {
        assert!(SpectrumTable::new("x".into(), vec![(1.0, 1.0)]).is_err());
        assert!(SpectrumTable::new("x".into(), vec![(2.0, 1.0), (1.0, 1.0)]).is_err());
        assert!(SpectrumTable::new("x".into(), vec![(1.0, 0.0), (2.0, 0.0)]).is_err());
    }
}
