//! A sensor's finished image, computed in one place for every consumer (the
//! files `output` writes, the CLI's report, Python's `SensorImage`, the live
//! window, the studies): the flux in the run's units, its sum over energy bands,
//! the image geometry and pixel centres, and the quality (centroid, EEF, HPD /
//! 80 % / 90 %).

use super::{analyse, Eef, ImageGeometry, ImageQuality};
use crate::sensor::{rebin, sum_bands, PixelGrid, Rebinned, SensorImage, SensorSpec};

/// One sensor's image, finished.
pub struct FinishedImage {
    /// `[ny, nx]`, or `[bands, ny, nx]` with energy bins (numpy's order).
    pub shape: Vec<usize>,
    /// Flux per pixel ([band][iy][ix]), times `absolute` if given (axions per
    /// second with a Sun).
    pub flux: Vec<f64>,
    /// The flux summed over bands ([iy][ix]) with energy bins; without, the
    /// flux itself is the sum (not copied: a large sensor's is 32 MB).
    summed_bands: Option<Vec<f64>>,
    pub geometry: ImageGeometry,
    /// Centroid and diameters, and the encircled-flux curve; `None` without flux.
    pub quality: Option<(ImageQuality, Eef)>,
    /// Whether the flux is in axions per second.
    pub absolute: bool,
}

/// A sensor's image array shape in numpy's order: `[ny, nx]`, or `[bands,
/// ny, nx]` with energy bins (flux and counts alike).
pub fn image_shape(spec: &SensorSpec) -> Vec<usize> {
    let (nx, ny) = (spec.pixels[0] as usize, spec.pixels[1] as usize);
    match spec.energy_bins {
        Some((_, _, n)) => vec![n as usize, ny, nx],
        None => vec![ny, nx],
    }
}

impl FinishedImage {
    /// The finished image of `image` on `spec`; `absolute` converts weights to
    /// axions per second (a Sun's runs), `None` keeps the weights.
    pub fn of(spec: &SensorSpec, image: &SensorImage, absolute: Option<f64>) -> FinishedImage {
        let mut flux = image.flux();
        if let Some(k) = absolute {
            flux.iter_mut().for_each(|f| *f *= k);
        }
        let summed_bands = spec
            .energy_bins
            .map(|_| sum_bands(&flux, spec.pixel_count()));
        let geometry = ImageGeometry::of_sensor(spec);
        let summed = summed_bands.as_deref().unwrap_or(&flux);
        let quality = analyse(summed, &geometry, spec.focal_length);
        FinishedImage {
            shape: image_shape(spec),
            flux,
            summed_bands,
            geometry,
            quality,
            absolute: absolute.is_some(),
        }
    }

    /// The flux summed over bands ([iy][ix]).
    pub fn summed(&self) -> &[f64] {
        self.summed_bands.as_deref().unwrap_or(&self.flux)
    }

    /// The total flux.
    pub fn total_flux(&self) -> f64 {
        self.flux.iter().sum()
    }

    /// The quality alone.
    pub fn image_quality(&self) -> Option<&ImageQuality> {
        self.quality.as_ref().map(|(q, _)| q)
    }

    /// The flux summed over bands, rebinned onto the sensor's detector pixel
    /// grid (`pixel_grid`), if it has one.
    pub fn on_grid(&self, spec: &SensorSpec) -> Option<(PixelGrid, Rebinned)> {
        let g = spec.pixel_grid?;
        Some((g, rebin(self.summed(), spec.size, spec.pixels, &g)))
    }

    /// Pixel centres (mm, sensor frame) along x and along y.
    pub fn pixel_centres_mm(&self) -> [Vec<f64>; 2] {
        let g = &self.geometry;
        let centres = |n: usize, origin: f64, pitch: f64| {
            (0..n)
                .map(|i| origin + (i as f64 + 0.5) * pitch)
                .collect::<Vec<f64>>()
        };
        [
            centres(g.nx, g.origin_mm[0], g.pitch[0]),
            centres(g.ny, g.origin_mm[1], g.pitch[1]),
        ]
    }
}
