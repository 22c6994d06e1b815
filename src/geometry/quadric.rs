//! Sections of surfaces of revolution about the local z axis:
//! x² + y² = a + b·z + c·z², cut to z_min ≤ z ≤ z_max and to an azimuth range.
//! One quadratic covers the cone and cylinder (the LLNL telescope's shells), and the
//! paraboloid and hyperboloid of a true Wolter-I optic.

use super::grid::polar_grid;
use super::{at, nearest_of_two, solve_quadratic, AzimuthRange, Resolution};
use super::{Surface, TriangleMesh};
use glam::DVec3;

/// x² + y² = a + b·z + c·z² for z in [z_min, z_max] and azimuth in `azimuth`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RevolutionQuadric {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub z_min: f64,
    pub z_max: f64,
    pub azimuth: AzimuthRange,
}

impl RevolutionQuadric {
    /// Truncated cone with radius `r0` at height `z0` and `r1` at `z1`.
    pub fn cone(r0: f64, z0: f64, r1: f64, z1: f64, azimuth: AzimuthRange) -> Self {
        // r(z) = r0 + s (z − z0) = k + s z;  r² = k² + 2ks z + s² z².
        let s = (r1 - r0) / (z1 - z0);
        let k = r0 - s * z0;
        RevolutionQuadric {
            a: k * k,
            b: 2.0 * k * s,
            c: s * s,
            z_min: z0.min(z1),
            z_max: z0.max(z1),
            azimuth,
        }
    }

    /// Cylinder (tube) of radius `r`.
    pub fn cylinder(r: f64, z0: f64, z1: f64, azimuth: AzimuthRange) -> Self {
        Self::cone(r, z0, r, z1, azimuth)
    }

    /// Paraboloid with its focus on the axis at z = `focus_z`, opening towards
    /// +z: r² = 4q (z − focus_z + q), q = the vertex-to-focus distance.
    pub fn paraboloid(q: f64, focus_z: f64, z0: f64, z1: f64, azimuth: AzimuthRange) -> Self {
        RevolutionQuadric {
            // As written before the focus could move, for focus_z = 0.
            a: if focus_z == 0.0 {
                4.0 * q * q
            } else {
                4.0 * q * (q - focus_z)
            },
            b: 4.0 * q,
            c: 0.0,
            z_min: z0.min(z1),
            z_max: z0.max(z1),
            azimuth,
        }
    }

    /// Hyperboloid of two sheets centred on the axis at z = `center_z` = z_c:
    /// (z − z_c)²/a² − r²/b² = 1, i.e. r² = b² ((z − z_c)²/a² − 1); foci at
    /// z_c ± √(a² + b²). The z range selects the sheet.
    pub fn hyperboloid(
        semi_a: f64,
        semi_b: f64,
        center_z: f64,
        z0: f64,
        z1: f64,
        azimuth: AzimuthRange,
    ) -> Self {
        let bb = semi_b * semi_b;
        let k = bb / (semi_a * semi_a);
        // r² = (k z_c² − b²) − 2k z_c z + k z²; as written before the centre
        // could move, for z_c = 0.
        let (a, b) = if center_z == 0.0 {
            (-bb, 0.0)
        } else {
            (k * center_z * center_z - bb, -2.0 * k * center_z)
        };
        RevolutionQuadric {
            a,
            b,
            c: k,
            z_min: z0.min(z1),
            z_max: z0.max(z1),
            azimuth,
        }
    }

    /// r² at height z (negative outside the surface's real part).
    #[inline]
    pub fn radius_squared(&self, z: f64) -> f64 {
        self.a + self.b * z + self.c * z * z
    }

    pub fn radius(&self, z: f64) -> f64 {
        self.radius_squared(z).max(0.0).sqrt()
    }

    /// The smallest and largest radius over z_min … z_max.
    pub fn radius_range(&self) -> (f64, f64) {
        // r(z) is monotonic on each side of its single extremum z* = −b/2c; sample
        // the ends and z* when it lies inside.
        let mut zs = vec![self.z_min, self.z_max];
        if self.c != 0.0 {
            let zs_ext = -self.b / (2.0 * self.c);
            if zs_ext > self.z_min && zs_ext < self.z_max {
                zs.push(zs_ext);
            }
        }
        let radii = zs.iter().map(|&z| self.radius(z));
        let r_max = radii.clone().fold(0.0, f64::max);
        let r_min = radii.fold(f64::INFINITY, f64::min);
        (r_min, r_max)
    }
}

impl Surface for RevolutionQuadric {
    #[inline]
    fn intersect(&self, o: DVec3, d: DVec3, t_max: f64, starts_on_surface: bool) -> Option<f64> {
        let qa = d.x * d.x + d.y * d.y - self.c * d.z * d.z;
        let qb = 2.0 * (o.x * d.x + o.y * d.y) - self.b * d.z - 2.0 * self.c * o.z * d.z;
        let qc = o.x * o.x + o.y * o.y - self.radius_squared(o.z);
        let roots = solve_quadratic(qa, qb, qc)?;
        nearest_of_two(roots, starts_on_surface, t_max, |t| {
            let p = at(o, d, t);
            p.z >= self.z_min && p.z <= self.z_max && self.azimuth.contains(p.x, p.y)
        })
    }

    /// Unit normal at a surface point, pointing towards the axis (the front side).
    #[inline]
    fn normal(&self, p: DVec3) -> DVec3 {
        // −∇(x² + y² − a − b z − c z²) / 2
        DVec3::new(-p.x, -p.y, 0.5 * self.b + self.c * p.z).normalize()
    }

    /// Local bounding box.
    fn bounds(&self) -> (DVec3, DVec3) {
        let (r_min, r_max) = self.radius_range();
        let mut lo = DVec3::new(f64::INFINITY, f64::INFINITY, self.z_min);
        let mut hi = DVec3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, self.z_max);
        for (x, y) in self.azimuth.extreme_directions() {
            for r in [r_min, r_max] {
                lo.x = lo.x.min(r * x);
                lo.y = lo.y.min(r * y);
                hi.x = hi.x.max(r * x);
                hi.y = hi.y.max(r * y);
            }
        }
        (lo, hi)
    }

    /// Grid of `res.segments` azimuthal × `res.rings` axial quads, vertices on the
    /// exact surface with exact normals.
    fn tessellate(&self, res: Resolution) -> TriangleMesh {
        let n_z = res.rings.max(1);
        let (positions, triangles) =
            polar_grid(&self.azimuth, res.segments.max(1), n_z, false, |j, phi| {
                let z = self.z_min + (self.z_max - self.z_min) * j as f64 / n_z as f64;
                let r = self.radius(z);
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
            });
        let normals = positions.iter().map(|&p| self.normal(p)).collect();
        let mut mesh = TriangleMesh {
            positions,
            normals: Some(normals),
            triangles,
        };
        mesh.orient_to_normals();
        mesh
    }
}
