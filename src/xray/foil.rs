//! Thin foils that X-rays pass through: detector windows (the 300 nm Si₃N₄
//! membrane of the CAST GridPix detector) and filters.
//!
//! A photon crossing a foil of thickness t at incidence angle θ (from the foil's
//! normal) keeps the fraction T = exp(−μ t / cos θ) of its weight and goes on in the
//! same direction (refraction by n = 1 − δ turns a ray by ~δ ≈ 1e-5 rad at most for
//! near-normal incidence on a thin flat foil and moves it by far less than a pixel:
//! neglected). μ = 4πβ/λ is the linear attenuation coefficient from the imaginary
//! part β of the refractive index (the same Henke data as the mirrors, SPEC §6).
//!
//! Data flow: `scene::materials` builds a [`Foil`] for each `type = "foil"`
//! material; the photon loop multiplies the weight by [`Foil::transmission`].

use super::optical::{EnergyOutOfRange, OpticalMaterial};
use crate::constants::HC_KEV_CM;

/// A foil: material and thickness.
#[derive(Clone, Debug, PartialEq)]
pub struct Foil {
    pub material: OpticalMaterial,
    pub thickness_nm: f64,
}

impl Foil {
    /// Linear attenuation coefficient μ = 4πβ/λ in 1/nm at `energy_kev`.
    pub fn attenuation_per_nm(&self, energy_kev: f64) -> Result<f64, EnergyOutOfRange> {
        let (_, beta) = self.material.delta_beta(energy_kev)?;
        let lambda_nm = HC_KEV_CM / energy_kev * 1e7;
        Ok(4.0 * std::f64::consts::PI * beta / lambda_nm)
    }

    /// Transmitted fraction at `energy_kev` for a ray whose direction makes
    /// cos θ = `cos_incidence` with the foil's normal (the path through the foil
    /// is t / cos θ). Energies outside the Henke tables transmit nothing (the
    /// scene build refuses sources that emit them).
    #[inline]
    pub fn transmission(&self, energy_kev: f64, cos_incidence: f64) -> f64 {
        match self.attenuation_per_nm(energy_kev) {
            Ok(mu) => (-mu * self.thickness_nm / cos_incidence.abs().max(1e-12)).exp(),
            Err(_) => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xray::CoatingLibrary;

    fn foil(material: &str, nm: f64) -> Foil {
        Foil {
            material: CoatingLibrary::shipped().material(material).unwrap(),
            thickness_nm: nm,
        }
    }

    #[test]
    fn path_length_grows_as_one_over_cos() {
        // T(θ) = T(0)^(1/cos θ): the exponent scales with the path length.
        let f = foil("SiO2", 500.0);
        let t0 = f.transmission(1.0, 1.0);
        let t60 = f.transmission(1.0, 0.5);
        assert!(t0 > 0.0 && t0 < 1.0);
        assert!((t60 - t0 * t0).abs() < 1e-12, "{t60} vs {}", t0 * t0);
    }

    #[test]
    fn zero_thickness_transmits_everything() {
        assert_eq!(foil("SiO2", 0.0).transmission(3.0, 0.3), 1.0);
    }
}
