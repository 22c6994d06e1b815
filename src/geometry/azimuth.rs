//! Azimuth ranges: the segments of surfaces of revolution and disks (the LLNL
//! telescope's 30° shells), as an interval of angles about the local z axis.

/// An azimuth interval [start, start + span] in degrees, measured from local +x
/// towards +y. A span of 360° or more is the full circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AzimuthRange {
    pub start_deg: f64,
    pub span_deg: f64,
}

impl AzimuthRange {
    pub const FULL: AzimuthRange = AzimuthRange {
        start_deg: 0.0,
        span_deg: 360.0,
    };

    pub fn is_full(&self) -> bool {
        self.span_deg >= 360.0
    }

    /// Whether the direction (x, y) lies inside the range.
    #[inline]
    pub fn contains(&self, x: f64, y: f64) -> bool {
        if self.is_full() {
            return true;
        }
        let phi = y.atan2(x).to_degrees();
        (phi - self.start_deg).rem_euclid(360.0) <= self.span_deg
    }

    /// Unit-circle points bounding the range: its two ends and every axis direction
    /// inside it (for bounding boxes).
    pub(crate) fn extreme_directions(&self) -> Vec<(f64, f64)> {
        let mut dirs = Vec::new();
        let end = self.start_deg + self.span_deg.min(360.0);
        for phi in [self.start_deg, end] {
            let r = phi.to_radians();
            dirs.push((r.cos(), r.sin()));
        }
        for (x, y) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)] {
            if self.contains(x, y) {
                dirs.push((x, y));
            }
        }
        dirs
    }
}
