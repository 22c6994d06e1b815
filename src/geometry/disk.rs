//! Flat disk or annulus in the local z = 0 plane, centred on the origin, facing +z.

use super::{quadric::AzimuthRange, Resolution};
use crate::mesh::TriangleMesh;
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    pub inner_radius: f64,
    pub outer_radius: f64,
    pub azimuth: AzimuthRange,
}

impl Disk {
    #[inline]
    pub fn intersect(
        &self,
        o: DVec3,
        d: DVec3,
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64> {
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

    pub fn normal(&self) -> DVec3 {
        DVec3::Z
    }

    pub fn bounds(&self) -> (DVec3, DVec3) {
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
    pub fn tessellate(&self, res: Resolution) -> TriangleMesh {
        let n_phi = res.segments.max(3);
        let n_r = res.rings.max(1);
        let span = self.azimuth.span_deg.min(360.0);
        let closed = self.azimuth.is_full();
        let cols = if closed { n_phi } else { n_phi + 1 };
        let mut mesh = TriangleMesh::default();
        for j in 0..=n_r {
            let r =
                self.inner_radius + (self.outer_radius - self.inner_radius) * j as f64 / n_r as f64;
            for i in 0..cols {
                let phi = (self.azimuth.start_deg + span * i as f64 / n_phi as f64).to_radians();
                mesh.positions
                    .push(DVec3::new(r * phi.cos(), r * phi.sin(), 0.0));
            }
        }
        for j in 0..n_r {
            for i in 0..n_phi {
                let i1 = (i + 1) % cols;
                let v00 = (j * cols + i) as u32;
                let v01 = (j * cols + i1) as u32;
                let v10 = ((j + 1) * cols + i) as u32;
                let v11 = ((j + 1) * cols + i1) as u32;
                if j == 0 && self.inner_radius == 0.0 {
                    // innermost ring collapses to the centre: one triangle per sector
                    mesh.triangles.push([v00, v11, v10]);
                } else {
                    mesh.triangles.push([v00, v01, v11]);
                    mesh.triangles.push([v00, v11, v10]);
                }
            }
        }
        mesh.normals = Some(vec![DVec3::Z; mesh.positions.len()]);
        mesh.orient_to_normals();
        mesh
    }
}
