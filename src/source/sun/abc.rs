//! The axion–electron ("ABC") emission of the solar plasma, for a coupling g_ae:
//! **A**tomic recombination and de-excitation, **B**remsstrahlung on ions and on
//! electrons, **C**ompton (J. Redondo, JCAP 12 (2013) 008, arXiv:1310.0823, §2;
//! S. Hoof, J. Jaeckel, L. J. Thormaehlen, JCAP 09 (2021) 006, arXiv:2101.08789,
//! §2). Natural units inside (ħ = c = k_B = 1, keV); every rate below is a
//! production rate per axion phase-space mode Γ^P(ω) in keV — the `emRates`
//! column of an emission table, so that axions per volume, time and energy are
//! Γ^P ω²/(2π²) as for Primakoff ([`super::primakoff`]).
//!
//! With T the temperature, u = ω/T, n_e the electron density (full ionisation of
//! every species of the model), m the electron mass and f_B = 1/(e^u − 1):
//!
//! - **Compton**, γ e → a e, non-relativistic electrons (ω' = ω):
//!   Γ_C = 2 · n_e · σ_C · f_B with σ_C = α g² ω²/(3 m⁴), the cross section
//!   averaged over the photon's polarisation; the factor 2 counts the two photon
//!   polarisations of a mode (as 2 Γ_γ→a f_B for Primakoff). Redondo's figure
//!   carries it; the SolarAxionFlux code (Hoof et al.) writes n_e σ_C f_B, half
//!   as much. We checked σ_C by a tree-level Dirac trace of γ e → e a (ratio to
//!   α g² ω²/(3 m⁴): 0.996 at ω = 1e-3 m) and the factor 2 by detailed balance with
//!   a e → γ e, whose cross section summed over the photon's polarisations is
//!   2 σ_C. Below the plasma frequency there are no photons: Γ_C = 0.
//! - **Electron–ion bremsstrahlung** on hydrogen and helium (Redondo eq. 2.17):
//!   Γ_ei = (8√π / (3√2)) α² g² n_e Σ_{H,He} Z² n_Z e^{−u} F(u, y_ei) / (ω √T m^{7/2}),
//!   y_ei² = κ²/(2 m T). The metals' free–free is in their OP opacities (atomic).
//! - **Electron–electron bremsstrahlung** (Redondo eq. 2.18):
//!   Γ_ee = (4√π / 3) α² g² n_e² e^{−u} F(u, y_ee) / (ω √T m^{7/2}), y_ee² = κ²/(m T).
//! - The screened free–free kernel
//!   F(u, y) = ∫₀^∞ dx x e^{−x²} ∫_{b}^{a} dt t³/(t² + y²)², a, b = √(x² + u) ± x
//!   (the momentum transfer t in units of √(2mT)): the Debye-screened Coulomb
//!   propagator 1/(t² + y²) squared, against the unscreened 1/t⁴ (the t³ is the
//!   dipole |q|² times the measure q dq). Without screening F(u, 0) =
//!   ½ e^{u/2} K₀(u/2), which makes Γ_ei exactly g²ω²/(8παm²) times the photon's
//!   Born free–free emission per polarisation (Rybicki & Lightman eq. 5.14 with
//!   the Born Gaunt factor): the same relation as the atomic term below, which
//!   is why we keep this kernel (the squared propagator) rather than a form with
//!   one power of the screening factor.
//! - **Atomic** (free–bound, bound–bound and the metals' free–free), from the OP
//!   monochromatic cross sections σ_Z(ω) (stimulated emission not removed):
//!   Γ_A = g² ω² / (8π α m²) · Σ_{Z ≥ C} n_Z σ_Z(ω) e^{−u}, i.e. g²ω²/(8παm²) times
//!   the photon production rate per polarisation κ_eff/(e^u − 1) with
//!   κ_eff = Σ n σ (1 − e^{−u}) (Redondo eq. 2.21, first term).
//! - Debye–Hückel screening κ² = (4πα/T)(n_e + Σ_Z ⟨Z²⟩ n_Z), with ⟨Z²⟩ of the
//!   metals from the OP ionisation tables and full ionisation for H and He.
//!
//! Choices not made (their size): the electrons' degeneracy (n_e λ_e³/2 ≈ 0.2 in
//! the core; Pauli blocking of the final electron would lower the bremsstrahlung
//! by a few per cent) and the recoil in Compton (O(ω/m) ≈ 0.4 % at 2 keV) are
//! left out, as in both papers; the elements without OP tables (P, Cl, K, Sc, Ti,
//! V, Co: mass fraction 1.3e-4 of the metals) emit nothing atomic.
//!
//! Data flow: `traxer solar-flux --emission abc --model FILE --opacities DIR` and
//! scripts/solar_table.sh call [`emission_tables`]; the built-in table
//! (data/solar/abc_b16_agss09met.csv) was made that way.

use super::emission::{energy_cell_edges, EmissionTable};
use super::model::{species, Shell, SolarDataError, SolarModel, Species};
use super::opacity_project::{GridCell, OpacityTables, OP_ELEMENTS};
use crate::constants::{
    ALPHA, ATOMIC_MASS_UNIT_G, ELECTRON_MASS_KEV, HBAR_C_KEV_CM, K_B_KEV_PER_K,
};
use std::f64::consts::PI;

/// The reference coupling of traxer's ABC tables: g_ae = 1e-13 (rates ∝ g_ae²).
pub const G_AE_REFERENCE: f64 = 1e-13;

/// The four processes, in the order of [`AbcEmission::processes`].
pub const PROCESSES: [&str; 4] = ["atomic", "electron_ion", "electron_electron", "compton"];

/// Fine step for the atomic term's cell averages (keV): the OP tables step by
/// Δln u = 5.6e-4, i.e. 0.6 eV at 1 keV.
const ATOMIC_STEP_KEV: f64 = 2.5e-4;
/// Sub-samples per energy cell for the smooth processes.
const SMOOTH_SAMPLES: usize = 4;

/// The plasma of one solar radius as the ABC processes need it.
#[derive(Clone, Debug)]
pub struct AbcPlasma {
    /// T, keV.
    pub temperature_kev: f64,
    /// n_e, keV³ (full ionisation).
    pub n_e: f64,
    /// Σ_{H,He} Z² n_Z, keV³.
    pub light_ions_z2: f64,
    /// κ², keV².
    pub kappa2: f64,
    /// ω_pl², keV².
    pub omega_pl2: f64,
    /// The OP grid cell of (T, n_e).
    pub cell: GridCell,
    /// (index in OP_ELEMENTS, number density in cm⁻³) of the metals.
    pub metals: Vec<(usize, f64)>,
}

/// The element symbol of a species name (`He4` → `He`).
fn element_of(name: &str) -> &str {
    name.trim_end_matches(|c: char| c.is_ascii_digit())
}

impl AbcPlasma {
    /// The plasma of `shell` (a row of a B16-format model) in the OP grid.
    pub fn of(
        shell: &Shell,
        species: &[Species],
        op: &OpacityTables,
    ) -> Result<AbcPlasma, SolarDataError> {
        let cm3_to_kev3 = HBAR_C_KEV_CM.powi(3);
        let t = shell.temperature_k * K_B_KEV_PER_K;
        let mut n_e_cm3 = 0.0;
        let mut light = 0.0;
        let mut metals: Vec<(usize, f64)> = Vec::new();
        // Metals without OP tables screen as fully ionised ions.
        let mut other_z2 = 0.0;
        for (s, &x) in species.iter().zip(&shell.mass_fractions) {
            let n = shell.density_g_cm3 * x / (s.mass_u * ATOMIC_MASS_UNIT_G);
            n_e_cm3 += s.charge * n;
            let element = element_of(&s.name);
            if s.charge <= 2.0 {
                light += s.charge * s.charge * n;
            } else if let Some(k) = OP_ELEMENTS.iter().position(|(e, _)| *e == element) {
                match metals.iter_mut().find(|(i, _)| *i == k) {
                    Some((_, total)) => *total += n,
                    None => metals.push((k, n)),
                }
            } else {
                other_z2 += s.charge * s.charge * n;
            }
        }
        let cell = op.cell(shell.temperature_k, n_e_cm3).map_err(|e| {
            SolarDataError(format!(
                "the solar model's shell at r = {:.4} R_sun: {}",
                shell.radius, e.0
            ))
        })?;
        let metals_z2: f64 = metals
            .iter()
            .map(|&(k, n)| op.mean_charge2(&cell, k) * n)
            .sum();
        let n_e = n_e_cm3 * cm3_to_kev3;
        Ok(AbcPlasma {
            temperature_kev: t,
            n_e,
            light_ions_z2: light * cm3_to_kev3,
            kappa2: 4.0 * PI * ALPHA / t * (n_e_cm3 + light + metals_z2 + other_z2) * cm3_to_kev3,
            omega_pl2: 4.0 * PI * ALPHA * n_e / ELECTRON_MASS_KEV,
            cell,
            metals,
        })
    }

    /// Γ_C (keV) at ω (keV) for coupling g.
    pub fn compton(&self, omega: f64, g: f64) -> f64 {
        if omega * omega <= self.omega_pl2 {
            return 0.0;
        }
        let m = ELECTRON_MASS_KEV;
        let sigma = ALPHA * g * g * omega * omega / (3.0 * m.powi(4));
        2.0 * self.n_e * sigma / (omega / self.temperature_kev).exp_m1()
    }

    /// The bremsstrahlung prefactor shared by both kinds, without the densities.
    fn bremsstrahlung(&self, omega: f64, g: f64, y2: f64) -> f64 {
        let t = self.temperature_kev;
        let u = omega / t;
        ALPHA * ALPHA * g * g * (-u).exp() * screened_free_free(u, y2)
            / (omega * t.sqrt() * ELECTRON_MASS_KEV.powf(3.5))
    }

    /// Γ_ei (keV): electrons on H and He nuclei.
    pub fn electron_ion(&self, omega: f64, g: f64) -> f64 {
        let y2 = self.kappa2 / (2.0 * ELECTRON_MASS_KEV * self.temperature_kev);
        8.0 * PI.sqrt() / (3.0 * 2f64.sqrt())
            * self.n_e
            * self.light_ions_z2
            * self.bremsstrahlung(omega, g, y2)
    }

    /// Γ_ee (keV).
    pub fn electron_electron(&self, omega: f64, g: f64) -> f64 {
        let y2 = self.kappa2 / (ELECTRON_MASS_KEV * self.temperature_kev);
        4.0 * PI.sqrt() / 3.0 * self.n_e * self.n_e * self.bremsstrahlung(omega, g, y2)
    }

    /// Γ_A (keV) at each increasing ω of `omegas` (keV).
    pub fn atomic(&self, op: &OpacityTables, omegas: &[f64], g: f64) -> Vec<f64> {
        let absorption = op.absorption_per_cm(&self.cell, &self.metals, omegas);
        let m = ELECTRON_MASS_KEV;
        omegas
            .iter()
            .zip(absorption)
            .map(|(&w, k)| {
                g * g * w * w / (8.0 * PI * ALPHA * m * m)
                    * (k * HBAR_C_KEV_CM)
                    * (-w / self.temperature_kev).exp()
            })
            .collect()
    }
}

/// F(u, y) with y² = `y2` (see the module documentation): the inner integral in
/// closed form, ½[ln((a² + y²)/(b² + y²)) + y²/(a² + y²) − y²/(b² + y²)], the
/// outer by Simpson's rule on x ∈ [0, 5.5] (the weight e^{−x²} is 7e-14 there;
/// 160 intervals: 1e-7 relative, tested against the Bessel-function form).
pub fn screened_free_free(u: f64, y2: f64) -> f64 {
    const N: usize = 160;
    const X_MAX: f64 = 5.5;
    let inner = |x: f64| {
        let s = (x * x + u).sqrt();
        let a2 = (s + x) * (s + x);
        // b = s − x without cancellation at large x.
        let b = u / (s + x);
        let b2 = b * b;
        0.5 * (((a2 + y2) / (b2 + y2)).ln() + y2 / (a2 + y2) - y2 / (b2 + y2))
    };
    let h = X_MAX / N as f64;
    let mut sum = 0.0;
    for k in 1..N {
        let x = k as f64 * h;
        let weight = if k % 2 == 1 { 4.0 } else { 2.0 };
        sum += weight * x * (-x * x).exp() * inner(x);
    }
    // The end points contribute 0 (x = 0) and e^{−30} (x = X_MAX).
    sum * h / 3.0
}

/// The ABC emission of a solar model on a grid: one table per process (order of
/// [`PROCESSES`]) and their sum, each value the cell average of Γ^P·E² over its
/// energy cell divided by the cell centre's E², so that the tables' cell rates
/// are the integrals over each cell and lines are not missed by a coarse grid.
#[derive(Clone, Debug)]
pub struct AbcEmission {
    pub processes: [EmissionTable; 4],
    pub total: EmissionTable,
}

/// Which of the model's radii the OP tables cover (the central ones, out to
/// where the plasma leaves their grid), said for a refused radius.
fn covered(model: &SolarModel, species: &[Species], op: &OpacityTables) -> String {
    // From the centre out, up to the first shell outside the tables' grid.
    let inside = |s: &&Shell| AbcPlasma::of(s, species, op).is_ok();
    let first = model.shells.first().filter(inside).map(|s| s.radius);
    let last = model
        .shells
        .iter()
        .take_while(inside)
        .last()
        .map(|s| s.radius);
    match (first, last) {
        (Some(a), Some(b)) => format!(
            "the Opacity Project tables cover this model's shells from r = {a:.4} to {b:.4} R_sun: give --radii within them (the built-in tables use 0.0025:0.6975:0.005)"
        ),
        _ => "the Opacity Project tables cover none of this model's shells from its centre".into(),
    }
}

/// Computes [`AbcEmission`] for g_ae = [`G_AE_REFERENCE`] at `radii` (fractions
/// of R_sun, the model interpolated linearly) and `energies` (keV, cell centres;
/// cells as in [`EmissionTable::energy_edges`]).
pub fn emission_tables(
    model: &SolarModel,
    op: &OpacityTables,
    radii: &[f64],
    energies: &[f64],
) -> Result<AbcEmission, SolarDataError> {
    EmissionTable::check_grid(radii, energies)?;
    let species = species();
    let g = G_AE_REFERENCE;
    let edges = energy_cell_edges(energies);
    // The fine energies of the atomic term, and which cell each falls in.
    let mut fine = Vec::new();
    let mut fine_cell = Vec::new();
    for j in 0..energies.len() {
        let (a, b) = (edges[j], edges[j + 1]);
        // Rounded, not ceiled: grids parsed from text or built by steps differ
        // in the last bit, and must sample alike.
        let n = ((b - a) / ATOMIC_STEP_KEV).round().max(1.0) as usize;
        for k in 0..n {
            fine.push(a + (k as f64 + 0.5) * (b - a) / n as f64);
            fine_cell.push((j, n));
        }
    }
    let mut rates: [Vec<f64>; 4] = Default::default();
    for &r in radii {
        let plasma = AbcPlasma::of(&model.at(r), &species, op).map_err(|e| {
            SolarDataError(format!(
                "--radii: {}; {}",
                e.0,
                covered(model, &species, op)
            ))
        })?;
        let mut atomic = vec![0.0; energies.len()];
        for ((w, &(j, n)), rate) in fine.iter().zip(&fine_cell).zip(plasma.atomic(op, &fine, g)) {
            atomic[j] += rate * w * w / n as f64;
        }
        for (j, &e) in energies.iter().enumerate() {
            let (a, b) = (edges[j], edges[j + 1]);
            let mut smooth = [0.0; 3];
            for k in 0..SMOOTH_SAMPLES {
                let w = a + (k as f64 + 0.5) * (b - a) / SMOOTH_SAMPLES as f64;
                let f = w * w / SMOOTH_SAMPLES as f64;
                smooth[0] += plasma.electron_ion(w, g) * f;
                smooth[1] += plasma.electron_electron(w, g) * f;
                smooth[2] += plasma.compton(w, g) * f;
            }
            rates[0].push(atomic[j] / (e * e));
            for p in 0..3 {
                rates[p + 1].push(smooth[p] / (e * e));
            }
        }
    }
    let total: Vec<f64> = (0..rates[0].len())
        .map(|k| rates.iter().map(|r| r[k]).sum())
        .collect();
    let table = |w: Vec<f64>| EmissionTable::new(radii.to_vec(), energies.to_vec(), w);
    let [a, b, c, d] = rates;
    Ok(AbcEmission {
        processes: [table(a)?, table(b)?, table(c)?, table(d)?],
        total: table(total)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K₀(z) = ∫₀^∞ e^{−z cosh t} dt, by the trapezoidal rule (exponentially
    /// accurate for this analytic integrand).
    fn bessel_k0(z: f64) -> f64 {
        let h: f64 = 0.01;
        let mut s = 0.5 * (-z).exp();
        let mut t = h;
        loop {
            let v = (-z * t.cosh()).exp();
            s += v;
            if v < 1e-18 {
                break;
            }
            t += h;
        }
        s * h
    }

    #[test]
    fn the_unscreened_kernel_is_the_born_free_free_gaunt_factor() {
        // F(u, 0) = ½ e^{u/2} K₀(u/2): the photon's Born free–free emission.
        for u in [0.05, 0.3, 1.0, 3.0, 10.0] {
            let f = screened_free_free(u, 0.0);
            let k = 0.5 * (u / 2.0).exp() * bessel_k0(u / 2.0);
            assert!((f / k - 1.0).abs() < 1e-6, "u = {u}: {f} vs {k}");
        }
    }

    #[test]
    fn screening_lowers_the_kernel_and_vanishes_for_small_y() {
        for u in [0.3, 1.0, 3.0] {
            let bare = screened_free_free(u, 0.0);
            let weak = screened_free_free(u, 1e-8);
            let strong = screened_free_free(u, 1.0);
            assert!((weak / bare - 1.0).abs() < 1e-6);
            assert!(strong < 0.9 * bare, "u = {u}: {strong} vs {bare}");
            assert!(strong > 0.0);
        }
    }

    #[test]
    fn rates_scale_as_the_coupling_squared() {
        let p = AbcPlasma {
            temperature_kev: 1.3,
            n_e: 6e25 * HBAR_C_KEV_CM.powi(3),
            light_ions_z2: 8e25 * HBAR_C_KEV_CM.powi(3),
            kappa2: 80.0,
            omega_pl2: 0.09,
            cell: GridCell {
                corners: [(0, 0); 4],
                weights: [0.25; 4],
            },
            metals: vec![],
        };
        for w in [0.5, 2.0, 6.0] {
            for f in [
                AbcPlasma::compton,
                AbcPlasma::electron_ion,
                AbcPlasma::electron_electron,
            ] {
                let (a, b) = (f(&p, w, 1e-13), f(&p, w, 3e-13));
                assert!((b / a / 9.0 - 1.0).abs() < 1e-12);
            }
        }
        assert_eq!(p.compton(0.29, 1e-13), 0.0, "no photons below ω_pl");
    }

    #[test]
    fn species_names_give_their_elements() {
        assert_eq!(element_of("He4"), "He");
        assert_eq!(element_of("O18"), "O");
        assert_eq!(element_of("Fe"), "Fe");
    }
}
