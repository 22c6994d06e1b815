//! The Primakoff emission of axions in the solar plasma: thermal photons convert to
//! axions in the electric fields of the electrons and ions (coupling g_aγ).
//!
//! Natural units (ħ = c = k_B = 1, energies in keV) inside; the conversion to
//! cm, s and keV is in [`differential_rate_cgs`]. With T the temperature, E the
//! photon (= axion) energy and n_j the number densities of the plasma's charged
//! particles (electrons and fully ionised nuclei of charge Z_j):
//!
//! - Debye–Hückel screening wave number, keV²:
//!   κ² = (4πα / T) · (n_e + Σ_j Z_j² n_j)
//! - the transition rate of one photon of energy E ≫ ω_pl into an axion
//!   (Raffelt, Phys. Rev. D 33 (1986) 897; van Bibber et al., Phys. Rev. D 39
//!   (1989) 2089), keV:
//!   Γ_γ→a(E) = g² T κ² / (32π) · [(1 + κ²/(4E²)) ln(1 + 4E²/κ²) − 1]
//! - the axion production rate per axion phase-space mode (the `emRates` column of
//!   an emission table), keV: both photon polarisations convert, each mode being
//!   occupied by f_B = 1/(e^{E/T} − 1) photons:
//!   w(E) = 2 Γ_γ→a(E) f_B(E)
//! - axions emitted per volume, time and energy: an axion has one polarisation,
//!   E²/(2π²) modes per volume and energy, so
//!   d³N/(dV dt dE) = w(E) · E²/(2π²)       [keV³ = 1/(keV⁻³ · keV⁻¹ · keV)]
//!   which is the familiar (E²/π²) Γ_γ→a f_B.
//!
//! Approximations, as in the CAST analyses: the plasma is fully ionised and
//! non-degenerate; photons are taken massless (E ≫ ω_pl, the plasma frequency
//! ω_pl² = 4πα n_e / m_e, ≤ 0.3 keV in the Sun): below ω_pl photons do not
//! propagate and the rate is set to 0; between ω_pl and ~1 keV the formula is only
//! indicative (recoil and collective effects neglected). The coupling of every
//! table traxer computes is g_aγ = 1e-10 GeV⁻¹ (rates scale as g²).
//!
//! Data flow: `traxer solar-flux --model FILE` calls [`emission_table`]; the
//! shipped table (data/solar/) was made that way from B16-AGSS09met.

use super::emission::EmissionTable;
use super::model::{species, Shell, SolarModel, Species};
use super::SolarDataError;
use crate::constants::{
    ALPHA, ATOMIC_MASS_UNIT_G, ELECTRON_MASS_KEV, HBAR_C_KEV_CM, K_B_KEV_PER_K,
};

/// The reference coupling g_aγ = 1e-10 GeV⁻¹ in keV⁻¹.
pub const G_REFERENCE_PER_KEV: f64 = 1e-10 * 1e-6;

/// The plasma of one solar shell, in natural units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plasma {
    /// Temperature T, keV.
    pub temperature_kev: f64,
    /// Debye–Hückel screening wave number squared κ², keV².
    pub kappa2_kev2: f64,
    /// Plasma frequency squared ω_pl², keV².
    pub omega_pl2_kev2: f64,
}

impl Plasma {
    /// The plasma of `shell`: number densities n_k = ρ X_k / (m_k u), electrons
    /// n_e = Σ Z_k n_k (full ionisation), converted to keV³ with (ħc)³.
    pub fn of(shell: &Shell, species: &[Species]) -> Plasma {
        let cm3_to_kev3 = HBAR_C_KEV_CM.powi(3);
        let (mut n_e, mut n_z2) = (0.0, 0.0);
        for (s, &x) in species.iter().zip(&shell.mass_fractions) {
            let n = shell.density_g_cm3 * x / (s.mass_u * ATOMIC_MASS_UNIT_G);
            n_e += s.charge * n;
            n_z2 += s.charge * s.charge * n;
        }
        let t = shell.temperature_k * K_B_KEV_PER_K;
        Plasma {
            temperature_kev: t,
            kappa2_kev2: 4.0 * std::f64::consts::PI * ALPHA / t * (n_e + n_z2) * cm3_to_kev3,
            omega_pl2_kev2: 4.0 * std::f64::consts::PI * ALPHA * n_e * cm3_to_kev3
                / ELECTRON_MASS_KEV,
        }
    }

    /// Γ_γ→a(E) in keV for coupling `g` (keV⁻¹).
    pub fn transition_rate(&self, e_kev: f64, g: f64) -> f64 {
        let x = 4.0 * e_kev * e_kev / self.kappa2_kev2;
        let bracket = (1.0 + 1.0 / x) * x.ln_1p() - 1.0;
        g * g * self.temperature_kev * self.kappa2_kev2 / (32.0 * std::f64::consts::PI) * bracket
    }

    /// w(E) = 2 Γ_γ→a f_B, the production rate per axion mode (keV); 0 at or below
    /// the plasma frequency.
    pub fn rate_per_mode(&self, e_kev: f64, g: f64) -> f64 {
        if e_kev * e_kev <= self.omega_pl2_kev2 {
            return 0.0;
        }
        let occupation = 1.0 / (e_kev / self.temperature_kev).exp_m1();
        2.0 * self.transition_rate(e_kev, g) * occupation
    }
}

/// The Primakoff emission table of `model` at the given radii (fractions of R_sun,
/// the model interpolated linearly between its rows) and energies (keV), for
/// g_aγ = 1e-10 GeV⁻¹.
pub fn emission_table(
    model: &SolarModel,
    radii: &[f64],
    energies: &[f64],
) -> Result<EmissionTable, SolarDataError> {
    let species = species();
    let mut rates = Vec::with_capacity(radii.len() * energies.len());
    for &r in radii {
        let plasma = Plasma::of(&model.at(r), &species);
        rates.extend(
            energies
                .iter()
                .map(|&e| plasma.rate_per_mode(e, G_REFERENCE_PER_KEV)),
        );
    }
    EmissionTable::new(radii.to_vec(), energies.to_vec(), rates)
        .map_err(|e| format!("the Primakoff emission of this model: {e}").into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bracket_has_its_limits() {
        // E ≫ κ: Γ → g² T κ²/(32π) (ln(4E²/κ²) − 1); E ≪ κ: Γ → g² T E²/(16π)·... → 0.
        let p = Plasma {
            temperature_kev: 1.0,
            kappa2_kev2: 1.0,
            omega_pl2_kev2: 0.0,
        };
        let g = 1.0;
        let big = p.transition_rate(1e3, g) * 32.0 * std::f64::consts::PI;
        assert!((big - ((4e6f64).ln() - 1.0)).abs() < 1e-5, "{big}");
        // x = 4E²/κ² small: bracket ≈ x/2, Γ ≈ g² T E²/(16π).
        let small = p.transition_rate(1e-3, g);
        let expected = 1e-6 / (16.0 * std::f64::consts::PI);
        assert!((small / expected - 1.0).abs() < 1e-5, "{small} {expected}");
    }

    #[test]
    fn a_hydrogen_plasma_screens_as_debye_hueckel_says() {
        // Pure hydrogen at ρ = 1 g/cm³, T = 1e7 K: n_e = n_p = ρ/m_H;
        // κ² = 8πα n_e/T with n in keV³.
        let mut x = vec![0.0; 29];
        x[0] = 1.0;
        let shell = Shell {
            radius: 0.1,
            temperature_k: 1e7,
            density_g_cm3: 1.0,
            mass_fractions: x,
        };
        let p = Plasma::of(&shell, &species());
        let n = 1.0 / (1.007825 * ATOMIC_MASS_UNIT_G) * HBAR_C_KEV_CM.powi(3);
        let t = 1e7 * K_B_KEV_PER_K;
        let k2 = 8.0 * std::f64::consts::PI * ALPHA * n / t;
        assert!((p.kappa2_kev2 / k2 - 1.0).abs() < 1e-12);
        // ω_pl = 28.7 eV at n_e = 6.0e23 cm⁻³ (ħω_pl = ħ·sqrt(4π e² n_e / m_e)).
        assert!(
            (p.omega_pl2_kev2.sqrt() - 0.0287).abs() < 0.001,
            "{}",
            p.omega_pl2_kev2.sqrt()
        );
    }
}
