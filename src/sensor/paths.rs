//! A sensor's flux split by where its photons have been (see `crate::history`):
//! per path class, per (first mirror, last mirror) pair, and, when the sensor asks
//! for it (`history_images = true`), one image per class. Filled in the same
//! fixed order as the image, so it is as reproducible.

use super::exact::{add_all, values, WeightSum};
use crate::history::PathClass;
use std::collections::BTreeMap;

/// Flux and photon counts of one sensor by path.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathTally {
    /// Flux and photons per [`PathClass`] (indexed by its number).
    pub class_flux: [WeightSum; 5],
    pub class_counts: [u64; 5],
    /// Flux and photons per (first mirror, last mirror) object pair
    /// ([`crate::history::NO_MIRROR`] for none).
    pub paths: BTreeMap<(u32, u32), (WeightSum, u64)>,
    /// One image per class (summed over energy bands), if asked for.
    pub class_images: Option<Vec<Vec<WeightSum>>>,
}

impl PathTally {
    /// An empty tally; with `images`, per-class images of `plane` pixels.
    pub fn new(images: bool, plane: usize) -> PathTally {
        PathTally {
            class_images: images.then(|| vec![vec![WeightSum::ZERO; plane]; PathClass::ALL.len()]),
            ..Default::default()
        }
    }

    /// One photon of weight `weight` on pixel `pixel` of a band plane.
    #[inline]
    pub fn record(
        &mut self,
        plane_pixel: usize,
        weight: WeightSum,
        class: PathClass,
        path: (u32, u32),
    ) {
        let c = class as usize;
        self.class_flux[c].add(weight);
        self.class_counts[c] += 1;
        let e = self.paths.entry(path).or_insert((WeightSum::ZERO, 0));
        e.0.add(weight);
        e.1 += 1;
        if let Some(images) = &mut self.class_images {
            images[c][plane_pixel].add(weight);
        }
    }

    /// Adds another tally of the same sensor (exact, in any order).
    pub fn add(&mut self, other: &PathTally) {
        add_all(&mut self.class_flux, &other.class_flux);
        for (a, b) in self.class_counts.iter_mut().zip(&other.class_counts) {
            *a += b;
        }
        for (path, (f, n)) in &other.paths {
            let e = self.paths.entry(*path).or_insert((WeightSum::ZERO, 0));
            e.0.add(*f);
            e.1 += n;
        }
        if let (Some(mine), Some(theirs)) = (&mut self.class_images, &other.class_images) {
            for (a, b) in mine.iter_mut().zip(theirs) {
                add_all(a, b);
            }
        }
    }

    /// Flux per class, indexed by the class's number.
    pub fn class_flux(&self) -> [f64; 5] {
        self.class_flux.map(WeightSum::value)
    }

    /// The per-class images as floating-point flux, if kept.
    pub fn class_images(&self) -> Option<Vec<Vec<f64>>> {
        self.class_images
            .as_ref()
            .map(|images| images.iter().map(|i| values(i)).collect())
    }
}
