//! Analytic shapes in f64, their transforms, triangle meshes and tessellation.
//! Knows nothing of Embree, files or the scene format.
//!
//! Data flow: `scene` turns each shape entry of a scene file into a [`Shape`] plus a
//! [`Transform`]; the scene build either hands the pair to Embree as user geometry
//! ([`AnalyticObject`], intersected here in f64) or tessellates it
//! ([`Surface::tessellate`]) into a [`TriangleMesh`], the same form mesh files
//! import to.
//!
//! Every shape implements [`Surface`] in its own file and lives in its own local
//! frame (documented per shape, mostly with the z axis as symmetry axis); its
//! *front* side is the side its [`Surface::normal`] points to. Surfaces of revolution (cone, cylinder, paraboloid, hyperboloid) face
//! the axis, because X-ray telescopes reflect on the inside; disks and rectangles
//! face local +z; boxes and spheres face outwards.

mod azimuth;
mod cuboid;
mod disk;
mod grid;
mod quadric;
mod rectangle;
mod shape;
mod sphere;
mod transform;
mod triangle_mesh;

pub use azimuth::AzimuthRange;
pub use cuboid::Cuboid;
pub use disk::Disk;
pub use quadric::RevolutionQuadric;
pub use rectangle::Rectangle;
pub use shape::{AnalyticObject, Resolution, Shape, Surface};
pub use sphere::Sphere;
pub use transform::Transform;
pub use triangle_mesh::TriangleMesh;

use glam::DVec3;

/// Every position a scene uses (object bounds, sources, targets, cameras) must lie
/// within ±this many millimetres (1000 km) of the origin. Embree works in float32:
/// at 1e9 mm neighbouring floats are 64 mm apart, and beyond ~1.8e18 Embree rejects
/// a ray outright (an assertion that aborts the process). A source as far away as
/// the Sun must start its photons near the target instead.
pub const WORLD_LIMIT_MM: f64 = 1e9;

/// The most quads (segments × rings) a tessellation may have: 1e8 triangles, several
/// GB of mesh, far beyond any useful resolution.
pub const MAX_TESSELLATION_QUADS: usize = 50_000_000;

/// Whether every coordinate lies within ±[`WORLD_LIMIT_MM`].
pub fn within_world(points: &[DVec3]) -> bool {
    points
        .iter()
        .all(|p| p.is_finite() && p.abs().max_element() <= WORLD_LIMIT_MM)
}

/// Roots of a·t² + b·t + c = 0 in ascending order, computed without cancellation
/// (the grazing rays of X-ray optics make a or b tiny). `None` if there is no real
/// root; a linear equation (a = 0) gives one root twice.
pub(crate) fn solve_quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        let t = -c / b;
        return Some((t, t));
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    if q == 0.0 {
        // b = 0 and c = 0: double root at 0.
        return Some((0.0, 0.0));
    }
    let (t1, t2) = (q / a, c / q);
    Some(if t1 <= t2 { (t1, t2) } else { (t2, t1) })
}

/// Picks the nearest admissible root among `roots` (candidates of one surface).
/// When the ray starts on this very surface, the root closest to t = 0 is the
/// point it starts from and is dropped first; a second, genuine hit on the same
/// surface (a concave mirror) survives.
pub(crate) fn nearest_root(
    roots: &[f64],
    starts_on_surface: bool,
    t_max: f64,
    admissible: impl Fn(f64) -> bool,
) -> Option<f64> {
    let mut skip = usize::MAX;
    if starts_on_surface {
        skip = (0..roots.len())
            .min_by(|&i, &j| roots[i].abs().total_cmp(&roots[j].abs()))
            .unwrap_or(usize::MAX);
    }
    let mut best: Option<f64> = None;
    for (i, &t) in roots.iter().enumerate() {
        if i == skip || !(t > 0.0 && t < t_max) {
            continue;
        }
        if best.is_some_and(|b| b <= t) {
            continue;
        }
        if admissible(t) {
            best = Some(t);
        }
    }
    best
}

/// A point of a local-frame ray.
#[inline]
pub(crate) fn at(o: DVec3, d: DVec3, t: f64) -> DVec3 {
    o + d * t
}
