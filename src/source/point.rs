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

use super::{
    far_from_origin, AnnulusSector, ApertureDesc, EnergyDesc, InvalidSource, Photon, Spectrum,
};
use crate::random::PhotonRng;
use glam::DVec3;
use serde::Deserialize;

#[derive(Clone, Debug)]
pub struct PointSource {
    pub position: DVec3,
    /// Radius of the emitting disk, which faces the target.
    pub radius: f64,
    /// Where the photons are aimed and start.
    pub target: AnnulusSector,
    pub spectrum: Spectrum,
    /// Unit normal of the target, pointing towards the source.
    target_normal: DVec3,
    /// The emitting disk (radius `radius`, centred on `position`).
    emitter: AnnulusSector,
}

impl PointSource {
    pub fn new(
        position: DVec3,
        radius: f64,
        target_center: DVec3,
        target_inner_radius: f64,
        target_radius: f64,
        target_azimuth: Option<[f64; 2]>,
        spectrum: Spectrum,
    ) -> Self {
        let target_normal = (position - target_center).normalize();
        PointSource {
            position,
            radius,
            target: AnnulusSector::new(
                target_center,
                -target_normal,
                target_inner_radius,
                target_radius,
                target_azimuth,
            ),
            spectrum,
            target_normal,
            emitter: AnnulusSector::new(position, -target_normal, 0.0, radius, None),
        }
    }

    #[inline]
    pub fn emit(&self, rng: &mut PhotonRng) -> Photon {
        let emit = if self.radius > 0.0 {
            self.emitter.sample(rng)
        } else {
            self.position
        };
        let on_target = self.target.sample(rng);
        let v = on_target - emit;
        let d2 = v.length_squared();
        let dir = v / d2.sqrt();
        let cos_t = dir.dot(self.target_normal).abs();
        Photon {
            origin: on_target,
            dir,
            energy: self.spectrum.sample(rng),
            weight: self.target.area() * cos_t / (4.0 * std::f64::consts::PI * d2),
            process: 0,
            cell: 0,
        }
    }
}

/// `type = "point"` in a scene file's `[[sources]]`.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct PointDesc {
    pub position: [f64; 3],
    #[serde(default)]
    pub radius: f64,
    pub target: ApertureDesc,
    pub energy: EnergyDesc,
}

impl PointDesc {
    /// The source, or what is wrong with its parameters.
    pub fn build(&self, dir: &std::path::Path) -> Result<PointSource, InvalidSource> {
        let p = self;
        if far_from_origin(&[p.position, p.target.center], &[p.target.radius]) {
            return Err(super::far_message());
        }
        if !p.target.is_valid() {
            return Err("point source: target needs finite center, 0 ≤ inner_radius < radius and azimuth = [from, to] with from < to ≤ from + 360".into());
        }
        if !p.position.iter().all(|x| x.is_finite()) || !p.radius.is_finite() || p.radius < 0.0 {
            return Err("point source: position must be finite and radius ≥ 0".into());
        }
        let dist = (DVec3::from(p.position) - DVec3::from(p.target.center)).length();
        if dist <= p.radius.max(p.target.radius) {
            return Err(InvalidSource::from(
                "point source: the source must be farther from the target centre than both radii",
            ));
        }
        Ok(PointSource::new(
            DVec3::from(p.position),
            p.radius,
            DVec3::from(p.target.center),
            p.target.inner_radius,
            p.target.radius,
            p.target.azimuth,
            p.energy.spectrum(dir)?,
        ))
    }
}
