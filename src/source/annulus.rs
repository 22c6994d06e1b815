//! A flat annulus sector (aperture or target of a source): where photons start or
//! are aimed, sampled uniformly over its area.

use super::frame;
use crate::random::PhotonRng;
use glam::DVec3;
use serde::Deserialize;

#[derive(Clone, Debug)]
pub struct AnnulusSector {
    pub center: DVec3,
    pub inner_radius: f64,
    pub radius: f64,
    /// Azimuth range (radians) from e1 towards e2, e1 and e2 spanning the plane.
    pub phi_start: f64,
    pub phi_span: f64,
    e1: DVec3,
    e2: DVec3,
}

impl AnnulusSector {
    /// The sector perpendicular to `travel` (the direction photons cross it in):
    /// azimuth 0 is along e1 (the part of +x perpendicular to `travel`) and grows
    /// towards e2 = e1 × travel — for travel along −z, from +x towards +y.
    /// `azimuth_deg` = None is the full circle.
    pub fn new(
        center: DVec3,
        travel: DVec3,
        inner_radius: f64,
        radius: f64,
        azimuth_deg: Option<[f64; 2]>,
    ) -> Self {
        let (e1, e2) = frame(travel.normalize());
        let (phi_start, phi_span) = match azimuth_deg {
            Some([a, b]) => (a.to_radians(), (b - a).to_radians()),
            None => (0.0, std::f64::consts::TAU),
        };
        AnnulusSector {
            center,
            inner_radius,
            radius,
            phi_start,
            phi_span,
            e1,
            e2,
        }
    }

    /// Area (mm²).
    pub fn area(&self) -> f64 {
        0.5 * self.phi_span * (self.radius * self.radius - self.inner_radius * self.inner_radius)
    }

    /// A uniform point on the sector.
    #[inline]
    pub fn sample(&self, rng: &mut PhotonRng) -> DVec3 {
        let (r_in, r_out) = (self.inner_radius, self.radius);
        let r = (r_in * r_in + rng.uniform() * (r_out * r_out - r_in * r_in)).sqrt();
        let phi = self.phi_start + self.phi_span * rng.uniform();
        self.center + (self.e1 * phi.cos() + self.e2 * phi.sin()) * r
    }
}

/// An aperture or target disk, annulus or sector in a scene file.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct ApertureDesc {
    pub center: [f64; 3],
    pub radius: f64,
    #[serde(default)]
    pub inner_radius: f64,
    /// Optional sector `[from, to]` in degrees (from e1 towards e2; for photons
    /// travelling along −z: from +x towards +y). Default: the full circle.
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

impl ApertureDesc {
    /// Whether the numbers describe a disk, annulus or sector.
    pub(super) fn is_valid(&self) -> bool {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        self.azimuth
            .is_none_or(|[f, t]| f.is_finite() && t.is_finite() && f < t && t - f <= 360.0)
            && finite(&self.center)
            && finite(&[self.radius, self.inner_radius])
            && self.radius > 0.0
            && self.inner_radius >= 0.0
            && self.inner_radius < self.radius
    }
}
