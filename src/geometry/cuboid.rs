//! Axis-aligned box in the local frame, centred on the origin, facing outwards.

use super::nearest_root;
use crate::mesh::TriangleMesh;
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cuboid {
    /// Full edge lengths along local x, y, z.
    pub size: DVec3,
}

impl Cuboid {
    #[inline]
    pub fn intersect(
        &self,
        o: DVec3,
        d: DVec3,
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64> {
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
    pub fn normal(&self, p: DVec3) -> DVec3 {
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

    pub fn bounds(&self) -> (DVec3, DVec3) {
        (-0.5 * self.size, 0.5 * self.size)
    }

    /// 12 triangles, 4 vertices per face (flat normals).
    pub fn tessellate(&self) -> TriangleMesh {
        let h = 0.5 * self.size;
        let mut mesh = TriangleMesh::default();
        let mut normals = Vec::new();
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut n = DVec3::ZERO;
                n[axis] = sign;
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let base = mesh.positions.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    let mut p = DVec3::ZERO;
                    p[axis] = sign * h[axis];
                    p[u] = a * h[u];
                    p[v] = b * h[v];
                    mesh.positions.push(p);
                    normals.push(n);
                }
                mesh.triangles.push([base, base + 1, base + 2]);
                mesh.triangles.push([base, base + 2, base + 3]);
            }
        }
        mesh.normals = Some(normals);
        mesh.orient_to_normals();
        mesh
    }
}
