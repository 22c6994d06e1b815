//! Optical constants: the refractive index n = 1 − δ + iβ of a material at an X-ray
//! energy, from its composition, its density and the atomic scattering factors
//! (Henke's, or Chantler's for a second opinion):
//! δ = r_e λ² / (2π) · N_A ρ Σ_k c_k f1_k(E), β likewise with f2, where c_k are the
//! moles of element k per gram (SPEC §4).

use super::compound::Composition;
use super::elements::{scattering_table, OpticalConstants, HENKE_MAX_KEV, HENKE_MIN_KEV};
use crate::constants::{AVOGADRO, ELECTRON_RADIUS_CM, HC_KEV_CM};

/// A material that X-rays see: composition and density.
#[derive(Clone, Debug, PartialEq)]
pub struct OpticalMaterial {
    pub name: String,
    pub composition: Composition,
    /// g/cm³.
    pub density: f64,
    /// The table of f1, f2.
    pub constants: OpticalConstants,
}

/// An energy outside the tables.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{} keV is outside the Henke tables' range {HENKE_MIN_KEV}–{HENKE_MAX_KEV} keV", crate::text::number(*.energy_kev))]
pub struct EnergyOutOfRange {
    pub energy_kev: f64,
}

impl OpticalMaterial {
    /// (δ, β) at `energy_kev`.
    pub fn delta_beta(&self, energy_kev: f64) -> Result<(f64, f64), EnergyOutOfRange> {
        if !(HENKE_MIN_KEV..=HENKE_MAX_KEV).contains(&energy_kev) {
            return Err(EnergyOutOfRange { energy_kev });
        }
        let lambda_cm = HC_KEV_CM / energy_kev;
        let scale = ELECTRON_RADIUS_CM * lambda_cm * lambda_cm / (2.0 * std::f64::consts::PI)
            * AVOGADRO
            * self.density;
        let (mut s1, mut s2) = (0.0, 0.0);
        for &(z, c) in &self.composition.moles_per_gram {
            let (f1, f2) = scattering_table(self.constants, z).at(energy_kev);
            s1 += c * f1;
            s2 += c * f2;
        }
        Ok((scale * s1, scale * s2))
    }
}
