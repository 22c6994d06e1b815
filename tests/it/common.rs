//! Helpers shared by the tests.

use std::path::{Path, PathBuf};
use traxer::embree::Device;
use traxer::scene::Scene;

pub fn device() -> Device {
    Device::new().expect("Embree device")
}

/// Writes `text` as `name` in `dir` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Builds a scene from TOML text (files it names are relative to `dir`).
pub fn scene_in(dir: &Path, text: &str) -> Scene {
    let p = write(dir, "scene.toml", text);
    Scene::load(&device(), &p, &[]).unwrap_or_else(|e| panic!("scene should load: {e}"))
}

pub fn scene(text: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    scene_in(dir.path(), text)
}

/// The repository root (for shipped scenes and meshes).
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Flux-weighted centroid and RMS radius (in pixels) of an image [iy][ix].
pub fn centroid_rms(img: &[f64], nx: usize) -> (f64, f64, f64) {
    let (mut w, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for (k, &v) in img.iter().enumerate() {
        let (x, y) = ((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5);
        w += v;
        sx += v * x;
        sy += v * y;
    }
    let (cx, cy) = (sx / w, sy / w);
    let mut s2 = 0.0;
    for (k, &v) in img.iter().enumerate() {
        let (x, y) = ((k % nx) as f64 + 0.5, (k / nx) as f64 + 0.5);
        s2 += v * ((x - cx).powi(2) + (y - cy).powi(2));
    }
    (cx, cy, (s2 / w).sqrt())
}

/// The flat-mirror bench used by several tests: a pencil beam (radius 0.2 mm)
/// along −z from z = 500 meets a 20 × 100 mm flat mirror at the origin at
/// `graze_deg`; a 60 × 60 mm screen lies 200 mm below. `mirror` is the mirror
/// material's table (with `type = "mirror"`), `pixels` the screen's pixels per
/// side, `sensor_extra` and `mirror_extra` extra lines for the sensor material and
/// the mirror object.
pub fn flat_mirror_bench(
    graze_deg: f64,
    mirror: &str,
    energy: &str,
    pixels: u32,
    sensor_extra: &str,
    mirror_extra: &str,
) -> String {
    format!(
        r#"
[[sources]]
type = "parallel"
aperture = {{ center = [0, 0, 500], radius = 0.2 }}
energy = {energy}

[materials.flat_mirror]
{mirror}

[materials.detector]
type = "sensor"
size = [60.0, 60.0]
pixels = [{pixels}, {pixels}]
{sensor_extra}

[[objects]]
name = "flat"
material = "flat_mirror"
shape = {{ type = "rectangle", size = [20.0, 100.0] }}
transform = [ {{ rotate = {{ axis = [1, 0, 0], angle = {angle} }} }} ]
{mirror_extra}

[[objects]]
name = "screen"
material = "detector"
shape = {{ type = "rectangle", size = [60.0, 60.0] }}
transform = [ {{ translate = [0, 0, -200] }} ]
"#,
        // Rotating the rectangle's +z normal about x by (90° − θ) makes the surface
        // meet −z rays at the grazing angle θ.
        angle = 90.0 - graze_deg
    )
}

/// Runs a `traxer` command that must succeed (stderr shown if it does not).
pub fn run_ok(cmd: &mut std::process::Command) -> std::process::Output {
    let out = cmd.output().expect("run traxer");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The error message of a scene that must fail to load.
pub fn load_error(dir: &Path, text: &str) -> String {
    let p = write(dir, "s.toml", text);
    match Scene::load(&device(), &p, &[]) {
        Ok(_) => panic!("the scene should not load"),
        Err(e) => e.to_string(),
    }
}
