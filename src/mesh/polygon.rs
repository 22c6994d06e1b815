//! Triangulating the polygon faces of a mesh file by ear clipping, so that a
//! concave face keeps exactly its area (a fan from the first corner would cover
//! area outside a concave polygon). Faces are planar in practice; each is
//! projected onto the plane of its Newell normal.

use glam::{DVec2, DVec3};

/// Triangles (indices into `corners`, wound like the polygon) covering the
/// polygon `corners` (3 or more, in order).
pub fn triangulate(corners: &[DVec3]) -> Vec<[usize; 3]> {
    let n = corners.len();
    if n < 3 {
        return Vec::new();
    }
    if n == 3 {
        return vec![[0, 1, 2]];
    }
    // Newell's normal: robust for any simple polygon, zero for a degenerate one.
    let mut normal = DVec3::ZERO;
    for i in 0..n {
        let (a, b) = (corners[i], corners[(i + 1) % n]);
        normal += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let Some(normal) = normal.try_normalize() else {
        return fan(n);
    };
    // A right-handed (u, v, normal) frame: the polygon runs counter-clockwise in it.
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let flat: Vec<DVec2> = corners
        .iter()
        .map(|p| DVec2::new(p.dot(u), p.dot(v)))
        .collect();
    let mut left: Vec<usize> = (0..n).collect();
    let mut out = Vec::with_capacity(n - 2);
    while left.len() > 3 {
        let m = left.len();
        let ear = (0..m).find(|&k| {
            let (p, i, q) = (left[(k + m - 1) % m], left[k], left[(k + 1) % m]);
            let (a, b, c) = (flat[p], flat[i], flat[q]);
            // Convex corner, and no other corner inside (or on) the triangle.
            (b - a).perp_dot(c - b) > 0.0
                && left
                    .iter()
                    .filter(|&&j| j != p && j != i && j != q)
                    .all(|&j| !inside(flat[j], a, b, c))
        });
        let Some(k) = ear else {
            // Self-intersecting or numerically flat: what is left becomes a fan.
            out.extend(fan(left.len()).into_iter().map(|t| t.map(|x| left[x])));
            return out;
        };
        out.push([left[(k + m - 1) % m], left[k], left[(k + 1) % m]]);
        left.remove(k);
    }
    out.push([left[0], left[1], left[2]]);
    out
}

/// The fan from corner 0.
fn fan(n: usize) -> Vec<[usize; 3]> {
    (1..n - 1).map(|i| [0, i, i + 1]).collect()
}

/// Whether `p` lies inside or on the counter-clockwise triangle (a, b, c).
fn inside(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    (b - a).perp_dot(p - a) >= 0.0
        && (c - b).perp_dot(p - b) >= 0.0
        && (a - c).perp_dot(p - c) >= 0.0
}
