//! The buffer gas in a helioscope's bore (BabyIAXO's and CAST's helium phases):
//! the photon's effective mass m_γ, which restores coherence for axions of
//! m_a ≈ m_γ, and the X-ray attenuation Γ along the bore.
//!
//! - m_γ² = 4πα n_e / m_e, the plasma frequency of the gas's electrons (valid
//!   for X-rays far above their binding energies: 24.6 eV in helium), n_e from
//!   the ideal gas law n = p / (k T) times the electrons per molecule. Helium-3
//!   and helium-4 at the same pressure and temperature have the same n, n_e and
//!   cross-sections per atom, hence the same m_γ and Γ: `He` stands for both.
//! - Γ is the **total** attenuation: photoabsorption (Henke's f2, σ_a =
//!   2 r_e λ f2, the numbers the rest of traxer uses) plus coherent and
//!   incoherent scattering (NIST FFAST, `xray::scattering`). A photon scattered
//!   by a helium atom leaves the coherent beam at a large angle and misses the
//!   focus as surely as an absorbed one; above ~5 keV scattering is most of
//!   helium's attenuation (photoabsorption alone would overstate the
//!   transmission of 10 m of 10 mbar, 1.8 K helium at 8 keV by 6 %).
//!
//! Data flow: `scene::magnet` builds it from the magnet's `gas` table; `magnet`
//! takes m_γ² and Γ(E) for each photon's conversion probability.

use crate::constants::{
    ALPHA, ELECTRON_MASS_EV, ELECTRON_RADIUS_CM, HBAR_C_EV_M, HC_KEV_CM, K_B_J_PER_K,
};
use crate::xray::elements::{element, scattering_table, OpticalConstants};
use crate::xray::elements::{HENKE_MAX_KEV, HENKE_MIN_KEV};
use crate::xray::gas::mixture_parts;
use crate::xray::scattering;
use serde::Deserialize;
use std::collections::BTreeMap;

/// The magnet's `gas` table.
///
/// ```toml
/// gas = { mixture = { He = 1.0 }, pressure_mbar = 10.0, temperature_k = 1.8 }
/// ```
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BufferGasDesc {
    /// Formula → fraction by volume (normalised; within 2 % of 1).
    pub mixture: BTreeMap<String, f64>,
    pub pressure_mbar: f64,
    pub temperature_k: f64,
}

/// The densest buffer gas traxer takes (molecules per m³): half liquid
/// helium's 2.2e28, a hundred times BabyIAXO's densest helium setting.
pub const MAX_NUMBER_DENSITY_M3: f64 = 1e28;

message_error!(
    /// A buffer gas that cannot be, with what is wrong.
    InvalidBufferGas
);

/// A buffer gas, ready for the conversion probability.
#[derive(Clone, Debug, PartialEq)]
pub struct BufferGas {
    pub desc: BufferGasDesc,
    /// Molecules per m³ (ideal gas).
    pub number_density_m3: f64,
    /// Electrons per m³.
    pub electron_density_m3: f64,
    /// m_γ² (eV²).
    pub photon_mass2_ev2: f64,
    /// (Z, atoms of it per molecule of the mixture on average).
    atoms: Vec<(u32, f64)>,
}

impl BufferGas {
    /// Checks `desc` and builds the gas.
    pub fn new(desc: &BufferGasDesc) -> Result<BufferGas, InvalidBufferGas> {
        let bad = |m: String| Err(InvalidBufferGas(m));
        if !(desc.pressure_mbar.is_finite() && desc.pressure_mbar >= 0.0) {
            return bad(format!(
                "pressure_mbar = {}: a pressure is ≥ 0 (0: vacuum)",
                crate::text::number(desc.pressure_mbar)
            ));
        }
        if !(desc.temperature_k.is_finite() && desc.temperature_k > 0.0) {
            return bad(format!(
                "temperature_k = {}: a temperature is > 0 K",
                crate::text::number(desc.temperature_k)
            ));
        }
        let mut atoms: BTreeMap<u32, f64> = BTreeMap::new();
        for (_, x, parts) in mixture_parts(&desc.mixture).map_err(InvalidBufferGas)? {
            for (symbol, n) in parts {
                let z = element(&symbol).expect("parse_formula checks symbols").z;
                *atoms.entry(z).or_default() += x * n;
            }
        }
        let electrons: f64 = atoms.iter().map(|(z, n)| *z as f64 * n).sum();
        let number_density_m3 = desc.pressure_mbar * 100.0 / (K_B_J_PER_K * desc.temperature_k);
        if number_density_m3.is_nan() || number_density_m3 > MAX_NUMBER_DENSITY_M3 {
            return bad(format!(
                "pressure_mbar = {} at temperature_k = {}: {:.3e} molecules per m³ by the ideal gas law, denser than a liquid (liquid helium holds 2.2e28): neither the ideal gas law nor the plasma-frequency photon mass holds there (a buffer gas is below {MAX_NUMBER_DENSITY_M3:e} per m³; BabyIAXO's densest helium setting is about 1e26)",
                crate::text::number(desc.pressure_mbar),
                crate::text::number(desc.temperature_k),
                number_density_m3
            ));
        }
        let electron_density_m3 = number_density_m3 * electrons;
        // n_e in eV³: (ħc)³ turns m⁻³ into eV³.
        let n_e_ev3 = electron_density_m3 * HBAR_C_EV_M.powi(3);
        let photon_mass2_ev2 = 4.0 * std::f64::consts::PI * ALPHA * n_e_ev3 / ELECTRON_MASS_EV;
        Ok(BufferGas {
            desc: desc.clone(),
            number_density_m3,
            electron_density_m3,
            photon_mass2_ev2,
            atoms: atoms.into_iter().collect(),
        })
    }

    /// The photon's effective mass m_γ (eV).
    pub fn photon_mass_ev(&self) -> f64 {
        self.photon_mass2_ev2.sqrt()
    }

    /// The total attenuation coefficient μ (1/m) at `energy_kev`
    /// (photoabsorption plus scattering); `None` outside 0.03–30 keV.
    pub fn attenuation_per_m(&self, energy_kev: f64) -> Option<f64> {
        if !(HENKE_MIN_KEV..=HENKE_MAX_KEV).contains(&energy_kev) {
            return None;
        }
        let lambda_cm = HC_KEV_CM / energy_kev;
        let per_molecule_cm2: f64 = self
            .atoms
            .iter()
            .map(|&(z, n)| {
                let (_, f2) = scattering_table(OpticalConstants::Henke, z).at(energy_kev);
                let photo = 2.0 * ELECTRON_RADIUS_CM * lambda_cm * f2;
                n * (photo + scattering::cross_section_cm2(z, energy_kev))
            })
            .sum();
        Some(self.number_density_m3 * per_molecule_cm2 * 1e-4)
    }

    /// Γ (eV) at `energy_kev`: μ in natural units, μ · ħc.
    pub fn attenuation_ev(&self, energy_kev: f64) -> Option<f64> {
        self.attenuation_per_m(energy_kev)
            .map(|mu| mu * HBAR_C_EV_M)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn helium(p: f64, t: f64) -> BufferGas {
        BufferGas::new(&BufferGasDesc {
            mixture: [("He".to_string(), 1.0)].into(),
            pressure_mbar: p,
            temperature_k: t,
        })
        .unwrap()
    }

    #[test]
    fn helium_at_10_mbar_and_1_8_k_gives_the_photon_mass_of_the_literature() {
        // 0.333 eV (the issue), and the textbook form m_γ ≈ 28.77 eV √(Z ρ / A)
        // with ρ in g/cm³ from the ideal gas law on its own (its coefficient is
        // rounded: CODATA's constants give 28.816, 0.16 % more).
        let g = helium(10.0, 1.8);
        assert!(
            (g.photon_mass_ev() - 0.333).abs() < 0.001,
            "{}",
            g.photon_mass_ev()
        );
        let rho: f64 = 1000.0 * 4.002602 / (8.314_462_618 * 1.8) * 1e-6;
        let textbook = 28.77 * (2.0 * rho / 4.002602).sqrt();
        assert!((g.photon_mass_ev() / textbook - 1.0).abs() < 2e-3);
    }
}
