//! Physical constants and angle units, in one place: every module that needs
//! h·c, ħ, the electron's radius or arcseconds per radian takes them from here.
//! A leaf: it depends on nothing. Values are CODATA 2018 (exact where the 2019
//! SI defines them) and IAU 2012; each is written as the nearest double of its
//! value in its unit, so a constant in two units is two literals, not one
//! multiplied by a power of ten (which would round differently).

use std::f64::consts::PI;

/// h·c in keV·nm (exact in the 2019 SI: 1.239 841 984 332 002 6… keV·nm).
pub const HC_KEV_NM: f64 = 1.239_841_984_332_002_6;
/// h·c in keV·µm: λ (µm) = HC_KEV_UM / E (keV).
pub const HC_KEV_UM: f64 = 1.239_841_984_332_002_6e-3;
/// h·c in keV·cm (12.398 419 843 320 026 keV·Å).
pub const HC_KEV_CM: f64 = 12.398_419_843_320_026e-8;
/// ħc, keV·cm (CODATA 2018): 1 cm = 1/(ħc) keV⁻¹.
pub const HBAR_C_KEV_CM: f64 = 1.973_269_804e-8;
/// ħ in keV·s (CODATA 2018).
pub const HBAR_KEV_S: f64 = 6.582_119_569e-19;
/// Fine-structure constant (CODATA 2018).
pub const ALPHA: f64 = 1.0 / 137.035_999_084;
/// Boltzmann constant, keV/K (CODATA 2018).
pub const K_B_KEV_PER_K: f64 = 8.617_333_262e-8;
/// Boltzmann constant, J/K (exact in the 2019 SI).
pub const K_B_J_PER_K: f64 = 1.380_649e-23;
/// Atomic mass unit, g (CODATA 2018).
pub const ATOMIC_MASS_UNIT_G: f64 = 1.660_539_066_60e-24;
/// Electron mass, eV (CODATA 2018).
pub const ELECTRON_MASS_EV: f64 = 510_998.950;
/// Electron mass, keV (CODATA 2018).
pub const ELECTRON_MASS_KEV: f64 = 510.998_950;
/// Classical electron radius (cm), CODATA 2018.
pub const ELECTRON_RADIUS_CM: f64 = 2.817_940_326_2e-13;
/// The Bohr radius in cm (CODATA 2018).
pub const BOHR_RADIUS_CM: f64 = 5.291_772_109_03e-9;
/// Avogadro constant (1/mol), exact.
pub const AVOGADRO: f64 = 6.022_140_76e23;
/// The molar gas constant (J mol⁻¹ K⁻¹), exact since the 2019 SI.
pub const GAS_CONSTANT: f64 = 8.314_462_618;
/// ħc in eV·m (CODATA 2018): with ħ = c = 1, 1 m = 1/(ħc) eV⁻¹.
pub const HBAR_C_EV_M: f64 = 1.973_269_804e-7;
/// 1 m in eV⁻¹ (ħ = c = 1): 1/(ħc) = 5.0677e6 eV⁻¹.
pub const INV_EV_PER_METRE: f64 = 5.067_730_717_679_395e6;
/// The vacuum magnetic permeability μ0 in N/A² (CODATA 2018).
pub const MU_0: f64 = 1.256_637_062_12e-6;
/// The elementary charge in C (exact in the 2019 SI).
pub const ELEMENTARY_CHARGE_C: f64 = 1.602_176_634e-19;
/// 1 T in eV² in natural Heaviside–Lorentz units (ħ = c = 1, α = e²/4π, the
/// units of the axion–photon coupling): B²/2 is the field's energy density,
/// so 1 T = √((ħc)³ / (μ0 e)) = 195.35 eV² (ħc in eV·m, e in C).
pub const TESLA_EV2: f64 = 195.352_771_140_595_6;
/// The solar radius in cm (SPEC §3: 6.96342e8 m, Emilio et al. 2012 from SOHO).
pub const R_SUN_CM: f64 = 6.963_42e10;
/// The astronomical unit in cm (IAU 2012, exact).
pub const AU_CM: f64 = 1.495_978_707e13;

/// Arcseconds per radian.
pub const ARCSEC_PER_RAD: f64 = 180.0 * 3600.0 / PI;
/// Radians per arcsecond.
pub const RAD_PER_ARCSEC: f64 = PI / (180.0 * 3600.0);
