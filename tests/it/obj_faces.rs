//! OBJ faces become triangles that cover exactly the polygon: concave faces keep
//! their area (ear clipping, not a fan), line elements are not faces, and a mesh
//! with nothing of area is refused.

use crate::common::{run_fails, traxer, write};
use glam::DVec3;

/// Shoelace area of a planar polygon in the x–y plane.
fn shoelace(p: &[(f64, f64)]) -> f64 {
    let n = p.len();
    0.5 * (0..n)
        .map(|i| p[i].0 * p[(i + 1) % n].1 - p[(i + 1) % n].0 * p[i].1)
        .sum::<f64>()
}

/// An OBJ with one face through `corners`, each mapped by `place`.
fn one_face(corners: &[(f64, f64)], place: impl Fn(f64, f64) -> DVec3) -> String {
    let mut s = String::from("o poly\n");
    for &(x, y) in corners {
        let p = place(x, y);
        s.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
    }
    s.push('f');
    for i in 1..=corners.len() {
        s.push_str(&format!(" {i}"));
    }
    s.push('\n');
    s
}

#[test]
fn concave_faces_keep_their_area() {
    let dir = tempfile::tempdir().unwrap();
    let shapes: [(&str, Vec<(f64, f64)>); 3] = [
        // Concave pentagon (a fan from the first corner covers 14, not 10).
        (
            "pentagon",
            vec![(0.0, 0.0), (4.0, 0.0), (4.0, 4.0), (2.0, 1.0), (0.0, 4.0)],
        ),
        // A 6 × 4 plate with a 2 × 2 notch cut into its top edge.
        (
            "notch",
            vec![
                (0.0, 0.0),
                (6.0, 0.0),
                (6.0, 4.0),
                (4.0, 4.0),
                (4.0, 2.0),
                (2.0, 2.0),
                (2.0, 4.0),
                (0.0, 4.0),
            ],
        ),
        // A comb whose first corner sees none of the others well.
        (
            "comb",
            vec![
                (0.0, 0.0),
                (5.0, 0.0),
                (5.0, 3.0),
                (4.0, 3.0),
                (4.0, 1.0),
                (3.0, 1.0),
                (3.0, 3.0),
                (2.0, 3.0),
                (2.0, 1.0),
                (1.0, 1.0),
                (1.0, 3.0),
                (0.0, 3.0),
            ],
        ),
    ];
    // In the x–y plane and tilted in space (the face's own plane is used).
    let tilt = glam::DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
    for (name, corners) in &shapes {
        let exact = shoelace(corners);
        for (frame, place) in [
            (
                "flat",
                Box::new(|x, y| DVec3::new(x, y, 0.0)) as Box<dyn Fn(f64, f64) -> DVec3>,
            ),
            (
                "tilted",
                Box::new(move |x, y| tilt * DVec3::new(x, y, 0.0) + DVec3::splat(3.0)),
            ),
        ] {
            let normal = if frame == "flat" {
                DVec3::Z
            } else {
                tilt * DVec3::Z
            };
            let p = write(
                dir.path(),
                &format!("{name}_{frame}.obj"),
                &one_face(corners, place),
            );
            let (m, _) = traxer::mesh::load(&p).unwrap();
            assert_eq!(m.triangles.len(), corners.len() - 2, "{name} {frame}");
            assert!(
                (m.area() - exact).abs() < 1e-9 * exact,
                "{name} {frame}: area {} vs {exact}",
                m.area()
            );
            // Every triangle keeps the face's winding (its front side).
            for i in 0..m.triangles.len() {
                assert!(
                    m.face_normal(i).dot(normal) > 0.0,
                    "{name} {frame}: triangle {i}"
                );
            }
        }
    }
}

#[test]
fn line_elements_are_not_faces() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "l.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nl 1 2 3 4\nl 4 1\n",
    );
    let (m, report) = traxer::mesh::load(&p).unwrap();
    assert_eq!(m.triangles.len(), 1, "the `l` elements became triangles");
    assert!((m.area() - 0.5).abs() < 1e-12);
    assert!(
        report
            .skipped
            .iter()
            .any(|s| s.what.contains("2 line element")),
        "{:?}",
        report.skipped
    );
}

#[test]
fn a_mesh_with_no_area_at_all_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // Two triangles, both collinear: lines exported as triangles.
    let p = write(
        dir.path(),
        "flat.obj",
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n",
    );
    let err = run_fails(traxer().arg("inspect").arg(&p), 2);
    assert!(err.contains("zero area"), "{err}");
}

#[test]
fn a_ring_drawn_as_one_face_keeps_its_hole_and_a_crossing_face_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // A CAD exporter's ring: the outer square (10 × 10) and the hole (4 × 4,
    // the other way round) joined by a bridge edge, its ends repeated.
    let ring = [
        (0.0, 0.0),
        (10.0, 0.0),
        (10.0, 10.0),
        (0.0, 10.0),
        (0.0, 0.0),
        (3.0, 3.0),
        (3.0, 7.0),
        (7.0, 7.0),
        (7.0, 3.0),
        (3.0, 3.0),
    ];
    let p = write(
        dir.path(),
        "ring.obj",
        &one_face(&ring, |x, y| DVec3::new(x, y, 0.0)),
    );
    let (m, _) = traxer::mesh::load(&p).unwrap();
    assert!((m.area() - 84.0).abs() < 1e-9, "area {}", m.area());
    // A face that crosses itself (a bow tie with unequal lobes): refused, named.
    let bow = [(0.0, 0.0), (4.0, 4.0), (4.0, 0.0), (0.0, 2.0)];
    let p = write(
        dir.path(),
        "bow.obj",
        &one_face(&bow, |x, y| DVec3::new(x, y, 0.0)),
    );
    let err = traxer::mesh::load(&p).unwrap_err().to_string();
    assert!(
        err.contains("bow.obj")
            && err.contains("object 'poly': face 1 (4 corners")
            && err.contains("crosses itself"),
        "{err}"
    );
    let err = run_fails(traxer().arg("inspect").arg(&p), 2);
    assert!(err.contains("crosses itself"), "{err}");
}

#[test]
fn a_quad_that_is_not_flat_loads_split_along_its_better_diagonal_with_a_note() {
    // Issue 39: a quad of a control cage that is not flat, whose projection on
    // its mean plane crosses itself by a sliver, was refused as self-crossing.
    // It is two triangles folded by 4° along its diagonal 1–3.
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "cage.obj",
        "o cage\nv -0.8 -0.6 0.7\nv 0.0 -0.8 -0.7\nv 0.1 0.2 -0.8\nv -0.4 -0.7 0.0\nf 1 2 3 4\n",
    );
    let (m, report) = traxer::mesh::load(&p).unwrap();
    assert_eq!(m.triangles.len(), 2);
    let corners = |t: [u32; 3]| t.map(|k| m.positions[k as usize]);
    let areas: f64 = m
        .triangles
        .iter()
        .map(|&t| {
            let [a, b, c] = corners(t);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum();
    // Split along the diagonal from the file's corner 2 to its corner 4: the
    // triangles (1, 2, 4) and (2, 3, 4) of the file's numbering.
    let expected = {
        let v = [
            DVec3::new(-0.8, -0.6, 0.7),
            DVec3::new(0.0, -0.8, -0.7),
            DVec3::new(0.1, 0.2, -0.8),
            DVec3::new(-0.4, -0.7, 0.0),
        ];
        let tri = |a: usize, b: usize, c: usize| 0.5 * (v[b] - v[a]).cross(v[c] - v[a]).length();
        tri(0, 1, 3) + tri(1, 2, 3)
    };
    assert!((areas - expected).abs() < 1e-12, "{areas} vs {expected}");
    let notes = report.warnings().join("\n");
    assert!(
        notes.contains("not flat") && notes.contains("faces 1 (4.0°)"),
        "{notes}"
    );
    // `traxer inspect` loads it and says so.
    let out = crate::common::run_ok(traxer().arg("inspect").arg(&p));
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(all.contains("not flat"), "{all}");
}
