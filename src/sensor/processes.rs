//! A sensor's flux by emission process: one image (summed over energy bands) per
//! process of the source, e.g. Primakoff and ABC of a Sun with both couplings,
//! so that a limit calculation can build the image for any couplings from one
//! run. Sums are exact ([`super::exact`]), like the total's: every photon adds
//! its weight, truncated the same way, to the total and to its process, so the
//! processes' images add up to the total image.
//!
//! Data flow: `trace` records each photon's process ([`crate::source::Photon`]);
//! [`super::SensorImage::record`] adds it here; `output` writes one image per
//! process.

use super::exact::{self, WeightSum};

/// Flux images and photon counts per process (none for a one-process source).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ProcessTally {
    /// One image of `plane` pixels per process.
    pub images: Vec<Vec<WeightSum>>,
    /// Photons recorded per process (for ABC's four: photons with a share of
    /// their weight in it).
    pub counts: Vec<u64>,
}

impl ProcessTally {
    /// Zeroed images for `processes` processes of `plane` pixels.
    pub fn new(processes: usize, plane: usize) -> ProcessTally {
        ProcessTally {
            images: vec![vec![WeightSum::ZERO; plane]; processes],
            counts: vec![0; processes],
        }
    }

    /// A photon of weight `weight` (and `fixed`, the same in fixed point) in
    /// pixel `pixel` of the plane, shared among the images as `shares` says:
    /// a share of 1 adds `fixed` itself, so a process drawn alone adds exactly
    /// what the total adds.
    #[inline]
    pub fn record(
        &mut self,
        pixel: usize,
        (weight, fixed): (f64, WeightSum),
        shares: &crate::source::ProcessWeights,
    ) {
        for &(k, share) in shares.iter() {
            let Some(image) = self.images.get_mut(k as usize) else {
                continue;
            };
            image[pixel].add(if share == 1.0 {
                fixed
            } else {
                WeightSum::of(weight * share)
            });
            if share > 0.0 {
                self.counts[k as usize] += 1;
            }
        }
    }

    /// Adds another part of the same run.
    pub fn add(&mut self, other: &ProcessTally) {
        for (a, b) in self.images.iter_mut().zip(&other.images) {
            exact::add_all(a, b);
        }
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
    }

    /// How many processes are tallied.
    pub fn len(&self) -> usize {
        self.images.len()
    }

    /// Whether no process is tallied.
    pub fn is_empty(&self) -> bool {
        self.images.is_empty()
    }

    /// Process `k`'s image as floating-point numbers (sums of weights): one
    /// dense image at a time, since a large sensor's are 12 MB each.
    pub fn image(&self, k: usize) -> Vec<f64> {
        exact::values(&self.images[k])
    }

    /// Each process's summed weight, exact.
    pub fn totals(&self) -> Vec<f64> {
        self.images
            .iter()
            .map(|i| {
                let mut t = WeightSum::ZERO;
                for s in i {
                    t.add(*s);
                }
                t.value()
            })
            .collect()
    }
}
