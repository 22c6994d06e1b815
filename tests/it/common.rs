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
