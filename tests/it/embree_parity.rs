//! Embree's f32 triangle hits agree with a brute-force f64 ray/triangle test, and
//! reflected rays never re-hit the surface they leave, even at grazing angles.

use crate::common::{scene, scene_in, write};
use crate::geometry::Lcg;
use glam::DVec3;
use traxer::raycast::{intersect, reflect};
use traxer::scene::ObjectGeometry;

/// Möller–Trumbore in f64: (t, barycentric u, v) of a hit with t > 0.
fn ray_triangle(o: DVec3, d: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, f64, f64)> {
    let e1 = b - a;
    let e2 = c - a;
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let s = o - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some((t, u, v))
}

#[test]
fn embree_mesh_hits_agree_with_brute_force_f64() {
    // A random triangle soup (OBJ) plus a tessellated grazing cone segment.
    let dir = tempfile::tempdir().unwrap();
    let mut rng = Lcg(11);
    let mut obj = String::new();
    let n_tri = 400;
    for _ in 0..n_tri {
        let c = DVec3::new(
            rng.range(-50., 50.),
            rng.range(-50., 50.),
            rng.range(-50., 50.),
        );
        for _ in 0..3 {
            let v = c + rng.unit() * rng.range(1.0, 15.0);
            obj += &format!("v {} {} {}\n", v.x, v.y, v.z);
        }
    }
    for i in 0..n_tri {
        obj += &format!("f {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3);
    }
    write(dir.path(), "soup.obj", &obj);
    let s = scene_in(
        dir.path(),
        r#"
[[sources]]
type = "parallel"
aperture = { center = [0, 0, 300], radius = 1.0 }
energy = { line = 1.0 }

[[objects]]
name = "soup"
material = "absorber"
shape = { type = "mesh", file = "soup.obj" }

[[objects]]
name = "cone"
material = "absorber"
shape = { type = "cone", radius_start = 63.0, z_start = 120.0, radius_end = 61.0, z_end = -100.0, azimuth = [-15, 15] }
tessellate = { segments = 200, rings = 10 }
"#,
    );
    // All triangles of the scene, in world space.
    let mut tris = Vec::new();
    for (oi, o) in s.objects.iter().enumerate() {
        let ObjectGeometry::Mesh(m) = &o.geometry else {
            panic!("meshes only")
        };
        for (pi, t) in m.triangles.iter().enumerate() {
            tris.push((oi, pi, t.map(|k| m.positions[k as usize])));
        }
    }
    let (mut agree, mut edge_cases, mut total) = (0, 0, 0);
    for k in 0..6000 {
        // Half the rays are aimed at a random point of a random triangle (so they
        // hit), half go in random directions.
        let o = DVec3::new(
            rng.range(-120., 120.),
            rng.range(-120., 120.),
            rng.range(-120., 120.),
        );
        let d = if k % 2 == 0 {
            let (_, _, [a, b, c]) = tris[(rng.next() * tris.len() as f64) as usize];
            let (u, v) = (rng.next(), rng.next());
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            (a + (b - a) * u + (c - a) * v - o).normalize()
        } else {
            rng.unit()
        };
        let brute = tris
            .iter()
            .filter_map(|(oi, pi, [a, b, c])| {
                ray_triangle(o, d, *a, *b, *c).map(|(t, u, v)| (t, u, v, *oi, *pi))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0));
        let embree = intersect(&s, o, d, None);
        total += 1;
        match (brute, embree) {
            (None, None) => agree += 1,
            (Some((t, _, _, oi, _)), Some(h))
                if h.object == oi && ((h.point - o).length() - t).abs() < 1e-9 * (1.0 + t) =>
            {
                agree += 1
            }
            (b, e) => {
                // Acceptable only where f32 rounding decides: a hit within 1e-5 of a
                // triangle edge (barycentric) or two surfaces at almost the same t.
                let near_edge = b.is_some_and(|(_, u, v, _, _)| u.min(v).min(1.0 - u - v) < 1e-5);
                let near_tie = match (b, e) {
                    (Some((t, ..)), Some(h)) => ((h.point - o).length() - t).abs() < 1e-4 * t,
                    _ => false,
                };
                let embree_near_edge = e.is_some_and(|h| {
                    tris.iter().any(|(oi, _, [a, b, c])| {
                        *oi == h.object
                            && ray_triangle(o, d, *a, *b, *c)
                                .is_some_and(|(_, u, v)| u.min(v).min(1.0 - u - v) < 1e-5)
                    })
                });
                assert!(
                    near_edge || near_tie || embree_near_edge,
                    "ray {k}: brute force {b:?} vs Embree {e:?}"
                );
                edge_cases += 1;
            }
        }
    }
    assert!(
        edge_cases * 1000 < total,
        "{edge_cases} edge cases out of {total}: more than 0.1 %"
    );
    assert!(agree + edge_cases == total);
}

fn reflected_rays_never_rehit_their_surface(tessellate: &str) {
    let s = scene(&format!(
        r#"
[[sources]]
type = "parallel"
aperture = {{ center = [0, 0, 300], radius = 1.0 }}
energy = {{ line = 1.0 }}

[[objects]]
name = "cone"
material = "mirror"
shape = {{ type = "cone", radius_start = 63.2384, z_start = 229.0, radius_end = 60.9121, z_end = 4.0, azimuth = [-15, 15] }}
{tessellate}
"#
    ));
    let cone_slope = ((63.2384f64 - 60.9121) / 225.0).atan();
    let mut rng = Lcg(5);
    let mut count = 0;
    let mesh_vertices: Vec<DVec3> = match &s.objects[0].geometry {
        ObjectGeometry::Mesh(m) => m.positions.clone(),
        _ => Vec::new(),
    };
    for k in 0..20_000 {
        // Target: a random point, or (every third ray) exactly a mesh vertex or an
        // edge midpoint, where seams make leaks likely.
        let z = rng.range(10.0, 220.0);
        let phi = rng.range(-14.5f64, 14.5).to_radians();
        let r = 60.9121 + (z - 4.0) * cone_slope.tan();
        let mut target = DVec3::new(r * phi.cos(), r * phi.sin(), z);
        if k % 3 == 0 && !mesh_vertices.is_empty() {
            let i = (rng.next() * mesh_vertices.len() as f64) as usize;
            let j = (i + 1).min(mesh_vertices.len() - 1);
            target = if k % 2 == 0 {
                mesh_vertices[i]
            } else {
                0.5 * (mesh_vertices[i] + mesh_vertices[j])
            };
            if target.z < 10.0 || target.z > 220.0 || target.y.abs() > 0.24 * target.x {
                continue;
            }
        }
        // Grazing angles from 0.05° to 3° relative to the cone surface.
        let graze = rng.range(0.05f64, 3.0).to_radians();
        let radial = DVec3::new(target.x, target.y, 0.0).normalize();
        let tilt = cone_slope + graze;
        let d = (radial * tilt.sin() - DVec3::Z * tilt.cos()).normalize();
        let o = target - d * 30.0;
        let Some(h) = intersect(&s, o, d, None) else {
            continue;
        };
        let out = reflect(d, h.shading_normal);
        if let Some(h2) = intersect(&s, h.point, out, Some(&h)) {
            // A second hit on a cone segment this narrow needs the ray to cross the
            // axis region: it can only be far away, never at the start point.
            assert!(
                (h2.point - h.point).length() > 10.0,
                "ray {k}: re-hit its own surface {} mm away",
                (h2.point - h.point).length()
            );
        }
        count += 1;
    }
    assert!(count > 10_000);
}

#[test]
fn analytic_reflections_never_rehit_their_surface() {
    reflected_rays_never_rehit_their_surface("");
}

#[test]
fn mesh_reflections_never_rehit_their_surface() {
    reflected_rays_never_rehit_their_surface(
        "tessellate = { segments = 500, rings = 20 }\nsmooth_normals = true",
    );
    reflected_rays_never_rehit_their_surface("tessellate = { segments = 100, rings = 4 }");
}

#[test]
fn rays_embree_cannot_represent_miss_instead_of_aborting() {
    // Debian's Embree 3 asserts `ray.valid()` and aborts the process on NaN or
    // coordinates beyond 1.8e18; such a query must simply miss. A sphere around
    // the origin is hit by the valid ray and by nothing else.
    let s = scene(
        r#"
[[objects]]
name = "ball"
material = "absorber"
shape = { type = "sphere", radius = 10.0 }
"#,
    );
    let q = |origin: [f64; 3], dir: [f64; 3]| traxer::embree::Query {
        origin,
        dir,
        t_max: f64::INFINITY,
        start_geometry: traxer::embree::INVALID_ID,
    };
    assert!(s
        .embree
        .intersect(&q([0.0, 0.0, 100.0], [0.0, 0.0, -1.0]))
        .is_some());
    for bad in [
        q([f64::NAN, 0.0, 100.0], [0.0, 0.0, -1.0]),
        q([0.0, 0.0, 1e300], [0.0, 0.0, -1.0]),
        q([0.0, 0.0, 100.0], [0.0, f64::INFINITY, -1.0]),
        q([0.0, 0.0, 100.0], [0.0, 0.0, f64::NAN]),
    ] {
        assert!(s.embree.intersect(&bad).is_none(), "{bad:?}");
    }
}

/// The nested-shell search (radius lookup, exact quadrics, Embree for the rest)
/// answers every query of a real run as Embree over the whole scene does, and
/// traces the same images: XMM's 58 Wolter shells (232 surfaces) and BabyIAXO's.
#[test]
fn nested_shell_search_answers_as_embree_does() {
    use traxer::embree::Query;
    use traxer::raycast::QueryHook;
    use traxer::trace::{run, trace_range_with, RunConfig};
    struct Recorder(Vec<Query>);
    impl QueryHook for Recorder {
        fn query(&mut self, q: &Query) {
            self.0.push(*q);
        }
    }
    let device = crate::common::device();
    for name in ["xmm_effective_area.toml", "babyiaxo_axion_image.toml"] {
        let path = crate::common::repo().join("scenes").join(name);
        let mut scene = traxer::scene::Scene::load(&device, &path, &[]).unwrap();
        let search = scene.shell_search.as_ref().expect("a nested telescope");
        assert!(
            search.shells.ids().count() > 100,
            "{name}: shells not found"
        );

        // Every query of 20 000 photons: the same object at the same distance.
        let mut rec = Recorder(Vec::new());
        trace_range_with(&scene, 5, 0, 20_000, &mut rec);
        assert!(rec.0.len() > 20_000, "{name}: only {} queries", rec.0.len());
        let answer = |h: Option<traxer::embree::Hit>| h.map(|h| (h.geometry, h.t));
        let differing = rec
            .0
            .iter()
            .filter(|q| answer(search.intersect(q)) != answer(scene.embree.intersect(q)))
            .count();
        assert_eq!(
            differing,
            0,
            "{name}: {differing} of {} queries differ",
            rec.0.len()
        );

        // The images of a run with and without it. The same answers make them
        // identical; a search that missed shells would change the counts far
        // beyond this bound (1 photon in 10⁴).
        let cfg = RunConfig::new(100_000, 9);
        let with = run(&scene, &cfg).unwrap();
        scene.shell_search = None;
        let without = run(&scene, &cfg).unwrap();
        let (a, b) = (
            with.images[0].counts.to_vec(),
            without.images[0].counts.to_vec(),
        );
        let moved: u64 = a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y)).sum();
        assert!(moved <= 10, "{name}: {moved} photons land elsewhere");
        let total: u64 = a.iter().sum();
        assert!(total > 1000, "{name}: only {total} photons on the sensor");
    }
}
