//! Analytic shapes: intersections against independent closed forms, normals,
//! bounds and tessellation.

use glam::DVec3;
use traxer::geometry::{
    AzimuthRange, Cuboid, Disk, Rectangle, Resolution, RevolutionQuadric, Shape, Sphere, Surface,
};

/// Deterministic pseudo-random numbers for test inputs.
pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1., 1.),
                self.range(-1., 1.),
                self.range(-1., 1.),
            );
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

fn shapes() -> Vec<Shape> {
    let seg = AzimuthRange::new(-15.0, 30.0);
    vec![
        Shape::Revolution(RevolutionQuadric::cone(63.2384, 229.0, 60.9121, 4.0, seg)),
        Shape::Revolution(RevolutionQuadric::cylinder(
            21.5,
            -50.0,
            50.0,
            AzimuthRange::FULL,
        )),
        Shape::Revolution(RevolutionQuadric::paraboloid(
            0.5,
            0.0,
            800.0,
            1000.0,
            AzimuthRange::FULL,
        )),
        Shape::Revolution(RevolutionQuadric::hyperboloid(
            700.0, 30.0, 0.0, 760.0, 850.0, seg,
        )),
        Shape::Disk(Disk {
            inner_radius: 2.0,
            outer_radius: 10.0,
            azimuth: AzimuthRange::FULL,
        }),
        Shape::Rectangle(Rectangle {
            width: 14.0,
            height: 7.0,
        }),
        Shape::Cuboid(Cuboid {
            size: DVec3::new(1.0, 2.0, 3.0),
        }),
        Shape::Sphere(Sphere { radius: 5.0 }),
    ]
}

/// Random points strictly inside each surface (away from clipping edges),
/// generated from the shapes' defining parameters.
fn surface_points(s: &Shape) -> Vec<DVec3> {
    let mut rng = Lcg(77);
    let mut out = Vec::new();
    for _ in 0..400 {
        let p = match s {
            Shape::Revolution(q) => {
                let z = rng.range(q.z_min, q.z_max);
                let z = q.z_min + (z - q.z_min) * 0.998 + 0.001 * (q.z_max - q.z_min);
                let a = &q.azimuth;
                let span = a.span_deg().min(360.0);
                let phi = (a.start_deg() + span * rng.range(0.001, 0.999)).to_radians();
                DVec3::new(q.radius(z) * phi.cos(), q.radius(z) * phi.sin(), z)
            }
            Shape::Disk(d) => {
                let r = rng.range(d.inner_radius, d.outer_radius) * 0.999 + 0.0005 * d.outer_radius;
                let phi = rng.range(0.0, std::f64::consts::TAU);
                DVec3::new(r * phi.cos(), r * phi.sin(), 0.0)
            }
            Shape::Rectangle(r) => DVec3::new(
                r.width * rng.range(-0.499, 0.499),
                r.height * rng.range(-0.499, 0.499),
                0.0,
            ),
            Shape::Cuboid(c) => {
                let h = 0.5 * c.size;
                let axis = (rng.next() * 3.0) as usize % 3;
                let mut p = DVec3::new(
                    h.x * rng.range(-0.99, 0.99),
                    h.y * rng.range(-0.99, 0.99),
                    h.z * rng.range(-0.99, 0.99),
                );
                p[axis] = if rng.next() < 0.5 { -h[axis] } else { h[axis] };
                p
            }
            Shape::Sphere(sp) => rng.unit() * sp.radius,
        };
        out.push(p);
    }
    out
}

/// Implicit surface equations, written independently of the library.
fn residual(s: &Shape, p: DVec3) -> f64 {
    match s {
        Shape::Revolution(q) => p.x * p.x + p.y * p.y - (q.a + q.b * p.z + q.c * p.z * p.z),
        Shape::Disk(_) | Shape::Rectangle(_) => p.z,
        Shape::Cuboid(c) => {
            let h = 0.5 * c.size;
            (p.abs() - h).max_element()
        }
        Shape::Sphere(sp) => p.length() - sp.radius,
    }
}

#[test]
fn quadric_coefficients_match_the_defining_formulas() {
    let c = RevolutionQuadric::cone(63.2384, 229.0, 60.9121, 4.0, AzimuthRange::FULL);
    assert!((c.radius(229.0) - 63.2384).abs() < 1e-12);
    assert!((c.radius(4.0) - 60.9121).abs() < 1e-12);
    let p = RevolutionQuadric::paraboloid(0.5, 0.0, 0.0, 10.0, AzimuthRange::FULL);
    // r² = 4q(z + q): vertex at z = −q, focus at 0, latus rectum 4q at z = 0.
    assert!((p.radius(-0.5)).abs() < 1e-12);
    assert!((p.radius(0.0) - 1.0).abs() < 1e-12);
    let h = RevolutionQuadric::hyperboloid(3.0, 4.0, 0.0, 3.0, 10.0, AzimuthRange::FULL);
    // z²/9 − r²/16 = 1 at z = 6: r² = 16·3 = 48.
    assert!((h.radius(6.0) - 48f64.sqrt()).abs() < 1e-12);
}

#[test]
fn rays_aimed_at_surface_points_hit_them() {
    let mut rng = Lcg(1);
    for s in shapes() {
        let pts = surface_points(&s);
        for (k, &p) in pts.iter().enumerate() {
            // Start 50 mm away in a random direction, aim at p; the first hit must
            // be on the surface (residual ~ 0) at or before p.
            let d = rng.unit();
            let o = p - d * 50.0;
            let t = s.intersect(o, d, f64::INFINITY, false);
            let Some(t) = t else {
                panic!("{s:?}: ray aimed at interior point {p} missed")
            };
            assert!(
                t <= 50.0 + 1e-7,
                "{s:?} point {k}: hit at {t} beyond the target 50"
            );
            let h = o + d * t;
            let tol = 1e-9 * (1.0 + p.length_squared());
            assert!(
                residual(&s, h).abs() < tol,
                "{s:?}: residual {} at {h}",
                residual(&s, h)
            );
        }
    }
}

#[test]
fn most_rays_aimed_at_interior_points_hit_exactly_there() {
    // Aiming from the front side at points strictly inside a section must return
    // that very point (nothing else is in the way for these convex/concave pieces).
    let mut rng = Lcg(2);
    let cone = RevolutionQuadric::cone(63.0, 200.0, 61.0, 0.0, AzimuthRange::new(-15.0, 30.0));
    for _ in 0..2000 {
        let z = rng.range(10.0, 190.0);
        let phi = rng.range(-14.0, 14.0).to_radians();
        let p = DVec3::new(cone.radius(z) * phi.cos(), cone.radius(z) * phi.sin(), z);
        // Grazing X-ray-like direction: mostly −z, slightly outwards.
        let d = DVec3::new(phi.cos() * 0.02, phi.sin() * 0.02, -1.0).normalize();
        let o = p - d * 30.0;
        let t = cone
            .intersect(o, d, f64::INFINITY, false)
            .expect("must hit");
        assert!(
            (o + d * t - p).length() < 1e-9,
            "hit {} vs {}",
            o + d * t,
            p
        );
    }
}

#[test]
fn normals_are_unit_perpendicular_and_face_the_documented_side() {
    for s in shapes() {
        for p in s
            .tessellate(Resolution {
                segments: 24,
                rings: 6,
            })
            .positions
        {
            let n = s.normal(p);
            assert!((n.length() - 1.0).abs() < 1e-12);
            // Perpendicular: moving along the surface keeps the residual ~0, so the
            // numerical gradient of the residual is parallel to n.
            let e = 1e-6;
            let g = DVec3::new(
                residual(&s, p + DVec3::X * e) - residual(&s, p - DVec3::X * e),
                residual(&s, p + DVec3::Y * e) - residual(&s, p - DVec3::Y * e),
                residual(&s, p + DVec3::Z * e) - residual(&s, p - DVec3::Z * e),
            );
            if let Shape::Cuboid(_) = s {
                continue; // residual is not smooth at edges
            }
            let g = g.normalize();
            assert!(
                g.cross(n).length() < 1e-5,
                "{s:?}: normal {n} vs gradient {g} at {p}"
            );
            // Documented side: surfaces of revolution face the axis.
            if let Shape::Revolution(_) = s {
                assert!(n.x * p.x + n.y * p.y < 0.0);
            }
        }
    }
}

#[test]
fn concave_surface_can_be_hit_again_but_not_at_the_start_point() {
    // Inside a cylinder a ray bounces from wall to wall: leaving the wall, the next
    // hit is the opposite wall (a second root), never the start point.
    let cyl = RevolutionQuadric::cylinder(10.0, -100.0, 100.0, AzimuthRange::FULL);
    let p = DVec3::new(10.0, 0.0, 0.0);
    let d = DVec3::new(-1.0, 0.2, -0.05).normalize();
    let t = cyl
        .intersect(p, d, f64::INFINITY, true)
        .expect("opposite wall");
    let h = p + d * t;
    assert!(t > 5.0 && (h.x * h.x + h.y * h.y - 100.0).abs() < 1e-9);
    // A ray leaving the wall outwards has nothing left to hit.
    assert!(cyl
        .intersect(p, DVec3::new(1.0, 0.0, 0.0), f64::INFINITY, true)
        .is_none());
}

#[test]
fn azimuth_range_and_z_range_clip_sections() {
    let seg = RevolutionQuadric::cone(60.0, 100.0, 60.0, 0.0, AzimuthRange::new(-15.0, 30.0));
    // Aimed at azimuth 0 → hit; azimuth 90 → miss (outside the segment).
    let hit = seg.intersect(DVec3::new(0.0, 0.0, 50.0), DVec3::X, f64::INFINITY, false);
    assert!((hit.unwrap() - 60.0).abs() < 1e-12);
    assert!(seg
        .intersect(DVec3::new(0.0, 0.0, 50.0), DVec3::Y, f64::INFINITY, false)
        .is_none());
    assert!(seg
        .intersect(DVec3::new(0.0, 0.0, 150.0), DVec3::X, f64::INFINITY, false)
        .is_none());
    // Ranges wrapping through ±180°.
    let back = AzimuthRange::new(170.0, 20.0);
    assert!(back.contains(-1.0, 0.0) && back.contains(-1.0, -0.1) && !back.contains(1.0, 0.0));
}

/// The azimuth test (two cross products against precomputed edge vectors) agrees
/// with the angle itself, measured with atan2, for ranges narrower and wider than
/// half a turn and ranges wrapping through ±180°, on directions at least 1e-6°
/// from an edge (closer, rounding may decide either way).
#[test]
fn azimuth_ranges_agree_with_the_angle() {
    let mut rng = traxer::random::PhotonRng::new(3, 0);
    for (start, span) in [
        (-15.0, 30.0),
        (170.0, 20.0),
        (0.0, 180.0),
        (-90.0, 180.0),
        (30.0, 200.0),
        (100.0, 350.0),
        (-400.0, 90.0),
        (0.0, 360.0),
    ] {
        let range = AzimuthRange::new(start, span);
        for _ in 0..20_000 {
            let phi: f64 = 360.0 * rng.uniform() - 180.0;
            let r = 0.01 + 1000.0 * rng.uniform();
            let (x, y) = (r * phi.to_radians().cos(), r * phi.to_radians().sin());
            let measured = y.atan2(x).to_degrees();
            let offset = (measured - start).rem_euclid(360.0);
            let to_edge = offset.min(360.0 - offset).min((offset - span).abs());
            if span < 360.0 && to_edge < 1e-6 {
                continue;
            }
            let inside = span >= 360.0 || offset <= span;
            assert_eq!(
                range.contains(x, y),
                inside,
                "range {start}+{span}°, direction {measured}°"
            );
        }
    }
}

#[test]
fn bounds_contain_every_tessellation_vertex() {
    for s in shapes() {
        let (lo, hi) = s.bounds();
        for p in s
            .tessellate(Resolution {
                segments: 97,
                rings: 13,
            })
            .positions
        {
            assert!(
                p.cmpge(lo - 1e-9).all() && p.cmple(hi + 1e-9).all(),
                "{s:?}: {p} outside {lo}..{hi}"
            );
        }
    }
}

#[test]
fn tessellation_is_wound_towards_the_front_and_converges_in_area() {
    use std::f64::consts::PI;
    for s in shapes() {
        let m = s.tessellate(Resolution {
            segments: 64,
            rings: 8,
        });
        m.validate().unwrap();
        let ns = m.normals.as_ref().unwrap();
        for (i, t) in m.triangles.iter().enumerate() {
            let f = m.face_normal(i);
            if f.length() == 0.0 {
                continue;
            }
            assert!(
                f.dot(ns[t[0] as usize]) > 0.0,
                "{s:?}: triangle {i} wound against its normals"
            );
        }
    }
    // Area converges to the closed form (from below for inscribed polygons).
    let sphere = Shape::Sphere(Sphere { radius: 5.0 });
    let a = sphere
        .tessellate(Resolution {
            segments: 400,
            rings: 200,
        })
        .area();
    assert!(
        (a / (4.0 * PI * 25.0) - 1.0).abs() < 2e-4,
        "sphere area {a}"
    );
    let disk = Shape::Disk(Disk {
        inner_radius: 2.0,
        outer_radius: 10.0,
        azimuth: AzimuthRange::FULL,
    });
    let a = disk
        .tessellate(Resolution {
            segments: 1000,
            rings: 3,
        })
        .area();
    assert!((a / (PI * 96.0) - 1.0).abs() < 1e-4, "annulus area {a}");
    let bx = Shape::Cuboid(Cuboid {
        size: DVec3::new(1.0, 2.0, 3.0),
    });
    assert!(
        (bx.tessellate(Resolution {
            segments: 1,
            rings: 1
        })
        .area()
            - 22.0)
            .abs()
            < 1e-12
    );
}

#[test]
fn a_box_tessellates_at_the_resolution_asked() {
    // Each face a 3 × 2 grid: 6 faces × 6 quads × 2 triangles, every vertex on the
    // surface, every facet facing outwards, the area unchanged.
    let size = DVec3::new(1.0, 2.0, 3.0);
    let bx = Shape::Cuboid(Cuboid { size });
    let m = bx.tessellate(Resolution {
        segments: 3,
        rings: 2,
    });
    assert_eq!(m.triangles.len(), 72);
    assert!((m.area() - 22.0).abs() < 1e-12, "{}", m.area());
    let h = 0.5 * size;
    for p in &m.positions {
        let on_face = (0..3).any(|k| (p[k].abs() - h[k]).abs() < 1e-12);
        let inside = (0..3).all(|k| p[k].abs() <= h[k] + 1e-12);
        assert!(on_face && inside, "{p}");
    }
    for i in 0..m.triangles.len() {
        let [a, b, c] = m.triangles[i].map(|k| m.positions[k as usize]);
        let centre = (a + b + c) / 3.0;
        assert!(
            m.face_normal(i).dot(centre) > 0.0,
            "triangle {i} faces inwards"
        );
        // The exact normal of the face the triangle lies on.
        assert_eq!(bx.normal(centre), m.face_normal(i).normalize());
    }
    // A finer grid has more triangles on the same surface.
    let fine = bx.tessellate(Resolution {
        segments: 10,
        rings: 10,
    });
    assert_eq!(fine.triangles.len(), 6 * 200);
    assert!((fine.area() - 22.0).abs() < 1e-12);
}

#[test]
fn moved_paraboloid_and_hyperboloid_are_the_translated_ones() {
    // focus_z / center_z in the coefficients, against the shape at the origin
    // seen through the shift: radius at matching heights, to rounding.
    let (q, dz) = (0.31, -15000.0);
    let moved = RevolutionQuadric::paraboloid(q, dz, 0.0, 300.0, AzimuthRange::FULL);
    let at_origin = RevolutionQuadric::paraboloid(q, 0.0, -dz, 300.0 - dz, AzimuthRange::FULL);
    let (a, b, c) = (3750.9, 17.6, -11250.0);
    let moved_h = RevolutionQuadric::hyperboloid(a, b, c, -300.0, 0.0, AzimuthRange::FULL);
    let origin_h = RevolutionQuadric::hyperboloid(a, b, 0.0, -300.0 - c, -c, AzimuthRange::FULL);
    for k in 0..=30 {
        let z = 10.0 * k as f64;
        let rel = |x: f64, y: f64| (x / y - 1.0).abs();
        assert!(
            rel(moved.radius(z), at_origin.radius(z - dz)) < 1e-12,
            "z = {z}"
        );
        assert!(
            rel(moved_h.radius(-z), origin_h.radius(-z - c)) < 1e-10,
            "z = {}",
            -z
        );
        // Against the closed forms themselves.
        let r2 = 4.0 * q * (z - dz + q);
        assert!(rel(moved.radius_squared(z), r2) < 1e-12);
        let u = (-z - c) / a;
        assert!(rel(moved_h.radius_squared(-z), b * b * (u * u - 1.0)) < 1e-10);
    }
}

#[test]
fn a_surface_cut_into_pieces_is_hit_where_the_whole_is() {
    use traxer::geometry::{AnalyticObject, Transform};
    // Full circles (cut into sectors; the disk also into rings) and a 30°
    // segment (kept whole): the nearest hit over the pieces is the whole
    // shape's, for rays from everywhere, including along the sectors' edges.
    let objects = [
        Shape::Revolution(RevolutionQuadric::paraboloid(
            0.5,
            -15000.0,
            0.0,
            300.0,
            AzimuthRange::FULL,
        )),
        Shape::Revolution(RevolutionQuadric::cone(
            350.0,
            0.0,
            340.0,
            -300.0,
            AzimuthRange::new(10.0, 200.0),
        )),
        Shape::Disk(Disk {
            inner_radius: 0.0,
            outer_radius: 350.0,
            azimuth: AzimuthRange::new(-1.0, 2.3),
        }),
        Shape::Revolution(RevolutionQuadric::cone(
            60.0,
            0.0,
            63.0,
            225.0,
            AzimuthRange::new(-15.0, 30.0),
        )),
    ];
    let mut rng = Lcg(7);
    for shape in objects {
        let object = AnalyticObject {
            shape,
            transform: Transform::default(),
        };
        let pieces = object.pieces();
        let segment = matches!(shape, Shape::Revolution(q) if q.azimuth.span_deg() < 90.0);
        assert_eq!(pieces.is_empty(), segment, "{shape:?}");
        let disk = matches!(shape, Shape::Disk(_));
        let z_target = |rng: &mut Lcg| if disk { 0.0 } else { rng.range(-300.0, 300.0) };
        let (mut hits, mut edge_hits) = (0, 0);
        for k in 0..20_000 {
            let o = DVec3::new(
                rng.range(-400.0, 400.0),
                rng.range(-400.0, 400.0),
                rng.range(-400.0, 400.0),
            );
            // Every tenth ray aims at a sector edge of the pieces.
            let target = if k % 10 == 0 && !pieces.is_empty() {
                let p = &pieces[k % pieces.len()];
                let phi = p.azimuth.start_deg().to_radians();
                let r = 0.5 * (p.inner_radius + p.outer_radius).clamp(200.0, 340.0);
                DVec3::new(r * phi.cos(), r * phi.sin(), z_target(&mut rng))
            } else {
                let z = z_target(&mut rng);
                DVec3::new(rng.range(-350.0, 350.0), rng.range(-350.0, 350.0), z)
            };
            let d = (target - o).normalize();
            let whole = object.intersect_world(o, d, f64::INFINITY, false);
            let cut = if pieces.is_empty() {
                whole
            } else {
                pieces
                    .iter()
                    .filter_map(|p| object.intersect_piece(p, o, d, f64::INFINITY, false))
                    .min_by(f64::total_cmp)
            };
            assert_eq!(whole, cut, "{shape:?}: ray {o} → {d}");
            hits += whole.is_some() as usize;
            edge_hits += (k % 10 == 0 && whole.is_some()) as usize;
        }
        assert!(hits > 200, "{shape:?}: {hits} hits");
        assert!(
            segment || edge_hits > 20,
            "{shape:?}: {edge_hits} edge hits"
        );
    }
}
