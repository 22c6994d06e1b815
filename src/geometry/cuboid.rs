//! Axis-aligned box in the local frame, centred on the origin, facing outwards.

use super::{nearest_root, Resolution, Surface, TriangleMesh};
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cuboid {
    /// Full edge lengths along local x, y, z.
    pub size: DVec3,
}

impl Surface for Cuboid {
    #[inline]
    fn intersect(&self, o: DVec3, d: DVec3, t_max: f64, starts_on_surface: bool) -> Option<f64> {
        let h = 0.5 * self.size;
        let inv = d.recip();
        let t0 = (-h - o) * inv;
        let t1 = (h - o) * inv;
        // NaN (0 × ∞ for a ray in a face plane) must not win min/max: glam's min/max
        // follow f64::min/max, which ignore NaN.
        let t_enter = t0.min(t1).max_element();
        let t_exit = t0.max(t1).min_element();
        // Written so that NaN also means "no hit".
        if t_enter.partial_cmp(&t_exit) == Some(std::cmp::Ordering::Greater)
            || t_enter.is_nan()
            || t_exit.is_nan()
        {
            return None;
        }
        let roots = [t_enter, t_exit];
        nearest_root(&roots, starts_on_surface, t_max, |_| true)
    }

    /// Outward normal of the face a surface point lies on.
    #[inline]
    fn normal(&self, p: DVec3) -> DVec3 {
        let q = p / (0.5 * self.size);
        let a = q.abs();
        if a.x >= a.y && a.x >= a.z {
            DVec3::new(q.x.signum(), 0.0, 0.0)
        } else if a.y >= a.z {
            DVec3::new(0.0, q.y.signum(), 0.0)
        } else {
            DVec3::new(0.0, 0.0, q.z.signum())
        }
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        (-0.5 * self.size, 0.5 * self.size)
    }

    /// Each face a grid of `segments` × `rings` quads (along the face's first and
    /// second in-plane axis, cyclically after its normal axis), with its own
    /// vertices and flat normals; 1 × 1 gives the 12-triangle box.
    fn tessellate(&self, res: Resolution) -> TriangleMesh {
        let h = 0.5 * self.size;
        let (nu, nv) = (res.segments.max(1), res.rings.max(1));
        let mut mesh = TriangleMesh::default();
        let mut normals = Vec::new();
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut n = DVec3::ZERO;
                n[axis] = sign;
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let base = mesh.positions.len() as u32;
                for j in 0..=nv {
                    for i in 0..=nu {
                        let mut p = DVec3::ZERO;
                        p[axis] = sign * h[axis];
                        p[u] = (2.0 * i as f64 / nu as f64 - 1.0) * h[u];
                        p[v] = (2.0 * j as f64 / nv as f64 - 1.0) * h[v];
                        mesh.positions.push(p);
                        normals.push(n);
                    }
                }
                let row = nu as u32 + 1;
                for j in 0..nv as u32 {
                    for i in 0..nu as u32 {
                        let v00 = base + j * row + i;
                        let (v10, v01) = (v00 + 1, v00 + row);
                        mesh.triangles.push([v00, v10, v01 + 1]);
                        mesh.triangles.push([v00, v01 + 1, v01]);
                    }
                }
            }
        }
        mesh.normals = Some(normals);
        mesh.orient_to_normals();
        mesh
    }
}
