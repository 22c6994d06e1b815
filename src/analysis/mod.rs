//! Image analysis that physicists quote: flux-weighted centroid, encircled-energy
//! function (EEF, each pixel's flux spread over its area: [`eef`]), and the
//! diameters holding 50 % (HPD), 80 % and 90 % of the flux, in mm and in
//! arcseconds (2·atan(r/f)); x and y projections.
//!
//! Data flow: `output` calls [`analyse`] on every sensor image after a trace (and
//! plots the EEF);
//! `traxer eef` calls it on any `.npy` image; `traxer focus` on a sweep of
//! sensor positions, whose diameters [`focus::fit_defocus`] fits.

pub mod centre;
pub mod combined;
mod doubts;
pub mod eef;
mod finished;
pub mod focus;
pub mod reach;
pub mod signal;

pub use doubts::doubts;
pub use finished::{image_shape, FinishedImage};

use eef::EncircledFlux;

/// The angle (arcseconds) under which a radius of `r_mm` on the sensor is seen
/// from the optics at focal length `focal_length_mm`: atan(r/f).
pub fn arcsec_of_radius(r_mm: f64, focal_length_mm: f64) -> f64 {
    (r_mm / focal_length_mm).atan().to_degrees() * 3600.0
}

/// The angular diameter (arcseconds) of a circle of diameter `d_mm`: 2·atan(d/2f).
pub fn arcsec_of_diameter(d_mm: f64, focal_length_mm: f64) -> f64 {
    2.0 * arcsec_of_radius(0.5 * d_mm, focal_length_mm)
}

/// Results for one image.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ImageQuality {
    /// Flux-weighted centroid (mm) in the sensor's local frame.
    pub centroid_mm: [f64; 2],
    pub total_flux: f64,
    /// Diameters (mm) holding 50, 80 and 90 % of the flux around the centroid.
    pub hpd_mm: f64,
    pub d80_mm: f64,
    pub d90_mm: f64,
    /// The same in arcseconds, when a focal length is known.
    pub focal_length_mm: Option<f64>,
    pub hpd_arcsec: Option<f64>,
    pub d80_arcsec: Option<f64>,
    pub d90_arcsec: Option<f64>,
}

/// Encircled-energy function: radii (mm, ascending) and the flux fraction inside.
#[derive(Clone, Debug)]
pub struct Eef {
    pub radius_mm: Vec<f64>,
    pub fraction: Vec<f64>,
}

impl Eef {
    /// Smallest radius holding `fraction` of the flux, interpolated linearly
    /// between pixels.
    pub fn radius_at(&self, fraction: f64) -> f64 {
        let i = self.fraction.partition_point(|&f| f < fraction);
        if i == 0 {
            return self.radius_mm.first().copied().unwrap_or(0.0);
        }
        if i >= self.fraction.len() {
            return self.radius_mm.last().copied().unwrap_or(0.0);
        }
        let (f0, f1) = (self.fraction[i - 1], self.fraction[i]);
        let (r0, r1) = (self.radius_mm[i - 1], self.radius_mm[i]);
        if f1 > f0 {
            r0 + (r1 - r0) * (fraction - f0) / (f1 - f0)
        } else {
            r1
        }
    }
}

/// A 2-D image [iy][ix] with its geometry: pixel (0, 0) has its corner at
/// (x0, y0) mm; pixels are `pitch` mm.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageGeometry {
    pub nx: usize,
    pub ny: usize,
    pub pitch: [f64; 2],
    pub origin_mm: [f64; 2],
}

impl ImageGeometry {
    /// The geometry of a traxer sensor's image (centred on the sensor's origin).
    pub fn of_sensor(spec: &crate::sensor::SensorSpec) -> ImageGeometry {
        ImageGeometry {
            nx: spec.pixels[0] as usize,
            ny: spec.pixels[1] as usize,
            pitch: spec.pitch(),
            origin_mm: [-0.5 * spec.size[0], -0.5 * spec.size[1]],
        }
    }

    fn center(&self, ix: usize, iy: usize) -> (f64, f64) {
        (
            self.origin_mm[0] + (ix as f64 + 0.5) * self.pitch[0],
            self.origin_mm[1] + (iy as f64 + 0.5) * self.pitch[1],
        )
    }
}

/// Centroid, EEF and diameters of `image` (row-major [iy][ix], flux ≥ 0).
/// Returns `None` for an image without flux.
pub fn analyse(
    image: &[f64],
    g: &ImageGeometry,
    focal_length_mm: Option<f64>,
) -> Option<(ImageQuality, Eef)> {
    let total: f64 = image.iter().sum();
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    let (mut sx, mut sy) = (0.0, 0.0);
    for (k, &v) in image.iter().enumerate() {
        if v != 0.0 {
            let (x, y) = g.center(k % g.nx, k / g.nx);
            sx += v * x;
            sy += v * y;
        }
    }
    let (cx, cy) = (sx / total, sy / total);
    let encircled = encircled_about(image, g, [cx, cy]);
    // The curve for plots: steps of half a pixel, at most 4000 points.
    let outer = encircled.outer_radius();
    let step = (0.5 * g.pitch[0].min(g.pitch[1])).max(outer / 4000.0);
    let n = (outer / step).ceil() as usize;
    let radius_mm: Vec<f64> = (0..=n).map(|i| (i as f64 * step).min(outer)).collect();
    let fraction = radius_mm
        .iter()
        .map(|&r| encircled.fraction_within(r))
        .collect();
    let eef = Eef {
        radius_mm,
        fraction,
    };
    let d = |f: f64| 2.0 * encircled.radius_at(f);
    let arcsec = |diam: f64| focal_length_mm.map(|fl| arcsec_of_diameter(diam, fl));
    let (hpd, d80, d90) = (d(0.5), d(0.8), d(0.9));
    Some((
        ImageQuality {
            centroid_mm: [cx, cy],
            total_flux: total,
            hpd_mm: hpd,
            d80_mm: d80,
            d90_mm: d90,
            focal_length_mm,
            hpd_arcsec: arcsec(hpd),
            d80_arcsec: arcsec(d80),
            d90_arcsec: arcsec(d90),
        },
        eef,
    ))
}

/// The flux of `image` within each radius of `radii_mm` about `centre_mm` (a
/// signal region), each pixel's flux spread over its area as for the EEF.
pub fn flux_within(
    image: &[f64],
    g: &ImageGeometry,
    centre_mm: [f64; 2],
    radii_mm: &[f64],
) -> Vec<f64> {
    let encircled = encircled_about(image, g, centre_mm);
    radii_mm.iter().map(|&r| encircled.flux_within(r)).collect()
}

/// The radius (mm) about `centre_mm` holding `fraction` of the flux of
/// `image`; `None` without flux.
pub fn radius_holding(
    image: &[f64],
    g: &ImageGeometry,
    centre_mm: [f64; 2],
    fraction: f64,
) -> Option<f64> {
    let encircled = encircled_about(image, g, centre_mm);
    (encircled.outer_radius() > 0.0).then(|| encircled.radius_at(fraction))
}

/// The encircled flux of `image` about `centre_mm`: each lit pixel's flux
/// spread over its area (see `eef`), so that circles have no lattice bias.
fn encircled_about(image: &[f64], g: &ImageGeometry, centre_mm: [f64; 2]) -> EncircledFlux {
    EncircledFlux::new(
        centre::image_points(image, g).into_iter().map(|(x, y, v)| {
            (
                x - 0.5 * g.pitch[0] - centre_mm[0],
                y - 0.5 * g.pitch[1] - centre_mm[1],
                v,
            )
        }),
        g.pitch,
    )
}

/// Sums of the image along y (a function of x) and along x (a function of y).
pub fn projections(image: &[f64], g: &ImageGeometry) -> (Vec<f64>, Vec<f64>) {
    let mut px = vec![0.0; g.nx];
    let mut py = vec![0.0; g.ny];
    for (k, &v) in image.iter().enumerate() {
        px[k % g.nx] += v;
        py[k / g.nx] += v;
    }
    (px, py)
}
