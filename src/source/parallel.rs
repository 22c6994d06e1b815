//! A plane wave filling an aperture disk, annulus or annulus sector: an X-ray
//! source at infinity, optionally off axis.

use super::{frame, AnnulusSector, Photon, Spectrum};
use crate::random::PhotonRng;
use glam::DVec3;

#[derive(Clone, Debug)]
pub struct ParallelBeam {
    /// Where photons start: perpendicular to the nominal direction.
    pub aperture: AnnulusSector,
    /// Nominal direction of travel (unit).
    pub axis: DVec3,
    /// Unit direction of every photon: `axis` tilted by the off-axis angle.
    pub direction: DVec3,
    pub spectrum: Spectrum,
}

impl ParallelBeam {
    /// A beam along `axis` (unit, normal to `aperture`) tilted by `off_axis`
    /// degrees towards cos(azimuth)·e1 + sin(azimuth)·e2 of [`frame`].
    pub fn new(
        aperture: AnnulusSector,
        axis: DVec3,
        off_axis: f64,
        azimuth: f64,
        spectrum: Spectrum,
    ) -> Self {
        let axis = axis.normalize();
        let (e1, e2) = frame(axis);
        let (th, ps) = (off_axis.to_radians(), azimuth.to_radians());
        let direction = (axis * th.cos() + (e1 * ps.cos() + e2 * ps.sin()) * th.sin()).normalize();
        ParallelBeam {
            aperture,
            axis,
            direction,
            spectrum,
        }
    }

    /// Area of the aperture (mm²): each of N photons stands for area / N.
    pub fn area(&self) -> f64 {
        self.aperture.area()
    }

    #[inline]
    pub fn emit(&self, rng: &mut PhotonRng) -> Photon {
        Photon {
            origin: self.aperture.sample(rng),
            dir: self.direction,
            energy: self.spectrum.sample(rng),
            weight: 1.0,
        }
    }
}
