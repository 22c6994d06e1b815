//! Azimuth ranges: the segments of surfaces of revolution and disks (the LLNL
//! telescope's 30° shells), as an interval of angles about the local z axis.
//!
//! A point's membership is decided with two cross products against the unit
//! vectors of the range's edges, computed once: no `atan2` in the photon loop
//! (it was 3 % of a PANTER run).

/// An azimuth interval [start, start + span] in degrees, measured from local +x
/// towards +y. A span of 360° or more is the full circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AzimuthRange {
    start_deg: f64,
    span_deg: f64,
    /// Unit vectors (cos, sin) of the first and the last edge.
    first: (f64, f64),
    last: (f64, f64),
}

/// s(e, p) = e × p (z component): ≥ 0 when p lies counter-clockwise of e, within
/// half a turn.
#[inline]
fn cross(e: (f64, f64), x: f64, y: f64) -> f64 {
    e.0 * y - e.1 * x
}

fn unit(deg: f64) -> (f64, f64) {
    let r = deg.to_radians();
    (r.cos(), r.sin())
}

impl AzimuthRange {
    pub const FULL: AzimuthRange = AzimuthRange {
        start_deg: 0.0,
        span_deg: 360.0,
        first: (1.0, 0.0),
        last: (1.0, 0.0),
    };

    /// The range [start_deg, start_deg + span_deg] (degrees, span > 0).
    pub fn new(start_deg: f64, span_deg: f64) -> AzimuthRange {
        AzimuthRange {
            start_deg,
            span_deg,
            first: unit(start_deg),
            last: unit(start_deg + span_deg.min(360.0)),
        }
    }

    pub fn start_deg(&self) -> f64 {
        self.start_deg
    }

    pub fn span_deg(&self) -> f64 {
        self.span_deg
    }

    pub fn is_full(&self) -> bool {
        self.span_deg >= 360.0
    }

    /// Whether the direction (x, y) lies inside the range (edges included).
    #[inline]
    pub fn contains(&self, x: f64, y: f64) -> bool {
        if self.is_full() {
            return true;
        }
        let after_first = cross(self.first, x, y) >= 0.0;
        let before_last = cross(self.last, x, y) <= 0.0;
        if self.span_deg <= 180.0 {
            after_first && before_last
        } else {
            // The complement is an open sector of less than half a turn.
            after_first || before_last
        }
    }

    /// The range cut into `n` equal sectors (n ≥ 1) that share their edges
    /// exactly: a point on an edge belongs to both neighbours, so no direction
    /// falls between them (the full circle's last edge is its first).
    pub fn sectors(&self, n: usize) -> Vec<AzimuthRange> {
        let n = n.max(1);
        let span = self.span_deg.min(360.0);
        let width = span / n as f64;
        let edge = |k: usize| self.start_deg + width * k as f64;
        (0..n)
            .map(|k| {
                let mut s = AzimuthRange::new(edge(k), width);
                s.first = if k == 0 { self.first } else { unit(edge(k)) };
                s.last = if k + 1 == n {
                    self.last
                } else {
                    unit(edge(k + 1))
                };
                s
            })
            .collect()
    }

    /// Unit-circle points bounding the range: its two ends and every axis direction
    /// inside it (for bounding boxes).
    pub(crate) fn extreme_directions(&self) -> Vec<(f64, f64)> {
        let mut dirs = vec![self.first, self.last];
        for (x, y) in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)] {
            if self.contains(x, y) {
                dirs.push((x, y));
            }
        }
        dirs
    }
}
