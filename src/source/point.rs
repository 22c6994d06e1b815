//! A source at a finite distance (lab X-ray tube, PANTER, the CAST X-ray finger):
//! a disk emitting isotropically, sampled only towards a target disk in front of
//! the optics.
//!
//! Importance sampling: the direction is chosen by picking a uniform point on the
//! target, whose density over solid angle is p(ω) = d² / (A cos θ_t) (d the
//! distance, θ_t the angle to the target's normal). Isotropic emission has
//! p_iso = 1/4π, so the photon gets weight p_iso / p = A cos θ_t / (4π d²): the
//! summed weights are what an isotropic source emitting the same number of photons
//! would put through the target. Photons start on the target disk, so the f32 ray
//! never spans the 100 m to the source, and nothing between source and target is
//! traced.

use super::{frame, sample_annulus, Photon, Spectrum};
use crate::random::PhotonRng;
use glam::DVec3;

#[derive(Clone, Debug)]
pub struct PointSource {
    pub position: DVec3,
    pub radius: f64,
    pub target_center: DVec3,
    pub target_inner_radius: f64,
    pub target_radius: f64,
    pub spectrum: Spectrum,
    /// Unit normal of the target disk, pointing towards the source.
    target_normal: DVec3,
    target_area: f64,
    t1: DVec3,
    t2: DVec3,
}

impl PointSource {
    pub fn new(
        position: DVec3,
        radius: f64,
        target_center: DVec3,
        target_inner_radius: f64,
        target_radius: f64,
        spectrum: Spectrum,
    ) -> Self {
        let target_normal = (position - target_center).normalize();
        let (t1, t2) = frame(target_normal);
        PointSource {
            position,
            radius,
            target_center,
            target_inner_radius,
            target_radius,
            spectrum,
            target_normal,
            t1,
            t2,
            target_area: std::f64::consts::PI
                * (target_radius * target_radius - target_inner_radius * target_inner_radius),
        }
    }

    #[inline]
    pub fn emit(&self, rng: &mut PhotonRng) -> Photon {
        let (t1, t2) = (self.t1, self.t2);
        let (r, phi) = sample_annulus(rng, 0.0, self.radius);
        // The emitting disk faces the target.
        let emit = self.position + (t1 * phi.cos() + t2 * phi.sin()) * r;
        let (r, phi) = sample_annulus(rng, self.target_inner_radius, self.target_radius);
        let on_target = self.target_center + (t1 * phi.cos() + t2 * phi.sin()) * r;
        let v = on_target - emit;
        let d2 = v.length_squared();
        let dir = v / d2.sqrt();
        let cos_t = dir.dot(self.target_normal).abs();
        Photon {
            origin: on_target,
            dir,
            energy: self.spectrum.sample(rng),
            weight: self.target_area * cos_t / (4.0 * std::f64::consts::PI * d2),
        }
    }
}
