//! Image sensors: a pixel grid in an object's local x–y plane that absorbs photons
//! and accumulates their weights ("flux") and their number ("counts").
//!
//! Data flow: `scene::build` creates a [`SensorSpec`] for each object whose material
//! is a sensor; `trace` maps hits to pixels with [`SensorSpec::pixel`] and merges
//! per-chunk records into a [`SensorImage`] in a fixed order; `output` writes it.

use glam::DVec3;

/// Geometry of one sensor. Pixel (0, 0) is at local (−w/2, −h/2); ix grows with
/// local x, iy with local y. Images are stored row-major as [iy][ix].
#[derive(Clone, Debug, serde::Serialize)]
pub struct SensorSpec {
    /// Name of the object carrying the sensor (also the output file stem).
    pub name: String,
    /// Index of that object in the scene.
    pub object: usize,
    /// Active area (mm) along local x and y.
    pub size: [f64; 2],
    /// Pixels along local x and y.
    pub pixels: [u32; 2],
}

impl SensorSpec {
    /// Linear pixel index of a local-frame point, or `None` outside the active area.
    #[inline]
    pub fn pixel(&self, local: DVec3) -> Option<u32> {
        let fx = (local.x / self.size[0] + 0.5) * self.pixels[0] as f64;
        let fy = (local.y / self.size[1] + 0.5) * self.pixels[1] as f64;
        if !(fx >= 0.0 && fy >= 0.0) {
            return None; // also rejects NaN
        }
        let (ix, iy) = (fx as u64, fy as u64);
        if ix >= self.pixels[0] as u64 || iy >= self.pixels[1] as u64 {
            return None;
        }
        Some((iy * self.pixels[0] as u64 + ix) as u32)
    }

    /// Pixel pitch (mm) along x and y.
    pub fn pitch(&self) -> [f64; 2] {
        [
            self.size[0] / self.pixels[0] as f64,
            self.size[1] / self.pixels[1] as f64,
        ]
    }

    pub fn pixel_count(&self) -> usize {
        self.pixels[0] as usize * self.pixels[1] as usize
    }
}

/// Accumulated image of one sensor.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorImage {
    /// Sum of photon weights per pixel.
    pub flux: Vec<f64>,
    /// Number of photons per pixel.
    pub counts: Vec<u64>,
}

impl SensorImage {
    pub fn new(spec: &SensorSpec) -> SensorImage {
        SensorImage {
            flux: vec![0.0; spec.pixel_count()],
            counts: vec![0; spec.pixel_count()],
        }
    }

    #[inline]
    pub fn record(&mut self, pixel: u32, weight: f64) {
        self.flux[pixel as usize] += weight;
        self.counts[pixel as usize] += 1;
    }

    pub fn total_flux(&self) -> f64 {
        self.flux.iter().sum()
    }

    pub fn total_counts(&self) -> u64 {
        self.counts.iter().sum()
    }
}
