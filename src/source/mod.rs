//! Photon sources: where photons start, in which direction, with which energy and
//! weight.
//!
//! Data flow: `scene::build` turns each `[[sources]]` entry into a [`Source`];
//! `trace` calls [`Source::emit`] with photon i's own random stream.

mod annulus;
mod parallel;
mod point;
mod spectrum;

pub use annulus::AnnulusSector;
pub use parallel::ParallelBeam;
pub use point::PointSource;
pub use spectrum::Spectrum;

use crate::random::PhotonRng;
use glam::DVec3;

/// A photon as it leaves a source.
#[derive(Clone, Copy, Debug)]
pub struct Photon {
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
    /// keV.
    pub energy: f64,
    /// Starts at the source's sampling weight; interactions only multiply it.
    pub weight: f64,
}

#[derive(Clone, Debug)]
pub enum Source {
    Parallel(ParallelBeam),
    Point(PointSource),
}

impl Source {
    #[inline]
    pub fn emit(&self, rng: &mut PhotonRng) -> Photon {
        match self {
            Source::Parallel(s) => s.emit(rng),
            Source::Point(s) => s.emit(rng),
        }
    }

    pub fn spectrum(&self) -> Spectrum {
        match self {
            Source::Parallel(s) => s.spectrum,
            Source::Point(s) => s.spectrum,
        }
    }

    /// What one photon's weight means, for the JSON summary.
    pub fn describe_weight(&self) -> &'static str {
        match self {
            Source::Parallel(_) => {
                "weight 1 per photon; each photon stands for aperture.area_mm2 / photons of the beam"
            }
            Source::Point(_) => {
                "weight = fraction of the full sphere; the image is the expected photons per pixel if the source emitted `photons` photons isotropically"
            }
        }
    }
}

/// Two unit vectors completing `axis` to an orthonormal frame: `e1` is the part of
/// world +x perpendicular to the axis (world +y if the axis is along x), and
/// e2 = e1 × axis.
pub(crate) fn frame(axis: DVec3) -> (DVec3, DVec3) {
    let pick = if axis.x.abs() < 0.9 {
        DVec3::X
    } else {
        DVec3::Y
    };
    let e1 = (pick - axis * pick.dot(axis)).normalize();
    (e1, e1.cross(axis))
}
