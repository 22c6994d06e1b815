//! Photon energy distributions (keV).

use crate::random::PhotonRng;

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
