//! A flat annulus sector (aperture or target of a source): where photons start or
//! are aimed, sampled uniformly over its area.

use super::frame;
use crate::geometry::AzimuthRange;
use crate::random::PhotonRng;
use glam::DVec3;
use serde::Deserialize;

#[derive(Clone, Debug)]
pub struct AnnulusSector {
    pub center: DVec3,
    pub inner_radius: f64,
    pub radius: f64,
    /// Azimuth range (radians) from e1 towards e2, e1 and e2 spanning the plane.
    pub phi_start: f64,
    pub phi_span: f64,
    e1: DVec3,
    e2: DVec3,
    azimuth: AzimuthRange,
    /// Box [x_lo, x_hi, y_lo, y_hi] around the sector in the (e1, e2) plane, for
    /// sampling by rejection when the sector fills at least half of it.
    bbox: [f64; 4],
    by_rejection: bool,
}

impl AnnulusSector {
    /// The sector perpendicular to `travel` (the direction photons cross it in):
    /// azimuth 0 is along e1 (the part of +x perpendicular to `travel`) and grows
    /// towards e2 = e1 × travel — for travel along −z, from +x towards +y.
    /// `azimuth_deg` = None is the full circle.
    pub fn new(
        center: DVec3,
        travel: DVec3,
        inner_radius: f64,
        radius: f64,
        azimuth_deg: Option<[f64; 2]>,
    ) -> Self {
        let (e1, e2) = frame(travel.normalize());
        let (phi_start, phi_span, azimuth) = match azimuth_deg {
            Some([a, b]) => (
                a.to_radians(),
                (b - a).to_radians(),
                AzimuthRange::new(a, b - a),
            ),
            None => (0.0, std::f64::consts::TAU, AzimuthRange::FULL),
        };
        let mut bbox = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for (x, y) in azimuth.extreme_directions() {
            for r in [inner_radius, radius] {
                bbox = [
                    bbox[0].min(r * x),
                    bbox[1].max(r * x),
                    bbox[2].min(r * y),
                    bbox[3].max(r * y),
                ];
            }
        }
        let mut sector = AnnulusSector {
            center,
            inner_radius,
            radius,
            phi_start,
            phi_span,
            e1,
            e2,
            azimuth,
            bbox,
            by_rejection: false,
        };
        let box_area = (bbox[1] - bbox[0]) * (bbox[3] - bbox[2]);
        sector.by_rejection = sector.area() >= 0.5 * box_area;
        sector
    }

    /// Area (mm²).
    pub fn area(&self) -> f64 {
        0.5 * self.phi_span * (self.radius * self.radius - self.inner_radius * self.inner_radius)
    }

    /// A uniform point on the sector: by rejection from its bounding box when
    /// the sector fills at least half of it (no sin/cos; on average fewer than
    /// four uniform draws), else in polar coordinates.
    #[inline]
    pub fn sample(&self, rng: &mut PhotonRng) -> DVec3 {
        let (r_in, r_out) = (self.inner_radius, self.radius);
        if self.by_rejection {
            let [x_lo, x_hi, y_lo, y_hi] = self.bbox;
            let (r_in2, r_out2) = (r_in * r_in, r_out * r_out);
            loop {
                let x = x_lo + (x_hi - x_lo) * rng.uniform();
                let y = y_lo + (y_hi - y_lo) * rng.uniform();
                let r2 = x * x + y * y;
                if r2 <= r_out2 && r2 >= r_in2 && self.azimuth.contains(x, y) {
                    return self.center + self.e1 * x + self.e2 * y;
                }
            }
        }
        let r = (r_in * r_in + rng.uniform() * (r_out * r_out - r_in * r_in)).sqrt();
        let phi = self.phi_start + self.phi_span * rng.uniform();
        self.center + (self.e1 * phi.cos() + self.e2 * phi.sin()) * r
    }
}

/// An aperture or target disk, annulus or sector in a scene file.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct ApertureDesc {
    pub center: [f64; 3],
    pub radius: f64,
    #[serde(default)]
    pub inner_radius: f64,
    /// Optional sector `[from, to]` in degrees (from e1 towards e2; for photons
    /// travelling along −z: from +x towards +y). Default: the full circle.
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

impl ApertureDesc {
    /// Whether the numbers describe a disk, annulus or sector.
    pub(super) fn is_valid(&self) -> bool {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        self.azimuth
            .is_none_or(|[f, t]| f.is_finite() && t.is_finite() && f < t && t - f <= 360.0)
            && finite(&self.center)
            && finite(&[self.radius, self.inner_radius])
            && self.radius > 0.0
            && self.inner_radius >= 0.0
            && self.inner_radius < self.radius
    }
}

#[cfg(test)]
mod tests {
    use super::AnnulusSector;
    use crate::random::PhotonRng;
    use glam::DVec3;

    /// Points fall inside the sector, uniformly over its area: ⟨r²⟩ is the mean of
    /// the two squared radii, and each half of the azimuth range and each of the
    /// inner and outer halves in r² get half of the points (5 standard errors).
    /// Covers both ways of sampling: rejection (disk, the PANTER target sector)
    /// and polar (a thin annulus, a thin sector).
    #[test]
    fn samples_are_uniform_over_the_sector() {
        let cases = [
            (0.0, 0.42, None, true),
            (58.0, 106.0, Some([-16.0, 16.0]), true),
            (0.0, 60.0, Some([90.0, 350.0]), true),
            (95.0, 100.0, None, false),
            (10.0, 100.0, Some([40.0, 43.0]), false),
        ];
        let n = 100_000;
        for (r_in, r_out, az, rejection) in cases {
            let center = DVec3::new(1.0, 2.0, 3.0);
            let a = AnnulusSector::new(center, DVec3::NEG_Z, r_in, r_out, az);
            assert_eq!(a.by_rejection, rejection, "{r_in} {r_out} {az:?}");
            let [from, to] = az.unwrap_or([0.0, 360.0]);
            let mid = 0.5 * (from + to);
            let (mut r2_sum, mut outer, mut first_half) = (0.0, 0, 0);
            let r2_mid = 0.5 * (r_in * r_in + r_out * r_out);
            for i in 0..n {
                let p = a.sample(&mut PhotonRng::new(3, i)) - center;
                assert!(p.z.abs() < 1e-12);
                let r2 = p.x * p.x + p.y * p.y;
                let r = r2.sqrt();
                assert!(r >= r_in * (1.0 - 1e-12) && r <= r_out * (1.0 + 1e-12));
                let phi = p.y.atan2(p.x).to_degrees();
                let phi = from + (phi - from).rem_euclid(360.0);
                assert!(phi <= to + 1e-9, "{phi} outside {from}..{to}");
                r2_sum += r2;
                outer += (r2 > r2_mid) as u32;
                first_half += (phi < mid) as u32;
            }
            let nf = n as f64;
            // r² is uniform on [r_in², r_out²]: sd (r_out² − r_in²)/√12.
            let sd = (r_out * r_out - r_in * r_in) / 12f64.sqrt() / nf.sqrt();
            assert!(
                (r2_sum / nf - r2_mid).abs() < 5.0 * sd,
                "{r_in} {r_out} {az:?}"
            );
            let half_sd = 0.5 / nf.sqrt();
            assert!((outer as f64 / nf - 0.5).abs() < 5.0 * half_sd);
            assert!((first_half as f64 / nf - 0.5).abs() < 5.0 * half_sd);
        }
    }
}
