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
mod nested_shells;
mod quadric;
mod rectangle;
mod shape;
mod sphere;
mod transform;
mod triangle_mesh;
pub mod wolter;

pub use azimuth::AzimuthRange;
pub use cuboid::Cuboid;
pub use disk::Disk;
pub use nested_shells::NestedShells;
pub use quadric::RevolutionQuadric;
pub use rectangle::Rectangle;
pub use shape::{AnalyticObject, Piece, Resolution, Shape, Surface};
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

/// [`nearest_root`] for the two roots of a quadratic in ascending order (as
/// [`solve_quadratic`] returns them), without the general search: the same
/// choice, for the shapes whose intersection the photon loop calls most.
#[inline(always)]
pub(crate) fn nearest_of_two(
    (t1, t2): (f64, f64),
    starts_on_surface: bool,
    t_max: f64,
    admissible: impl Fn(f64) -> bool,
) -> Option<f64> {
    // The root nearest t = 0 is the start point (the first one on a tie).
    let skip_first = starts_on_surface && t1.abs() <= t2.abs();
    let skip_second = starts_on_surface && !skip_first;
    let usable = |t: f64| t > 0.0 && t < t_max && admissible(t);
    if !skip_first && usable(t1) {
        Some(t1)
    } else if !skip_second && usable(t2) {
        Some(t2)
    } else {
        None
    }
}

/// A point of a local-frame ray.
#[inline]
pub(crate) fn at(o: DVec3, d: DVec3, t: f64) -> DVec3 {
    o + d * t
}

#[cfg(test)]
mod tests {
    use super::{nearest_of_two, nearest_root};

    /// The two-root shortcut picks what the general search picks: ascending root
    /// pairs of every sign pattern, ties, zeros, rays starting on the surface or
    /// not, t_max cutting between them, and a predicate that refuses some roots.
    #[test]
    fn nearest_of_two_agrees_with_nearest_root() {
        let values = [-3.0, -1e-12, -0.0, 0.0, 1e-12, 0.5, 2.0, 2.0, 7.0];
        for (i, &a) in values.iter().enumerate() {
            for &b in &values[i..] {
                for starts in [false, true] {
                    for t_max in [1.0, 5.0, f64::INFINITY] {
                        let refuse = |t: f64| t != 2.0;
                        let general = nearest_root(&[a, b], starts, t_max, refuse);
                        let two = nearest_of_two((a, b), starts, t_max, refuse);
                        assert_eq!(
                            general, two,
                            "roots {a}, {b}, starts {starts}, t_max {t_max}"
                        );
                        let general = nearest_root(&[a, b], starts, t_max, |_| true);
                        let two = nearest_of_two((a, b), starts, t_max, |_| true);
                        assert_eq!(
                            general, two,
                            "roots {a}, {b}, starts {starts}, t_max {t_max}"
                        );
                    }
                }
            }
        }
    }
}
