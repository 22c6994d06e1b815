//! Rectangle in the local z = 0 plane, centred on the origin, facing +z; its sides
//! run along local x (width) and y (height). Image sensors are usually rectangles.

use super::Resolution;
use super::{Surface, TriangleMesh};
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
    pub width: f64,
    pub height: f64,
}

impl Surface for Rectangle {
    #[inline]
    fn intersect(&self, o: DVec3, d: DVec3, t_max: f64, starts_on_surface: bool) -> Option<f64> {
        if starts_on_surface || d.z == 0.0 {
            return None;
        }
        let t = -o.z / d.z;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let x = o.x + t * d.x;
        let y = o.y + t * d.y;
        (x.abs() <= 0.5 * self.width && y.abs() <= 0.5 * self.height).then_some(t)
    }

    #[inline]
    fn normal(&self, _p: DVec3) -> DVec3 {
        DVec3::Z
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        let h = DVec3::new(0.5 * self.width, 0.5 * self.height, 0.0);
        (-h, h)
    }

    /// `segments` × `rings` grid (x × y) of quads.
    fn tessellate(&self, res: Resolution) -> TriangleMesh {
        let nx = res.segments.max(1);
        let ny = res.rings.max(1);
        let mut mesh = TriangleMesh::default();
        for j in 0..=ny {
            for i in 0..=nx {
                mesh.positions.push(DVec3::new(
                    self.width * (i as f64 / nx as f64 - 0.5),
                    self.height * (j as f64 / ny as f64 - 0.5),
                    0.0,
                ));
            }
        }
        let cols = (nx + 1) as u32;
        for j in 0..ny as u32 {
            for i in 0..nx as u32 {
                let v00 = j * cols + i;
                mesh.triangles.push([v00, v00 + 1, v00 + cols + 1]);
                mesh.triangles.push([v00, v00 + cols + 1, v00 + cols]);
            }
        }
        mesh.normals = Some(vec![DVec3::Z; mesh.positions.len()]);
        mesh
    }
}
