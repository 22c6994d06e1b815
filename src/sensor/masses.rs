//! A sensor's images for a list of axion masses, from one run: the paths of
//! the photons do not depend on the axion mass, only each axion's conversion
//! probability does, so every recorded photon adds its weight times
//! P(m_k) / P(m_scene) — its own path's ratio — to the image of each mass
//! m_k. Each mass's image has the total's shape ([band][pixel]) and its own
//! per-process images, so that the processes add up to the mass's total as
//! they do for the scene's mass. Sums are exact ([`super::exact`]).
//!
//! Data flow: `trace` computes each recorded photon's ratios with
//! [`crate::magnet::Magnet::convert`]; [`super::SensorImage::record`]
//! adds them here; `output` writes the stack.

use super::exact::{self, WeightSum};
use super::processes::ProcessTally;

/// One mass's images.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MassImage {
    /// As the sensor's `flux_sum`: [band][pixel].
    pub flux_sum: Vec<WeightSum>,
    /// One image of the plane per process of the source.
    pub processes: ProcessTally,
}

/// The images of every mass of the scan, in the scan's order (none without
/// one).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MassTally {
    pub images: Vec<MassImage>,
}

impl MassTally {
    /// Zeroed images for `masses` masses of `pixels` entries ([band][pixel])
    /// and `processes` process images of `plane` pixels each.
    pub fn new(masses: usize, pixels: usize, processes: usize, plane: usize) -> MassTally {
        MassTally {
            images: (0..masses)
                .map(|_| MassImage {
                    flux_sum: vec![WeightSum::ZERO; pixels],
                    processes: ProcessTally::new(processes, plane),
                })
                .collect(),
        }
    }

    /// A photon of weight `weight` (at the scene's mass) in `pixel` (band
    /// included; `in_plane` without it): each mass gets `weight × factor`.
    #[inline]
    pub fn record(
        &mut self,
        (pixel, in_plane): (usize, usize),
        weight: f64,
        factors: &[f64],
        shares: &crate::source::ProcessWeights,
    ) {
        for (image, &f) in self.images.iter_mut().zip(factors) {
            let w = weight * f;
            let fixed = WeightSum::of(w);
            image.flux_sum[pixel].add(fixed);
            image.processes.record(in_plane, (w, fixed), shares);
        }
    }

    /// Adds another part of the same run.
    pub fn add(&mut self, other: &MassTally) {
        for (a, b) in self.images.iter_mut().zip(&other.images) {
            exact::add_all(&mut a.flux_sum, &b.flux_sum);
            a.processes.add(&b.processes);
        }
    }

    /// Each mass's total weight, exact.
    pub fn totals(&self) -> Vec<f64> {
        self.images
            .iter()
            .map(|i| {
                let mut t = WeightSum::ZERO;
                for s in &i.flux_sum {
                    t.add(*s);
                }
                t.value()
            })
            .collect()
    }
}
