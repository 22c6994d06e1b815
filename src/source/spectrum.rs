//! Photon energy distributions (keV).

use crate::random::PhotonRng;
use serde::Deserialize;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Spectrum {
    /// One energy.
    Line(f64),
    /// Uniform in [min, max].
    Band(f64, f64),
}

impl Spectrum {
    /// Lowest and highest energy (keV).
    pub fn range(&self) -> (f64, f64) {
        match *self {
            Spectrum::Line(e) => (e, e),
            Spectrum::Band(lo, hi) => (lo, hi),
        }
    }

    #[inline]
    pub fn sample(&self, rng: &mut PhotonRng) -> f64 {
        match *self {
            Spectrum::Line(e) => e,
            Spectrum::Band(lo, hi) => lo + (hi - lo) * rng.uniform(),
        }
    }
}

/// Photon energies in keV: `{ line = E }` or `{ band = [min, max] }` (uniform).
#[derive(Debug, Deserialize, Clone)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum EnergyDesc {
    Line(f64),
    Band([f64; 2]),
}

impl EnergyDesc {
    pub fn spectrum(&self) -> Result<Spectrum, super::InvalidSource> {
        match *self {
            EnergyDesc::Line(x) if x.is_finite() && x > 0.0 => Ok(Spectrum::Line(x)),
            EnergyDesc::Band([a, b]) if a.is_finite() && b.is_finite() && a > 0.0 && b > a => {
                Ok(Spectrum::Band(a, b))
            }
            _ => Err("source energy: { line = E } with E > 0 or { band = [min, max] } with 0 < min < max (keV)".into()),
        }
    }
}
