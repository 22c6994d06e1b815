//! The photon loop's rules: the interaction limit, one-sided mirrors, sensors
//! outside their active area, and `traxer tessellate` output lying on the surface.

use crate::common::scene;
use traxer::trace::{self, RunConfig};

fn run(s: &traxer::scene::Scene, n: u64) -> traxer::trace::RunResult {
    trace::run(s, &RunConfig::new(n, 1)).unwrap()
}

#[test]
fn photons_trapped_between_mirrors_stop_at_max_interactions() {
    // A beam enters a closed mirror box (a sphere mirror around it): it can never
    // leave, so every photon ends at the interaction limit after exactly that many
    // hits on the mirror.
    let s = scene(
        r#"
max_interactions = 7

[[sources]]
type = "parallel"
aperture = { center = [0, 0, 0], radius = 1.0 }
energy = { line = 1.0 }

[[objects]]
name = "cavity"
material = "mirror"
shape = { type = "sphere", radius = 10.0 }
"#,
    );
    let r = run(&s, 1000);
    assert_eq!(r.stats.max_interactions_reached, 1000);
    assert_eq!(r.stats.hits_per_object[0], 7000);
    assert_eq!(r.stats.embree_queries, 7000);
}

#[test]
fn one_sided_mirrors_absorb_on_the_back_and_sensors_only_record_their_area() {
    // A cylinder segment facing the axis: photons arriving from outside hit its
    // back. The sensor's active area (2 × 2 mm) is smaller than its rectangle.
    let s = scene(
        r#"
[materials.inner]
type = "mirror"
side = "front"

[materials.detector]
type = "sensor"
size = [2.0, 2.0]
pixels = [4, 4]

[[sources]]
type = "parallel"
direction = [-1, 0, 0]
aperture = { center = [50, 0, 0], radius = 1.0 }
energy = { line = 1.0 }

[[sources]]
type = "parallel"
aperture = { center = [30, 0, 10], radius = 3.0 }
energy = { line = 1.0 }

[[objects]]
name = "tube"
material = "inner"
shape = { type = "cylinder", radius = 20.0, z_start = -5.0, z_end = 5.0 }

[[objects]]
name = "sensor"
material = "detector"
shape = { type = "rectangle", size = [6.0, 6.0] }
transform = [ { translate = [30, 0, 0] } ]
"#,
    );
    let r = run(&s, 20_000);
    // Source 0 (even photons) hits the tube's back; source 1 (odd) hits the sensor,
    // inside its 2 × 2 mm area with probability 4 / (π 3²).
    assert_eq!(r.stats.absorbed_mirror_back, 10_000);
    let inside = r.stats.reached_sensor as f64;
    assert_eq!(r.stats.reached_sensor + r.stats.sensor_outside_area, 10_000);
    let p = 4.0 / (std::f64::consts::PI * 9.0);
    let sigma = (10_000.0 * p * (1.0 - p)).sqrt();
    assert!(
        (inside - 10_000.0 * p).abs() < 4.0 * sigma,
        "{inside} inside vs {}",
        10_000.0 * p
    );
    assert_eq!(r.images[0].total_counts(), r.stats.reached_sensor);
}

#[test]
fn tessellate_command_writes_meshes_on_the_exact_surface() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["gltf", "glb", "obj"] {
        let out = dir.path().join(format!("cone.{ext}"));
        let status = crate::common::traxer()
            .args(["tessellate", "--shape"])
            .arg("type = \"cone\", radius_start = 63.2384, z_start = 229.0, radius_end = 60.9121, z_end = 4.0, azimuth = [-15.0, 15.0]")
            .args(["--segments", "500", "--rings", "20", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(
            status.status.success(),
            "{}",
            String::from_utf8_lossy(&status.stderr)
        );
        let (m, report) = traxer::mesh::load(&out).unwrap();
        assert!(report.normals_from_file);
        assert_eq!(m.triangles.len(), 2 * 500 * 20);
        assert_eq!(m.positions.len(), 501 * 21);
        // Every vertex on the cone r(z) = 60.9121 + (z − 4)·(63.2384 − 60.9121)/225
        // (f32 in glTF: ~1e-5 mm), within the azimuth range.
        let tol = if ext == "obj" { 1e-9 } else { 2e-5 };
        for p in &m.positions {
            let r = 60.9121 + (p.z - 4.0) * (63.2384 - 60.9121) / 225.0;
            assert!(
                (p.truncate().length() - r).abs() < tol,
                "{ext}: {p} off the cone"
            );
            assert!(p.y.atan2(p.x).to_degrees().abs() <= 15.0 + 1e-4);
        }
        // Exact normals face the axis and are perpendicular to the cone's slope.
        for (p, n) in m.positions.iter().zip(m.normals.as_ref().unwrap()) {
            assert!(n.dot(p.truncate().extend(0.0)) < 0.0);
            let along = glam::DVec3::new(
                p.x / p.truncate().length() * (63.2384 - 60.9121) / 225.0,
                p.y / p.truncate().length() * (63.2384 - 60.9121) / 225.0,
                1.0,
            );
            assert!(
                n.dot(along).abs() < 1e-6,
                "{ext}: normal {n} not perpendicular to the slope"
            );
        }
    }
    // Bad input: exit code 2 with the reason.
    let err = crate::common::run_fails(
        crate::common::traxer()
            .args([
                "tessellate",
                "--shape",
                "type = \"cone\", radius_start = 1",
                "--out",
            ])
            .arg(dir.path().join("x.obj")),
        2,
    );
    assert!(err.contains("missing field"), "{err}");
}
