//! The gas of a gaseous X-ray detector (the CAST GridPix: argon/isobutane
//! 97.7/2.3 % at 1050 mbar, 3 cm drift): where in the gas an X-ray converts.
//!
//! An X-ray entering the gas converts (is photoabsorbed, freeing the electron
//! whose ionisation trail the readout sees) after a path s with the probability
//! density μ e^{−μ s}; μ is the photoabsorption coefficient 4πβ/λ from the Henke
//! tables, the same numbers the foils and mirrors use (Henke's f2 is the
//! photoabsorption cross-section: Compton and Rayleigh scattering, which convert
//! nothing and are < 1 % of μ below 10 keV in argon, are not in it). The gas
//! density follows from the ideal gas law ρ = p M̄ / (R T) with the mixture's mean
//! molar mass M̄ (isobutane's departure from ideality at 1 bar, ~2 %, changes ρ of
//! a 2.3 % admixture by 0.05 %).
//!
//! A photon crossing the drift gap of thickness t at cos θ to the readout's
//! normal converts inside it with probability P = 1 − e^{−μ t / cos θ}; the
//! photon loop multiplies its weight by P (the rest is tallied as transmitted)
//! and draws the depth of the conversion from the exponential truncated to the
//! gap, so every photon that reaches the detector contributes (no photon is lost
//! to Monte Carlo for being unconverted).
//!
//! Data flow: `sensor` builds a [`DetectorGas`] from a sensor's `gas` table;
//! the photon loop calls [`DetectorGas::convert`] when a photon reaches the
//! readout.

use super::compound::{parse_formula, Composition};
use super::elements::{element, OpticalConstants, HENKE_MAX_KEV, HENKE_MIN_KEV};
use super::optical::{EnergyOutOfRange, OpticalMaterial};
use crate::constants::GAS_CONSTANT;
use crate::constants::HC_KEV_CM;
use serde::Deserialize;
use std::collections::BTreeMap;

/// The `gas` table of a sensor material.
///
/// ```toml
/// gas = { mixture = { Ar = 0.977, C4H10 = 0.023 }, pressure_mbar = 1050.0,
///         temperature_k = 293.15, drift_mm = 30.0 }
/// ```
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GasDesc {
    /// Formula → fraction by volume (= by moles, for ideal gases); they must sum
    /// to 1 within 2 %, and are normalised.
    pub mixture: BTreeMap<String, f64>,
    pub pressure_mbar: f64,
    /// Default 293.15 K (20 °C).
    #[serde(default = "room_temperature")]
    pub temperature_k: f64,
    /// Thickness of the gas from the entrance (window side) to the readout.
    pub drift_mm: f64,
    /// Width of the conversion-depth histogram's bins (default 0.1 mm).
    #[serde(default = "default_depth_step")]
    pub depth_step_mm: f64,
    /// The depth-resolved spectrum: energy bins `[min, max, count]` (keV, default
    /// [0, 15, 150]) …
    #[serde(default = "default_spectrum_energies")]
    pub spectrum_energy_bins: (f64, f64, u32),
    /// … in this many equal depth slices of the drift gap (default 10).
    #[serde(default = "default_depth_slices")]
    pub spectrum_depth_slices: u32,
}

fn room_temperature() -> f64 {
    293.15
}
fn default_depth_step() -> f64 {
    0.1
}
fn default_spectrum_energies() -> (f64, f64, u32) {
    (0.0, 15.0, 150)
}
fn default_depth_slices() -> u32 {
    10
}

/// The most bins of the depth histogram and of the depth-resolved spectrum.
const MAX_BINS: u64 = 1 << 20;

message_error!(
    /// A `gas` table that describes no gas, with what is wrong.
    InvalidGas
);

/// A detector gas, ready for the photon loop.
#[derive(Clone, Debug, PartialEq)]
pub struct DetectorGas {
    pub desc: GasDesc,
    /// Composition (moles per gram) and density (g/cm³) from the ideal gas law.
    pub material: OpticalMaterial,
    /// Mean molar mass of the mixture (g/mol).
    pub molar_mass: f64,
    /// ln μ (μ in 1/mm) on [`MU_TABLE_POINTS`] energies equally spaced in ln E
    /// over the Henke range: one lookup per photon instead of a sum over the
    /// elements' scattering tables.
    ln_mu: Vec<f64>,
}

/// Points of the μ(E) table: the step is 0.012 % in energy, so interpolation
/// (linear in ln μ against ln E) blurs an absorption edge over 0.4 eV at 3.2 keV and
/// changes μ elsewhere by < 1e-6 (Henke's own f2 interpolation is linear in
/// ln f2 against ln E too).
const MU_TABLE_POINTS: usize = 1 << 16;

/// Where a photon converts: the probability and, if it does, how far below the
/// gas entrance (along the readout's normal) and after which path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conversion {
    /// P = 1 − e^{−μ L}, L the path across the whole gap.
    pub probability: f64,
    /// Path length from the entrance to the conversion point (mm).
    pub path_mm: f64,
    /// Path length from the conversion point on to the readout (mm).
    pub remaining_mm: f64,
    /// Depth of the conversion point below the entrance, along the normal (mm).
    pub depth_mm: f64,
}

impl DetectorGas {
    /// Checks `desc` and builds the gas.
    pub fn new(desc: &GasDesc) -> Result<DetectorGas, InvalidGas> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(desc.pressure_mbar) {
            return Err(InvalidGas::from(
                "pressure_mbar must be a positive pressure (mbar)",
            ));
        }
        if !positive(desc.temperature_k) {
            return Err(InvalidGas::from(
                "temperature_k must be a positive temperature (K)",
            ));
        }
        if !positive(desc.drift_mm) {
            return Err(InvalidGas::from(
                "drift_mm must be a positive thickness (mm)",
            ));
        }
        if !positive(desc.depth_step_mm)
            || (desc.drift_mm / desc.depth_step_mm).ceil() > MAX_BINS as f64
        {
            return Err(InvalidGas::from(format!(
                "depth_step_mm must be positive and make at most {MAX_BINS} bins of drift_mm"
            )));
        }
        let (lo, hi, n) = desc.spectrum_energy_bins;
        if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && lo < hi && n >= 1)
            || desc.spectrum_depth_slices == 0
            || n as u64 * desc.spectrum_depth_slices as u64 > MAX_BINS
        {
            return Err(InvalidGas::from(format!(
                "spectrum_energy_bins = [min, max, count] needs 0 ≤ min < max (keV) and count ≥ 1, spectrum_depth_slices ≥ 1, and at most {MAX_BINS} bins in all"
            )));
        }
        let (parts, molar_mass) = mass_fractions(&desc.mixture)?;
        let composition = Composition::mixture(&parts).map_err(|e| InvalidGas(e.0))?;
        // ρ = p M̄ / (R T): Pa · g/mol / (J/mol) = g/m³, then g/cm³.
        let density =
            desc.pressure_mbar * 100.0 * molar_mass / (GAS_CONSTANT * desc.temperature_k) * 1e-6;
        let name = desc
            .mixture
            .iter()
            .map(|(f, x)| format!("{f} {:.4}", x))
            .collect::<Vec<_>>()
            .join(" + ");
        // The gas's absorption stays on Henke's table: the mirrors' optical
        // constants are a reflectivity systematic, the gas has its own.
        let material = OpticalMaterial {
            name,
            composition,
            density,
            constants: OpticalConstants::Henke,
        };
        let ln_mu = (0..MU_TABLE_POINTS)
            .map(|i| {
                let e = (HENKE_MIN_KEV.ln() + i as f64 * ln_step())
                    .exp()
                    .clamp(HENKE_MIN_KEV, HENKE_MAX_KEV);
                exact_attenuation_per_mm(&material, e)
                    .expect("table energies lie in the Henke range")
                    .max(f64::MIN_POSITIVE)
                    .ln()
            })
            .collect();
        Ok(DetectorGas {
            desc: desc.clone(),
            material,
            molar_mass,
            ln_mu,
        })
    }

    /// Photoabsorption coefficient μ = 4πβ/λ (1/mm) at `energy_kev`, from the
    /// table (see [`MU_TABLE_POINTS`]).
    #[inline]
    pub fn attenuation_per_mm(&self, energy_kev: f64) -> Result<f64, EnergyOutOfRange> {
        if !(HENKE_MIN_KEV..=HENKE_MAX_KEV).contains(&energy_kev) {
            return Err(EnergyOutOfRange { energy_kev });
        }
        let x = (energy_kev / HENKE_MIN_KEV).ln() / ln_step();
        let i = (x as usize).min(MU_TABLE_POINTS - 2);
        let f = x - i as f64;
        Ok((self.ln_mu[i] * (1.0 - f) + self.ln_mu[i + 1] * f).exp())
    }

    /// Absorption length 1/μ (mm) at `energy_kev`.
    pub fn absorption_length_mm(&self, energy_kev: f64) -> Result<f64, EnergyOutOfRange> {
        Ok(1.0 / self.attenuation_per_mm(energy_kev)?)
    }

    /// Where a photon of `energy_kev` arriving at |cos θ| = `cos` to the normal
    /// converts, for a uniform deviate `u` in [0, 1): the depth is drawn from the
    /// exponential truncated to the gap, s = −ln(1 − u P) / μ. Energies outside
    /// the Henke tables never convert (the scene build refuses sources that emit
    /// them).
    #[inline]
    pub fn convert(&self, energy_kev: f64, cos: f64, u: f64) -> Conversion {
        let cos = cos.abs().max(1e-12);
        let path = self.desc.drift_mm / cos;
        let Ok(mu) = self.attenuation_per_mm(energy_kev) else {
            return Conversion {
                probability: 0.0,
                path_mm: path,
                remaining_mm: 0.0,
                depth_mm: self.desc.drift_mm,
            };
        };
        // −expm1(−x) = 1 − e^{−x}, accurate also for thin gaps (μL ≪ 1).
        let probability = -(-mu * path).exp_m1();
        let s = (-(-u * probability).ln_1p() / mu).min(path);
        Conversion {
            probability,
            path_mm: s,
            remaining_mm: path - s,
            depth_mm: s * cos,
        }
    }
}

/// The table's step in ln E.
fn ln_step() -> f64 {
    (HENKE_MAX_KEV / HENKE_MIN_KEV).ln() / (MU_TABLE_POINTS - 1) as f64
}

/// μ = 4πβ/λ (1/mm) of `material` at `energy_kev`, from the Henke tables.
fn exact_attenuation_per_mm(
    material: &OpticalMaterial,
    energy_kev: f64,
) -> Result<f64, EnergyOutOfRange> {
    let (_, beta) = material.delta_beta(energy_kev)?;
    let lambda_mm = HC_KEV_CM / energy_kev * 10.0;
    Ok(4.0 * std::f64::consts::PI * beta / lambda_mm)
}

/// One part of a gas mixture: its formula, its normalised fraction by volume
/// and its atoms per molecule (symbol → count).
pub type MixturePart = (String, f64, BTreeMap<String, f64>);

/// A gas mixture's parts with their fractions by volume (= by moles),
/// checked (each positive, summing to 1 within 2 %) and normalised, each with
/// its atoms per molecule: for a detector's gas and a magnet's buffer gas.
pub fn mixture_parts(mixture: &BTreeMap<String, f64>) -> Result<Vec<MixturePart>, String> {
    if mixture.is_empty() {
        return Err(
            "mixture is empty: give each gas's fraction by volume, e.g. { Ar = 0.977, C4H10 = 0.023 }"
                .into(),
        );
    }
    if let Some((gas, x)) = mixture.iter().find(|(_, x)| !(x.is_finite() && **x > 0.0)) {
        return Err(format!(
            "mixture: {gas} = {}: a part's fraction by volume must be positive (leave out a gas that is not in the mixture)",
            crate::text::number(*x)
        ));
    }
    let total: f64 = mixture.values().sum();
    if (total - 1.0).abs() > 0.02 {
        return Err(format!(
            "mixture: fractions by volume must sum to 1 (they sum to {total:.6}; within 2 % they are normalised)"
        ));
    }
    mixture
        .iter()
        .map(|(formula, x)| {
            let atoms = parse_formula(formula).map_err(|e| format!("mixture: {}", e.0))?;
            Ok((formula.clone(), x / total, atoms))
        })
        .collect()
}

/// Mass fractions of the mixture's parts (from the volume fractions, normalised)
/// and the mean molar mass M̄ = Σ x_i M_i.
fn mass_fractions(
    mixture: &BTreeMap<String, f64>,
) -> Result<(Vec<(String, f64)>, f64), InvalidGas> {
    let mut molar = Vec::new();
    for (formula, x, atoms) in mixture_parts(mixture).map_err(InvalidGas)? {
        let m: f64 = atoms
            .iter()
            .map(|(s, n)| n * element(s).expect("parse_formula checks symbols").mass)
            .sum();
        molar.push((formula, x, m));
    }
    let mean: f64 = molar.iter().map(|(_, x, m)| x * m).sum();
    let parts = molar
        .into_iter()
        .map(|(f, x, m)| (f, x * m / mean))
        .collect();
    Ok((parts, mean))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gas(mixture: &[(&str, f64)], drift: f64) -> DetectorGas {
        DetectorGas::new(&GasDesc {
            mixture: mixture.iter().map(|(f, x)| (f.to_string(), *x)).collect(),
            pressure_mbar: 1013.25,
            temperature_k: 273.15,
            drift_mm: drift,
            depth_step_mm: 0.1,
            spectrum_energy_bins: default_spectrum_energies(),
            spectrum_depth_slices: 10,
        })
        .unwrap()
    }

    #[test]
    fn ideal_gas_density_at_stp() {
        // One mole of an ideal gas fills 22.414 L at 0 °C and 1 atm: argon
        // (39.948 g/mol) weighs 1.7824 g/L there.
        let ar = gas(&[("Ar", 1.0)], 30.0);
        assert!(
            (ar.material.density / 1.7824e-3 - 1.0).abs() < 2e-4,
            "{}",
            ar.material.density
        );
    }

    #[test]
    fn the_depth_is_the_truncated_exponential() {
        // u ↦ depth must be the inverse of the truncated exponential CDF:
        // F(s) = (1 − e^{−μ s}) / P.
        let ar = gas(&[("Ar", 1.0)], 30.0);
        let mu = ar.attenuation_per_mm(3.0).unwrap();
        for u in [0.0, 0.1, 0.5, 0.9, 0.999] {
            let c = ar.convert(3.0, 0.5, u);
            let f = -(-mu * c.path_mm).exp_m1() / c.probability;
            assert!((f - u).abs() < 1e-12, "u {u}: F = {f}");
            assert!((c.depth_mm - 0.5 * c.path_mm).abs() < 1e-12);
        }
    }

    #[test]
    fn the_table_gives_the_henke_attenuation() {
        // Away from edges (within a table step of one, the table blurs it) the
        // interpolated μ equals the direct sum over the elements.
        let g = gas(&[("Ar", 0.977), ("C4H10", 0.023)], 30.0);
        for e in [0.3, 0.77, 1.49, 2.9, 3.3, 4.51, 8.04, 12.0, 25.0] {
            let exact = exact_attenuation_per_mm(&g.material, e).unwrap();
            let table = g.attenuation_per_mm(e).unwrap();
            assert!(
                (table / exact - 1.0).abs() < 1e-5,
                "{e} keV: {table} vs {exact}"
            );
        }
    }

    #[test]
    fn volume_fractions_become_mass_fractions() {
        // 50/50 by volume of He (4.0026) and Ar (39.95 in data/elements.csv,
        // 39.948 in other tables): the mean molar mass is their average, and argon
        // holds M_Ar / (2 · M̄) of the mass.
        let m = BTreeMap::from([("He".to_string(), 0.5), ("Ar".to_string(), 0.5)]);
        let (parts, mean) = mass_fractions(&m).unwrap();
        assert!((mean - 21.976).abs() < 2e-3, "{mean}");
        let ar = parts.iter().find(|p| p.0 == "Ar").unwrap().1;
        assert!(
            (ar - (2.0 * mean - 4.002602) / (2.0 * mean)).abs() < 1e-6,
            "{ar}"
        );
    }
}
