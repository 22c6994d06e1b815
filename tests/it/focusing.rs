//! Closed-form optics: a paraboloid focuses an axial beam to its focus, a flat
//! mirror deflects by twice the grazing angle, a true Wolter-I pair focuses at its
//! design focal length.

use crate::common::{centroid_rms, scene};
use glam::DVec3;
use traxer::random::PhotonRng;
use traxer::raycast::{intersect, reflect};
use traxer::scene::Scene;
use traxer::trace::{self, RunConfig};

/// Emits `n` photons of the scene's first source, reflects each once, and returns
/// the points where the reflected rays cross the plane z = z_plane.
fn single_reflection_spots(s: &Scene, n: u64, z_plane: f64) -> Vec<DVec3> {
    let mut out = Vec::new();
    for i in 0..n {
        let mut rng = PhotonRng::new(3, i);
        let p = s.sources[0].emit(&mut rng);
        let Some(h) = intersect(s, p.origin, p.dir, None) else {
            continue;
        };
        let d = reflect(p.dir, h.shading_normal);
        let t = (z_plane - h.point.z) / d.z;
        out.push(h.point + d * t);
    }
    out
}

fn paraboloid_scene(extra: &str) -> String {
    // r² = 4q(z + q), q = 0.5 mm, focus at the origin; the beam annulus r = 40..45 mm
    // meets it at z ≈ 800..1012 mm, i.e. at grazing angles of 0.6–0.8° like an
    // X-ray mirror.
    format!(
        r#"
[[sources]]
type = "parallel"
aperture = {{ center = [0, 0, 1100], radius = 45.0, inner_radius = 40.0 }}
energy = {{ line = 1.0 }}

[[objects]]
name = "paraboloid"
material = "mirror"
shape = {{ type = "paraboloid", focal_length = 0.5, z_start = 790.0, z_end = 1020.0 }}
{extra}
"#
    )
}

fn max_radius(spots: &[DVec3]) -> f64 {
    spots
        .iter()
        .map(|p| p.truncate().length())
        .fold(0.0, f64::max)
}

#[test]
fn analytic_paraboloid_focuses_an_axial_beam_to_its_focus() {
    let s = scene(&paraboloid_scene(""));
    let spots = single_reflection_spots(&s, 20_000, 0.0);
    assert_eq!(spots.len(), 20_000, "every photon hits the paraboloid");
    let r = max_radius(&spots);
    // f64 refinement: the spot is a point up to rounding (~1e-13 relative of 1000 mm).
    assert!(r < 1e-8, "analytic spot radius {r} mm");
}

#[test]
fn tessellated_paraboloid_focuses_within_the_stated_bound() {
    // 720 azimuthal × 40 axial quads. Smooth (interpolated exact) normals: the hit
    // lies on the chord, at most r·(1 − cos(Δφ/2)) ≈ 45·(1 − cos 0.25°) ≈ 4e-4 mm
    // inside the surface, and the interpolated normal is exact to O(Δφ²); the
    // spot radius is bounded by ~10× that sag: 5 µm.
    let s = scene(&paraboloid_scene(
        "tessellate = { segments = 720, rings = 40 }\nsmooth_normals = true",
    ));
    let spots = single_reflection_spots(&s, 20_000, 0.0);
    assert_eq!(spots.len(), 20_000);
    let smooth = max_radius(&spots);
    assert!(
        smooth < 5e-3,
        "smooth-normal tessellated spot radius {smooth} mm"
    );

    // Flat facets tilt the normal sideways by up to Δφ/2 = 0.25°; the reflected ray
    // then turns by ≈ 2 sin(θ) · 0.25° ≈ 2·0.013·4.4e-3 rad over ~900 mm: ~0.1 mm.
    let s = scene(&paraboloid_scene(
        "tessellate = { segments = 720, rings = 40 }",
    ));
    let flat = max_radius(&single_reflection_spots(&s, 20_000, 0.0));
    assert!(
        flat > 10.0 * smooth && flat < 0.3,
        "flat-facet spot radius {flat} mm"
    );
}

#[test]
fn tessellated_paraboloid_converges_with_resolution() {
    let mut last = f64::INFINITY;
    for segments in [90, 360, 1440] {
        let s = scene(&paraboloid_scene(&format!(
            "tessellate = {{ segments = {segments}, rings = 20 }}\nsmooth_normals = true"
        )));
        let r = max_radius(&single_reflection_spots(&s, 5000, 0.0));
        assert!(
            r < last,
            "{segments} segments: spot {r} mm not below {last} mm"
        );
        last = r;
    }
}

fn flat_mirror_scene(graze_deg: f64, tessellate: bool) -> String {
    let tess = if tessellate {
        "tessellate = { segments = 7, rings = 3 }"
    } else {
        ""
    };
    crate::common::flat_mirror_bench(
        graze_deg,
        "type = \"mirror\"",
        "{ line = 1.0 }",
        1200,
        "",
        tess,
    )
}

#[test]
fn flat_mirror_deflects_by_twice_the_grazing_angle() {
    for tess in [false, true] {
        for graze in [0.3, 1.0, 3.0] {
            let s = scene(&flat_mirror_scene(graze, tess));
            // Direction check on single reflections.
            for i in 0..500 {
                let mut rng = PhotonRng::new(9, i);
                let p = s.sources[0].emit(&mut rng);
                let h = intersect(&s, p.origin, p.dir, None).expect("hits the mirror");
                let d = reflect(p.dir, h.shading_normal);
                let angle = p.dir.angle_between(d).to_degrees();
                assert!(
                    (angle - 2.0 * graze).abs() < 1e-9,
                    "tess {tess}: deflection {angle} for θ = {graze}"
                );
            }
            // Full trace: the mirror normal is (0, −cos θ, sin θ), so the reflected
            // direction is (0, −sin 2θ, −cos 2θ) and the spot on the screen 200 mm
            // below the mirror centre is at y = −200·tan(2θ).
            let r = trace::run(&s, &RunConfig::new(20_000, 1)).unwrap();
            assert_eq!(r.stats.reached_sensor, 20_000, "tess {tess}, θ {graze}");
            let (_, cy, _) = centroid_rms(&r.images[0].flux(), 1200);
            let y_mm = cy * 60.0 / 1200.0 - 30.0;
            let expected = -200.0 * (2.0 * graze.to_radians()).tan();
            assert!(
                (y_mm - expected).abs() < 0.02,
                "tess {tess}, θ {graze}: spot at y = {y_mm} mm, expected {expected}"
            );
        }
    }
}

/// Wolter-I equal-angle design (Van Speybroeck & Chase 1972), computed here
/// independently of `geometry::wolter` and the `nested_telescope` assembly:
/// returns the scene objects.
fn wolter_shell(f: f64, l: f64, r0: f64, i: usize) -> String {
    let theta = (r0 / f).atan() / 4.0;
    let d = r0 / (2.0 * theta).tan();
    let zp = -d;
    let q = (-d + (d * d + r0 * r0).sqrt()) / 2.0;
    let zc = (zp - f) / 2.0;
    let c = (-f - zp).abs() / 2.0;
    let a = ((r0 * r0 + zp * zp).sqrt() - (r0 * r0 + f * f).sqrt()) / 2.0;
    let b = (c * c - a * a).sqrt();
    format!(
        r#"
[[objects]]
name = "p{i}"
material = "shell"
shape = {{ type = "paraboloid", focal_length = {q:e}, z_start = {z0:e}, z_end = {z1:e} }}
transform = [ {{ translate = [0, 0, {zp:e}] }} ]

[[objects]]
name = "h{i}"
material = "shell"
shape = {{ type = "hyperboloid", semi_axis_a = {a:e}, semi_axis_b = {b:e}, z_start = {h0:e}, z_end = {h1:e} }}
transform = [ {{ translate = [0, 0, {zc:e}] }} ]
"#,
        z0 = -zp,
        z1 = l - zp,
        h0 = -l - zc,
        h1 = -zc
    )
}

#[test]
fn wolter1_pair_focuses_at_its_design_focal_length() {
    let f = 1500.0;
    let mut text = String::from(
        r#"
[[sources]]
type = "parallel"
aperture = { center = [0, 0, 200], radius = 82.0, inner_radius = 48.0 }
energy = { line = 1.49 }

[materials.shell]
type = "mirror"
side = "front"

[materials.detector]
type = "sensor"
size = [2.0, 2.0]
pixels = [200, 200]

[[objects]]
name = "sensor"
material = "detector"
shape = { type = "rectangle", size = [2.0, 2.0] }
transform = [ { translate = [0, 0, -1500] } ]
"#,
    );
    for (i, r0) in [50.0, 60.0, 70.0, 80.0].into_iter().enumerate() {
        text += &wolter_shell(f, 100.0, r0, i);
    }
    let s = scene(&text);
    let n = 200_000;
    let r = trace::run(&s, &RunConfig::new(n, 5)).unwrap();
    // Photons entering between a shell's front radius and its radius at the
    // intersection plane are reflected twice and reach the focus: the expected
    // fraction is Σ (R_front² − r0²) / (82² − 48²), with R_front² = 4q(L − z_p + q).
    let mut area = 0.0;
    for r0 in [50.0f64, 60.0, 70.0, 80.0] {
        let theta = (r0 / f).atan() / 4.0;
        let d = r0 / (2.0 * theta).tan();
        let q = (-d + (d * d + r0 * r0).sqrt()) / 2.0;
        area += 4.0 * q * (100.0 + d + q) - r0 * r0;
    }
    let p = area / (82.0f64.powi(2) - 48.0f64.powi(2));
    let expected = p * n as f64;
    let sigma = (n as f64 * p * (1.0 - p)).sqrt();
    let got = r.stats.reached_sensor as f64;
    assert!(
        (got - expected).abs() < 4.0 * sigma,
        "reached {got}, expected {expected} ± {sigma}"
    );
    assert_eq!(r.stats.max_interactions_reached, 0);
    // All flux in the four pixels around the focus (10 µm pixels): the on-axis
    // Wolter-I image is a point.
    let img = &r.images[0].flux();
    let central: f64 = [(99, 99), (99, 100), (100, 99), (100, 100)]
        .iter()
        .map(|&(y, x)| img[y * 200 + x])
        .sum();
    assert_eq!(central, r.images[0].total_flux());
    // And moving the sensor by 5 mm defocuses it into a ring of radius
    // ≈ 5 mm · tan(4θ) = 5 · r0/f for each shell: 0.167 … 0.267 mm.
    let s = scene(&text.replace("translate = [0, 0, -1500]", "translate = [0, 0, -1495]"));
    let r = trace::run(&s, &RunConfig::new(200_000, 5)).unwrap();
    let img = &r.images[0].flux();
    let mut rmin = f64::INFINITY;
    let mut rmax: f64 = 0.0;
    for (k, &v) in img.iter().enumerate() {
        if v > 0.0 {
            let x = ((k % 200) as f64 + 0.5) * 0.01 - 1.0;
            let y = ((k / 200) as f64 + 0.5) * 0.01 - 1.0;
            let rr = x.hypot(y);
            rmin = rmin.min(rr);
            rmax = rmax.max(rr);
        }
    }
    assert!(
        (rmin - 5.0 * 50.0 / 1500.0).abs() < 0.02 && (rmax - 5.0 * 81.3 / 1500.0).abs() < 0.02,
        "defocus ring {rmin}..{rmax} mm"
    );
}

#[test]
fn point_source_at_finite_distance_focuses_where_the_lens_equation_says() {
    // Source 130.297 m away: the image forms at f·D/(D − f) = 1517.47 mm, not at
    // f = 1500 mm. The RMS spot radius there must be several times smaller than
    // 2.5 mm before or after it, and the design focus must be far worse.
    let rms_at = |z: f64| {
        let s = Scene::load(
            &crate::common::device(),
            &crate::common::repo().join("scenes/wolter1_point_source.toml"),
            &[format!("sensor_z={z}")],
        )
        .unwrap();
        let r = trace::run(&s, &RunConfig::new(300_000, 2)).unwrap();
        assert!(r.stats.reached_sensor > 20_000);
        centroid_rms(&r.images[0].flux(), 512).2 * 14.0 / 512.0
    };
    let f = 1500.0;
    let d = 130_297.0;
    let image = f * d / (d - f);
    let best = rms_at(-image);
    let (before, after, design) = (rms_at(-image + 2.5), rms_at(-image - 2.5), rms_at(-f));
    assert!(
        best * 3.0 < before && best * 3.0 < after,
        "rms {before} / {best} / {after} mm around {image} mm"
    );
    assert!(
        design > 10.0 * best,
        "design focus rms {design} mm vs {best} mm"
    );
}
