//! Visible-light renders: closed-form lighting checks (furnace tests), the camera
//! frame, reproducibility across threads, and X-ray images on sensors.

use glam::DVec3;
use traxer::render::{part_labels, render, Camera, RenderSettings, SensorTexture};
use traxer::scene::Scene;

const UNIFORM_SKY: &str = "[sky]\nzenith = [1.0, 1.0, 1.0]\nhorizon = [1.0, 1.0, 1.0]\n";

fn one_sphere(appearance: &str) -> Scene {
    crate::common::scene(&format!(
        r#"{UNIFORM_SKY}
[[objects]]
name = "ball"
material = "absorber"
shape = {{ type = "sphere", radius = 1.0 }}
appearance = {appearance}
"#
    ))
}

/// Render settings: size, samples per pixel, maximum depth, seed.
fn settings(size: (usize, usize), spp: u32, max_depth: u32, seed: u64) -> RenderSettings {
    RenderSettings {
        width: size.0,
        height: size.1,
        spp,
        max_depth,
        seed,
    }
}

fn looking_at_origin(vfov: f64) -> Camera {
    Camera {
        look_from: DVec3::new(0.0, 0.0, 6.0),
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        vfov,
    }
}

#[test]
fn convex_objects_under_a_uniform_sky_show_their_albedo_exactly() {
    // Under a uniform sky of radiance 1, a ray that hits a convex object bounces
    // once and escapes to the sky: a diffuse or polished-metal surface of albedo ρ
    // has radiance ρ whatever the direction, the background 1.
    for (appearance, rho) in [
        (r#"{ type = "diffuse", color = [0.6, 0.6, 0.6] }"#, 0.6),
        (
            r#"{ type = "metal", color = [0.8, 0.8, 0.8], roughness = 0.3 }"#,
            0.8,
        ),
    ] {
        let s = one_sphere(appearance);
        let img = render(
            &s,
            &looking_at_origin(30.0),
            &s.sky,
            &[],
            &settings((48, 32), 4, 64, 7),
        );
        let (w, h) = (48, 32);
        // The centre pixel sees the sphere, the corner the sky.
        let centre = img[(h / 2) * w + w / 2];
        assert!(
            (centre - DVec3::splat(rho)).abs().max_element() < 1e-12,
            "{centre}"
        );
        assert!((img[0] - DVec3::ONE).abs().max_element() < 1e-12);
        // Every pixel is a mix of the two (edge pixels see both).
        assert!(img.iter().all(|c| c.x >= rho - 1e-12 && c.x <= 1.0 + 1e-12));
    }
}

#[test]
fn clear_glass_under_a_uniform_sky_is_invisible() {
    // A lossless dielectric only redirects light: every path ends in the uniform
    // sky with full weight, so the picture is uniformly 1 (energy conservation of
    // the Fresnel split and refraction), up to paths cut at max_depth.
    let s = one_sphere(r#"{ type = "glass", ior = 1.5 }"#);
    let img = render(
        &s,
        &looking_at_origin(30.0),
        &s.sky,
        &[],
        &settings((48, 32), 16, 64, 7),
    );
    let mean = img.iter().map(|c| c.x).sum::<f64>() / img.len() as f64;
    assert!((mean - 1.0).abs() < 1e-3, "mean {mean}");
}

#[test]
fn an_object_at_the_look_at_point_appears_at_the_image_centre() {
    // A small glowing sphere at look_at, and a second one 1 unit above it
    // (camera 6 units away, vfov 20°): it must appear tan⁻¹(1/6) above the centre,
    // i.e. (1/6)/tan(10°) of the half-height.
    let s = crate::common::scene(
        r#"
[sky]
zenith = [0.0, 0.0, 0.0]
horizon = [0.0, 0.0, 0.0]

[[objects]]
name = "target"
material = "absorber"
shape = { type = "sphere", radius = 0.05 }
transform = [ { translate = [0.3, -0.2, 0.0] } ]
appearance = { type = "emitting", color = [1.0, 0.0, 0.0] }

[[objects]]
name = "above"
material = "absorber"
shape = { type = "sphere", radius = 0.05 }
transform = [ { translate = [0.3, 0.8, 0.0] } ]
appearance = { type = "emitting", color = [0.0, 1.0, 0.0] }
"#,
    );
    let cam = Camera {
        look_from: DVec3::new(0.3, -0.2, 6.0),
        look_at: DVec3::new(0.3, -0.2, 0.0),
        up: DVec3::Y,
        vfov: 20.0,
    };
    let (w, h) = (201, 201);
    let img = render(&s, &cam, &s.sky, &[], &settings((w, h), 4, 4, 1));
    let centroid = |f: fn(&DVec3) -> f64| {
        let (mut sw, mut sx, mut sy) = (0.0, 0.0, 0.0);
        for (k, c) in img.iter().enumerate() {
            let v = f(c);
            sw += v;
            sx += v * ((k % w) as f64 + 0.5);
            sy += v * ((k / w) as f64 + 0.5);
        }
        (sx / sw, sy / sw)
    };
    let (rx, ry) = centroid(|c| c.x);
    assert!(
        (rx - 100.5).abs() < 0.5 && (ry - 100.5).abs() < 0.5,
        "red at ({rx}, {ry})"
    );
    let (gx, gy) = centroid(|c| c.y);
    let expect_up = (1.0f64 / 6.0) / 10f64.to_radians().tan() * 100.5;
    assert!((gx - 100.5).abs() < 0.5, "green at x = {gx}");
    // Rows count down from the top: "above" means a smaller row.
    assert!(
        (100.5 - gy - expect_up).abs() < 1.0,
        "green {} rows up, expected {expect_up}",
        100.5 - gy
    );
}

#[test]
fn the_same_seed_gives_the_same_picture_on_any_number_of_threads() {
    let s = crate::common::scene(
        &std::fs::read_to_string(crate::common::repo().join("scenes/spheres.toml")).unwrap(),
    );
    let cam = s.cameras["classic"];
    let st = settings((60, 40), 4, 12, 3);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&s, &cam, &s.sky, &[], &st))
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
    // ... and another seed gives another picture.
    let other = render(&s, &cam, &s.sky, &[], &RenderSettings { seed: 4, ..st });
    assert_ne!(one, other);
}

#[test]
fn a_sensor_image_glows_on_the_sensor_face() {
    // A 2 × 2 pixel sensor seen face on, filling the view: its left column holds
    // the maximum, the right column nothing. The left half of the picture shows
    // viridis' bright end times the brightness, the right half its dark end.
    let s = crate::common::scene(
        r#"
[sky]
zenith = [0.0, 0.0, 0.0]
horizon = [0.0, 0.0, 0.0]

[materials.detector]
type = "sensor"
size = [10.0, 10.0]
pixels = [2, 2]

[[objects]]
name = "sensor"
material = "detector"
shape = { type = "rectangle", size = [10.0, 10.0] }
"#,
    );
    let tex = SensorTexture::viridis(
        0,
        [10.0, 10.0],
        [2, 2],
        &[4.0, 0.0, 4.0, 0.0],
        traxer::output::Scale::Linear,
        2.0,
    );
    let cam = Camera {
        look_from: DVec3::new(0.0, 0.0, 10.0),
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        vfov: 20.0,
    };
    let st = settings((20, 20), 1, 4, 1);
    let img = render(&s, &cam, &s.sky, &[tex], &st);
    // viridis(1) = #fde725, viridis(0) = #440154 (sRGB) → linear.
    let lin = |c: u8| {
        let c = c as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let bright = DVec3::new(lin(0xfd), lin(0xe7), lin(0x25)) * 2.0;
    let dark = DVec3::new(lin(0x44), lin(0x01), lin(0x54)) * 2.0;
    assert!(
        (img[10 * 20 + 5] - bright).abs().max_element() < 0.02,
        "{}",
        img[10 * 20 + 5]
    );
    assert!(
        (img[10 * 20 + 15] - dark).abs().max_element() < 0.02,
        "{}",
        img[10 * 20 + 15]
    );
}

#[test]
fn a_sensor_image_glows_only_on_the_active_area() {
    // The object (20 mm, an emitting green carrier) is larger than the sensor's
    // active area (10 mm, 2 × 2 pixels, all at the maximum). Outside the active
    // area the picture shows the carrier, not the image's edge pixels smeared
    // outwards (the streaks once seen right of CAST's image on its chip).
    let s = crate::common::scene(
        r#"
[sky]
zenith = [0.0, 0.0, 0.0]
horizon = [0.0, 0.0, 0.0]

[materials.detector]
type = "sensor"
size = [10.0, 10.0]
pixels = [2, 2]

[[objects]]
name = "sensor"
material = "detector"
shape = { type = "rectangle", size = [20.0, 20.0] }
appearance = { type = "emitting", color = [0.0, 1.0, 0.0] }
"#,
    );
    let tex = SensorTexture::viridis(
        0,
        [10.0, 10.0],
        [2, 2],
        &[4.0, 4.0, 4.0, 4.0],
        traxer::output::Scale::Linear,
        1.0,
    );
    // 60 mm away with a 20° field: the picture spans ±10.6 mm, 1.06 mm a pixel.
    let cam = Camera {
        look_from: DVec3::new(0.0, 0.0, 60.0),
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        vfov: 20.0,
    };
    let img = render(&s, &cam, &s.sky, &[tex], &settings((20, 20), 1, 4, 1));
    let green = DVec3::new(0.0, 1.0, 0.0);
    // Column 1 (x ≈ −8.5 mm) and row 1 lie on the carrier; the centre on the image.
    for k in [10 * 20 + 1, 10 * 20 + 18, 20 + 10, 18 * 20 + 10] {
        assert!(
            (img[k] - green).abs().max_element() < 1e-9,
            "pixel {k}: {}",
            img[k]
        );
    }
    assert!(img[10 * 20 + 10].x > 0.5, "centre {}", img[10 * 20 + 10]);
}

#[test]
fn part_labels_sit_on_the_parts_seen_and_name_a_telescope_once() {
    // Two plates left and right of the view and a speck too small to label: the
    // labels name the plates, each at a pixel on its own half of the picture.
    let s = crate::common::scene(
        r#"
[materials.plate]
type = "absorber"

[[objects]]
name = "left plate"
material = "plate"
shape = { type = "rectangle", size = [6.0, 6.0] }
transform = [ { translate = [-5.0, 0.0, 0.0] } ]

[[objects]]
name = "right plate"
material = "plate"
shape = { type = "rectangle", size = [6.0, 6.0] }
transform = [ { translate = [5.0, 0.0, 0.0] } ]

[[objects]]
name = "speck"
material = "plate"
shape = { type = "rectangle", size = [0.1, 0.1] }
transform = [ { translate = [0.0, 8.0, 0.0] } ]
"#,
    );
    let cam = Camera {
        look_from: DVec3::new(0.0, 0.0, 60.0),
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        vfov: 20.0,
    };
    let labels = part_labels(&s, &cam, 100, 100);
    let texts: Vec<&str> = labels.iter().map(|l| l.text.as_str()).collect();
    assert_eq!(texts, ["left plate", "right plate"]);
    assert!(
        labels[0].pixel.0 < 50 && labels[1].pixel.0 > 50,
        "{labels:?}"
    );
    // The LLNL telescope's 130-odd parts are labelled once, by its name.
    let panter = Scene::load(
        &crate::common::device(),
        &crate::common::repo().join("scenes/panter_al_ka.toml"),
        &[],
    )
    .unwrap();
    let cam = panter.cameras["telescope"];
    let texts: Vec<String> = part_labels(&panter, &cam, 160, 100)
        .into_iter()
        .map(|l| l.text)
        .collect();
    assert!(texts.contains(&"llnl".to_string()), "{texts:?}");
    assert!(texts.iter().all(|t| !t.starts_with("llnl_")), "{texts:?}");
}

#[test]
fn render_command_writes_a_png_and_refuses_bad_cameras() {
    let dir = tempfile::tempdir().unwrap();
    let scene = crate::common::repo().join("scenes/panter_al_ka.toml");
    let png = dir.path().join("t.png");
    crate::common::run_ok(
        crate::common::traxer()
            .arg("render")
            .arg(&scene)
            .args([
                "--camera",
                "telescope",
                "--width",
                "40",
                "--height",
                "30",
                "--spp",
                "2",
            ])
            .arg("--out")
            .arg(&png),
    );
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (40, 30));
    // Several cameras and none chosen, an unknown one, a degenerate one, and a
    // sensor image of the wrong shape: exit code 2, no picture written.
    for args in [
        vec![],
        vec!["--camera", "nope"],
        vec![
            "--camera",
            "sensor",
            "--up",
            "0,0,1",
            "--look-from",
            "0,0,5",
            "--look-at",
            "0,0,0",
        ],
        vec!["--camera", "sensor", "--vfov", "0"],
    ] {
        let bad = dir.path().join("bad.png");
        let out = crate::common::traxer()
            .arg("render")
            .arg(&scene)
            .args(&args)
            .arg("--out")
            .arg(&bad)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!bad.exists(), "{args:?}");
    }
    let npy = dir.path().join("wrong.npy");
    traxer::output::write_npy_f64(&npy, &[3, 3], &[1.0; 9]).unwrap();
    let out = crate::common::traxer()
        .arg("render")
        .arg(&scene)
        .args(["--camera", "sensor", "--sensor-image"])
        .arg(&npy)
        .arg("--out")
        .arg(dir.path().join("bad.png"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not match sensor"));
}

/// A scene with only a Sun source (0.989 AU, offset and sun_scale as given) under
/// a uniform white sky.
fn sun_in_the_sky(offset_arcmin: [f64; 2], sun_scale: f64) -> Scene {
    crate::common::scene(&format!(
        r#"
[sky]
zenith = [1.0, 1.0, 1.0]
horizon = [1.0, 1.0, 1.0]
sun_scale = {sun_scale}

[[sources]]
type = "sun"
offset_arcmin = {offset_arcmin:?}
target = {{ center = [0.0, 0.0, 0.0], radius = 21.5 }}
"#
    ))
}

#[test]
fn the_sun_shows_as_a_disk_of_its_true_angular_size_where_it_stands() {
    // The solar disk seen from 0.989 AU has an angular radius
    // ρ = asin(R_sun / d) = asin(6.96342e8 m / (0.989 × 1.495978707e11 m)) = 0.2697°.
    // A pinhole camera looking along it (vfov 2°, 240 px high) maps the cone to a
    // circle of tan ρ / tan 1° × 120 px radius. Each pixel's blue channel mixes the
    // white sky (1) and the default sun colour (0.12), so summing the mixing
    // fractions gives the disk's area in pixels; 16 random samples per pixel leave
    // an edge noise of a few pixels in ≈ 2300, so 1 % is ample.
    let rho = (6.963_42e8 / (0.989 * 1.495_978_707e11_f64)).asin();
    let (w, h) = (240usize, 240usize);
    let camera = Camera {
        look_from: DVec3::ZERO,
        look_at: DVec3::new(0.0, 0.0, 1000.0),
        up: DVec3::Y,
        vfov: 2.0,
    };
    let px = |angle: f64| angle.tan() / 1f64.to_radians().tan() * 0.5 * h as f64;
    for (offset, scale) in [([0.0, 0.0], 1.0), ([20.0, 0.0], 2.0)] {
        let s = sun_in_the_sky(offset, scale);
        let img = render(&s, &camera, &s.sky, &[], &settings((w, h), 16, 4, 3));
        let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
        for (k, c) in img.iter().enumerate() {
            let f = (1.0 - c.z) / (1.0 - 0.12);
            area += f;
            cx += f * ((k % w) as f64 + 0.5);
            cy += f * ((k / w) as f64 + 0.5);
        }
        let (cx, cy) = (cx / area, cy / area);
        let expected = std::f64::consts::PI * px(rho * scale).powi(2);
        assert!(
            (area / expected - 1.0).abs() < 0.01,
            "offset {offset:?}: area {area} px, expected {expected}"
        );
        // Looking along +z with +y up, +x is on the left. A 20′ offset in x moves
        // the disk by tan(20′)/tan(1°) × 120 px.
        let dx = px((offset[0] / 60.0f64).to_radians());
        assert!(
            (cx - (0.5 * w as f64 - dx)).abs() < 0.5,
            "centre x {cx}, dx {dx}"
        );
        assert!((cy - 0.5 * h as f64).abs() < 0.5, "centre y {cy}");
    }
}
