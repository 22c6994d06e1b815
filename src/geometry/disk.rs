//! Flat disk or annulus in the local z = 0 plane, centred on the origin, facing +z.

use super::grid::polar_grid;
use super::{AzimuthRange, Resolution};
use super::{Surface, TriangleMesh};
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    pub inner_radius: f64,
    pub outer_radius: f64,
    pub azimuth: AzimuthRange,
}

impl Surface for Disk {
    #[inline]
    fn intersect(&self, o: DVec3, d: DVec3, t_max: f64, starts_on_surface: bool) -> Option<f64> {
        if starts_on_surface || d.z == 0.0 {
            return None; // a plane cannot be hit again by a ray leaving it
        }
        let t = -o.z / d.z;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let x = o.x + t * d.x;
        let y = o.y + t * d.y;
        let r2 = x * x + y * y;
        let inside = r2 <= self.outer_radius * self.outer_radius
            && r2 >= self.inner_radius * self.inner_radius
            && self.azimuth.contains(x, y);
        inside.then_some(t)
    }

    #[inline]
    fn normal(&self, _p: DVec3) -> DVec3 {
        DVec3::Z
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::new(f64::INFINITY, f64::INFINITY, 0.0);
        let mut hi = DVec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, 0.0);
        for (x, y) in self.azimuth.extreme_directions() {
            for r in [self.inner_radius, self.outer_radius] {
                lo = lo.min(DVec3::new(r * x, r * y, 0.0));
                hi = hi.max(DVec3::new(r * x, r * y, 0.0));
            }
        }
        (lo, hi)
    }

    /// `segments` around, `rings` radial steps. A full disk without a hole gets a
    /// centre fan; the outer edge is inscribed (vertices on the circle).
    fn tessellate(&self, res: Resolution) -> TriangleMesh {
        let n_r = res.rings.max(1);
        let (positions, triangles) = polar_grid(
            &self.azimuth,
            res.segments.max(3),
            n_r,
            self.inner_radius == 0.0,
            |j, phi| {
                let r = self.inner_radius
                    + (self.outer_radius - self.inner_radius) * j as f64 / n_r as f64;
                DVec3::new(r * phi.cos(), r * phi.sin(), 0.0)
            },
        );
        let normals = vec![DVec3::Z; positions.len()];
        let mut mesh = TriangleMesh {
            positions,
            normals: Some(normals),
            triangles,
        };
        mesh.orient_to_normals();
        mesh
    }
}
