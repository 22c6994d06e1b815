//! A plane wave filling an aperture disk (or annulus): an X-ray source at infinity,
//! optionally off axis.

use super::{frame, sample_annulus, Photon, Spectrum};
use crate::random::PhotonRng;
use glam::DVec3;

#[derive(Clone, Debug)]
pub struct ParallelBeam {
    /// Centre of the aperture disk, which is perpendicular to `axis`.
    pub center: DVec3,
    /// Nominal direction of travel (unit).
    pub axis: DVec3,
    pub inner_radius: f64,
    pub radius: f64,
    /// Unit direction of every photon: `axis` tilted by the off-axis angle.
    pub direction: DVec3,
    pub spectrum: Spectrum,
    e1: DVec3,
    e2: DVec3,
}

impl ParallelBeam {
    /// `off_axis` and `azimuth` in degrees; the tilt is towards
    /// cos(azimuth)·e1 + sin(azimuth)·e2 of [`frame`].
    pub fn new(
        center: DVec3,
        axis: DVec3,
        off_axis: f64,
        azimuth: f64,
        inner_radius: f64,
        radius: f64,
        spectrum: Spectrum,
    ) -> Self {
        let axis = axis.normalize();
        let (e1, e2) = frame(axis);
        let (th, ps) = (off_axis.to_radians(), azimuth.to_radians());
        let direction = (axis * th.cos() + (e1 * ps.cos() + e2 * ps.sin()) * th.sin()).normalize();
        ParallelBeam {
            center,
            axis,
            inner_radius,
            radius,
            direction,
            spectrum,
            e1,
            e2,
        }
    }

    /// Area of the aperture (mm²): each of N photons stands for area / N.
    pub fn area(&self) -> f64 {
        std::f64::consts::PI * (self.radius * self.radius - self.inner_radius * self.inner_radius)
    }

    #[inline]
    pub fn emit(&self, rng: &mut PhotonRng) -> Photon {
        let (e1, e2) = (self.e1, self.e2);
        let (r, phi) = sample_annulus(rng, self.inner_radius, self.radius);
        let origin = self.center + (e1 * phi.cos() + e2 * phi.sin()) * r;
        Photon {
            origin,
            dir: self.direction,
            energy: self.spectrum.sample(rng),
            weight: 1.0,
        }
    }
}
