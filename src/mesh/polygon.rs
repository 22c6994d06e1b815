//! Triangulating the polygon faces of a mesh file (OBJ faces of four or more
//! corners) with their true area: a concave face, or a face with a hole drawn as
//! one polygon with a bridge edge (as CAD exporters write rings, with corners
//! repeated), must not be covered by a fan from its first corner. Each face is
//! projected onto the plane of its Newell normal and cut into triangles by the
//! `earcutr` crate (a port of Mapbox's earcut, which handles repeated corners and
//! bridged holes); the triangles' area is then checked against the polygon's own
//! (shoelace) area, and a face that cannot be covered exactly — one that crosses
//! itself — is refused with the reason, never filled silently.
//!
//! Real exporters also write quads that are not flat (the quads of a
//! subdivision control cage, folded at a crease): projected onto one plane such
//! a quad can look like a bow tie although it is a fine surface. A quad that
//! fails the projection is therefore split along the diagonal that folds it
//! least (its two triangles' normals closest), and reported; only a quad whose
//! two triangles would lie back to back along either diagonal (folded by more
//! than [`MAX_FOLD_DEG`], as a flat bow tie is, by 180°) is refused.

use glam::{DVec2, DVec3};

/// Relative difference allowed between the triangles' area and the polygon's:
/// rounding only (a wrongly covered face differs by a whole piece of its area).
const AREA_TOLERANCE: f64 = 1e-9;

/// The most a non-flat quad may be folded along the diagonal it is split at:
/// beyond it the two triangles nearly lie on each other, which is a face that
/// crosses itself (a flat bow tie is folded by 180° along both diagonals).
pub const MAX_FOLD_DEG: f64 = 175.0;

/// A face's triangles (indices into its corners, wound like the polygon).
#[derive(Debug, PartialEq)]
pub struct Triangulation {
    pub triangles: Vec<[usize; 3]>,
    /// For a quad that is not flat and was split along its better diagonal:
    /// the angle between its two triangles' normals, degrees.
    pub folded_deg: Option<f64>,
}

/// The triangles covering face `corners` (see [`triangulate_polygon`]), or, for
/// a quad whose projection crosses itself because it is not flat, its split
/// along the diagonal that folds it least, reported in `folded_deg`.
pub fn triangulate(corners: &[DVec3]) -> Result<Triangulation, String> {
    match triangulate_polygon(corners) {
        Ok(triangles) => Ok(Triangulation {
            triangles,
            folded_deg: None,
        }),
        Err(why) if corners.len() == 4 => match split_quad(corners) {
            Some((triangles, fold)) if fold <= MAX_FOLD_DEG => Ok(Triangulation {
                triangles: triangles.to_vec(),
                folded_deg: Some(fold),
            }),
            _ => Err(why),
        },
        Err(why) => Err(why),
    }
}

/// A quad's two triangles along the diagonal that folds it least (0–2 or
/// 1–3, wound like the quad) and that fold in degrees; `None` if a triangle
/// has no area along both.
fn split_quad(c: &[DVec3]) -> Option<([[usize; 3]; 2], f64)> {
    [[[0, 1, 2], [0, 2, 3]], [[0, 1, 3], [1, 2, 3]]]
        .into_iter()
        .filter_map(|pair| {
            let normal = |[a, b, d]: [usize; 3]| (c[b] - c[a]).cross(c[d] - c[a]).try_normalize();
            let (n1, n2) = (normal(pair[0])?, normal(pair[1])?);
            Some((pair, n1.dot(n2).clamp(-1.0, 1.0).acos().to_degrees()))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

/// Triangles (indices into `corners`, wound like the polygon) covering the
/// polygon `corners` (3 or more, in order) projected onto its own plane, or
/// why it cannot be covered. A face whose corners all lie on a line has no
/// area and no triangles.
pub fn triangulate_polygon(corners: &[DVec3]) -> Result<Vec<[usize; 3]>, String> {
    let n = corners.len();
    if n < 3 {
        return Ok(Vec::new());
    }
    if n == 3 {
        return Ok(vec![[0, 1, 2]]);
    }
    let Some(normal) = newell_normal(corners).try_normalize() else {
        return if collinear(corners) {
            Ok(Vec::new())
        } else {
            Err("its corners enclose no area with one orientation: the face crosses itself (a figure eight); split it into simple polygons".into())
        };
    };
    // A right-handed (u, v, normal) frame: the polygon runs counter-clockwise in it.
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let flat: Vec<DVec2> = corners
        .iter()
        .map(|p| DVec2::new(p.dot(u), p.dot(v)))
        .collect();
    let coords: Vec<f64> = flat.iter().flat_map(|p| [p.x, p.y]).collect();
    let indices =
        earcutr::earcut(&coords, &[], 2).map_err(|e| format!("cannot be triangulated ({e:?})"))?;
    let triangles: Vec<[usize; 3]> = indices
        .chunks_exact(3)
        .map(|t| {
            // Wound counter-clockwise in the frame, like the polygon.
            let [a, b, c] = [t[0], t[1], t[2]];
            if (flat[b] - flat[a]).perp_dot(flat[c] - flat[a]) < 0.0 {
                [a, c, b]
            } else {
                [a, b, c]
            }
        })
        .collect();
    let covered: f64 = triangles
        .iter()
        .map(|&[a, b, c]| 0.5 * (flat[b] - flat[a]).perp_dot(flat[c] - flat[a]).abs())
        .sum();
    let area = 0.5 * shoelace(&flat).abs();
    let scale = flat
        .iter()
        .map(|p| (*p - flat[0]).length_squared())
        .fold(0.0, f64::max);
    if (covered - area).abs() > AREA_TOLERANCE * scale.max(area) {
        return Err(format!(
            "its triangles would cover {covered:.6e} where the face encloses {area:.6e} (in the file's units squared): the face crosses itself; split it into simple polygons"
        ));
    }
    Ok(triangles)
}

/// Newell's normal (twice the vector area): robust for any simple polygon, zero
/// for a degenerate or self-cancelling one.
fn newell_normal(corners: &[DVec3]) -> DVec3 {
    let n = corners.len();
    (0..n)
        .map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            DVec3::new(
                (a.y - b.y) * (a.z + b.z),
                (a.z - b.z) * (a.x + b.x),
                (a.x - b.x) * (a.y + b.y),
            )
        })
        .sum()
}

/// Whether all corners lie on one line (or one point).
fn collinear(corners: &[DVec3]) -> bool {
    let o = corners[0];
    let Some(far) = corners.iter().max_by(|a, b| {
        (**a - o)
            .length_squared()
            .total_cmp(&(**b - o).length_squared())
    }) else {
        return true;
    };
    let d = *far - o;
    let len2 = d.length_squared();
    len2 == 0.0
        || corners
            .iter()
            .all(|p| (*p - o).cross(d).length_squared() <= 1e-24 * len2 * len2)
}

/// Twice the signed area of a 2D polygon.
fn shoelace(p: &[DVec2]) -> f64 {
    (0..p.len())
        .map(|i| p[i].perp_dot(p[(i + 1) % p.len()]))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(corners: &[DVec3], tris: &[[usize; 3]]) -> f64 {
        tris.iter()
            .map(|&[a, b, c]| {
                0.5 * (corners[b] - corners[a])
                    .cross(corners[c] - corners[a])
                    .length()
            })
            .sum()
    }

    #[test]
    fn a_concave_face_keeps_its_area_and_winding() {
        // An L of area 3, counter-clockwise seen from +z.
        let l: Vec<DVec3> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect();
        let t = triangulate(&l).unwrap().triangles;
        assert_eq!(t.len(), 4);
        assert!((area(&l, &t) - 3.0).abs() < 1e-12);
        for &[a, b, c] in &t {
            assert!((l[b] - l[a]).cross(l[c] - l[a]).z > 0.0);
        }
    }

    #[test]
    fn a_ring_drawn_as_one_face_with_a_bridge_keeps_its_hole() {
        // Outer square 4 × 4, inner square 2 × 2 (clockwise), joined by a bridge
        // from (0, 0) to (1, 1): corners repeated, area 16 − 4 = 12.
        let ring: Vec<DVec3> = [
            (0., 0.),
            (4., 0.),
            (4., 4.),
            (0., 4.),
            (0., 0.),
            (1., 1.),
            (1., 3.),
            (3., 3.),
            (3., 1.),
            (1., 1.),
        ]
        .iter()
        .map(|&(x, y)| DVec3::new(x, y, 5.0))
        .collect();
        let t = triangulate(&ring).unwrap().triangles;
        assert!((area(&ring, &t) - 12.0).abs() < 1e-9, "{}", area(&ring, &t));
        // A fan from corner 0 would have covered the hole.
        let centre = DVec3::new(2.0, 2.0, 5.0);
        assert!(!t.iter().any(|&[a, b, c]| {
            let (p, q, r) = (ring[a], ring[b], ring[c]);
            let s = |u: DVec3, v: DVec3| (v - u).cross(centre - u).z;
            let (x, y, z) = (s(p, q), s(q, r), s(r, p));
            (x > 0.0 && y > 0.0 && z > 0.0) || (x < 0.0 && y < 0.0 && z < 0.0)
        }));
    }

    #[test]
    fn faces_that_cross_themselves_are_refused_and_lines_have_no_area() {
        let bow_tie: Vec<DVec3> = [(0., 0.), (1., 1.), (1., 0.), (0., 1.)]
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect();
        assert!(triangulate(&bow_tie)
            .unwrap_err()
            .contains("crosses itself"));
        let line: Vec<DVec3> = (0..5).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
        assert!(triangulate(&line).unwrap().triangles.is_empty());
    }

    #[test]
    fn a_quad_that_is_not_flat_is_split_along_its_better_diagonal_and_a_flat_bow_tie_is_not() {
        // A quad that is not flat (its corner 3 sits just beyond edge 0–1 when
        // seen along its mean normal): projected, it crosses itself by a sliver,
        // yet split along 1–3 it is two triangles folded by 4°.
        let folded: Vec<DVec3> = [
            (-0.8, -0.6, 0.7),
            (0.0, -0.8, -0.7),
            (0.1, 0.2, -0.8),
            (-0.4, -0.7, 0.0),
        ]
        .iter()
        .map(|&(x, y, z)| DVec3::new(x, y, z))
        .collect();
        assert!(
            triangulate_polygon(&folded).is_err(),
            "the projection crosses itself"
        );
        let t = triangulate(&folded).unwrap();
        let fold = t.folded_deg.expect("reported as folded");
        assert!((fold - 4.03).abs() < 0.01, "{fold}");
        // Two triangles sharing one diagonal, every corner used, none flat.
        assert_eq!(t.triangles.len(), 2);
        let shared: Vec<usize> = t.triangles[0]
            .iter()
            .copied()
            .filter(|i| t.triangles[1].contains(i))
            .collect();
        assert_eq!(shared.len(), 2);
        assert_eq!(shared, vec![1, 3]);
        // The other diagonal folds it more.
        let other = if shared.contains(&0) {
            [[0, 1, 3], [1, 2, 3]]
        } else {
            [[0, 1, 2], [0, 2, 3]]
        };
        let n = |[a, b, c]: [usize; 3]| {
            (folded[b] - folded[a])
                .cross(folded[c] - folded[a])
                .normalize()
        };
        let other_fold = n(other[0]).dot(n(other[1])).acos().to_degrees();
        assert!(other_fold > fold, "{other_fold} vs {fold}");
        // A flat bow tie folds by 180° either way: refused.
        let bow_tie: Vec<DVec3> = [(0., 0.), (1., 1.), (1., 0.), (0., 1.)]
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect();
        assert!(triangulate(&bow_tie).is_err());
    }
}
