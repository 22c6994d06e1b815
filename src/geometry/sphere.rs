//! Sphere centred on the local origin, facing outwards.

use super::{nearest_of_two, solve_quadratic, Resolution};
use super::{Surface, TriangleMesh};
use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub radius: f64,
}

impl Surface for Sphere {
    #[inline]
    fn intersect(&self, o: DVec3, d: DVec3, t_max: f64, starts_on_surface: bool) -> Option<f64> {
        let roots = solve_quadratic(
            d.length_squared(),
            2.0 * o.dot(d),
            o.length_squared() - self.radius * self.radius,
        )?;
        nearest_of_two(roots, starts_on_surface, t_max, |_| true)
    }

    #[inline]
    fn normal(&self, p: DVec3) -> DVec3 {
        p.normalize()
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        (DVec3::splat(-self.radius), DVec3::splat(self.radius))
    }

    /// Latitude–longitude grid: `segments` around, `rings` from pole to pole.
    fn tessellate(&self, res: Resolution) -> TriangleMesh {
        let n_phi = res.segments.max(3);
        let n_theta = res.rings.max(2);
        let mut mesh = TriangleMesh::default();
        for j in 0..=n_theta {
            let theta = std::f64::consts::PI * j as f64 / n_theta as f64;
            for i in 0..n_phi {
                let phi = 2.0 * std::f64::consts::PI * i as f64 / n_phi as f64;
                mesh.positions.push(
                    self.radius
                        * DVec3::new(
                            theta.sin() * phi.cos(),
                            theta.sin() * phi.sin(),
                            theta.cos(),
                        ),
                );
            }
        }
        let cols = n_phi as u32;
        for j in 0..n_theta as u32 {
            for i in 0..cols {
                let i1 = (i + 1) % cols;
                let (v00, v01) = (j * cols + i, j * cols + i1);
                let (v10, v11) = ((j + 1) * cols + i, (j + 1) * cols + i1);
                if j != 0 {
                    mesh.triangles.push([v00, v10, v01]);
                }
                if j + 1 != n_theta as u32 {
                    mesh.triangles.push([v01, v10, v11]);
                }
            }
        }
        mesh.normals = Some(mesh.positions.iter().map(|p| p.normalize()).collect());
        mesh.orient_to_normals();
        mesh
    }
}
