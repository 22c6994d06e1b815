//! A plane wave filling an aperture disk, annulus or annulus sector: an X-ray
//! source at infinity, optionally off axis.

use super::{
    far_from_origin, frame, AnnulusSector, ApertureDesc, EnergyDesc, InvalidSource, Photon,
    Spectrum,
};
use crate::random::PhotonRng;
use glam::DVec3;
use serde::Deserialize;

#[derive(Clone, Debug)]
pub struct ParallelBeam {
    /// Where photons start: perpendicular to the nominal direction.
    pub aperture: AnnulusSector,
    /// Nominal direction of travel (unit).
    pub axis: DVec3,
    /// Unit direction of every photon: `axis` tilted by the off-axis angle.
    pub direction: DVec3,
    /// Direction of the tilt (degrees, see [`ParallelBeam::new`]).
    pub off_axis_azimuth: f64,
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
            off_axis_azimuth: azimuth,
            spectrum,
        }
    }

    /// The same beam tilted by `off_axis` degrees (in the same direction).
    pub fn tilted(&self, off_axis: f64) -> ParallelBeam {
        ParallelBeam::new(
            self.aperture.clone(),
            self.axis,
            off_axis,
            self.off_axis_azimuth,
            self.spectrum.clone(),
        )
    }

    /// The beam's cross-section through the aperture (mm²): the aperture's area
    /// projected on the plane perpendicular to the photons.
    pub fn cross_section(&self) -> f64 {
        self.area() * self.direction.dot(self.axis).abs()
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
            process: 0,
            cell: 0,
        }
    }
}

/// `type = "parallel"` in a scene file's `[[sources]]`.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct ParallelDesc {
    #[serde(default = "minus_z")]
    pub direction: [f64; 3],
    #[serde(default)]
    pub off_axis: f64,
    #[serde(default)]
    pub off_axis_azimuth: f64,
    pub aperture: ApertureDesc,
    pub energy: EnergyDesc,
}

fn minus_z() -> [f64; 3] {
    [0.0, 0.0, -1.0]
}

impl ParallelDesc {
    /// The beam, or what is wrong with its parameters.
    pub fn build(&self, dir: &std::path::Path) -> Result<ParallelBeam, InvalidSource> {
        let p = self;
        if far_from_origin(&[p.aperture.center], &[p.aperture.radius]) {
            return Err(super::far_message());
        }
        if !p.aperture.is_valid() {
            return Err("parallel source: aperture needs finite center, 0 ≤ inner_radius < radius and azimuth = [from, to] with from < to ≤ from + 360".into());
        }
        let Some(axis) = DVec3::from(p.direction).try_normalize() else {
            return Err("parallel source: direction must be a non-zero vector".into());
        };
        if !(p.off_axis.is_finite() && p.off_axis_azimuth.is_finite()) || p.off_axis.abs() >= 90.0 {
            return Err("parallel source: off_axis must be below 90 degrees".into());
        }
        let aperture = AnnulusSector::new(
            DVec3::from(p.aperture.center),
            axis,
            p.aperture.inner_radius,
            p.aperture.radius,
            p.aperture.azimuth,
        );
        Ok(ParallelBeam::new(
            aperture,
            axis,
            p.off_axis,
            p.off_axis_azimuth,
            p.energy.spectrum(dir)?,
        ))
    }
}
