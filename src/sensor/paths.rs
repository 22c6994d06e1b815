//! A sensor's flux split by where its photons have been (see `crate::history`):
//! per path class, per (first mirror, last mirror) pair, and, when the sensor asks
//! for it (`history_images = true`), one image per class. Filled in the same
//! fixed order as the image, so it is as reproducible.

use crate::history::PathClass;
use std::collections::BTreeMap;

/// Flux and photon counts of one sensor by path.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PathTally {
    /// Flux and photons per [`PathClass`] (indexed by its number).
    pub class_flux: [f64; 5],
    pub class_counts: [u64; 5],
    /// Flux and photons per (first mirror, last mirror) object pair
    /// ([`crate::history::NO_MIRROR`] for none).
    pub paths: BTreeMap<(u32, u32), (f64, u64)>,
    /// One image per class (summed over energy bands), if asked for.
    pub class_images: Option<Vec<Vec<f64>>>,
}

impl PathTally {
    /// An empty tally; with `images`, per-class images of `plane` pixels.
    pub fn new(images: bool, plane: usize) -> PathTally {
        PathTally {
            class_images: images.then(|| vec![vec![0.0; plane]; PathClass::ALL.len()]),
            ..Default::default()
        }
    }

    /// One photon of weight `weight` on pixel `pixel` of a band plane.
    #[inline]
    pub fn record(&mut self, plane_pixel: usize, weight: f64, class: PathClass, path: (u32, u32)) {
        let c = class as usize;
        self.class_flux[c] += weight;
        self.class_counts[c] += 1;
        let e = self.paths.entry(path).or_insert((0.0, 0));
        e.0 += weight;
        e.1 += 1;
        if let Some(images) = &mut self.class_images {
            images[c][plane_pixel] += weight;
        }
    }
}
