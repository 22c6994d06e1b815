//! The path tracer: per pixel `spp` camera rays through random points of the
//! pixel, each followed through at most `max_depth` bounces (diffuse, metal,
//! glass), lit by the sky and by emitting surfaces. Pixel k draws its random
//! numbers from the stream (seed, k), so a render is identical for any number of
//! threads.

use super::camera::Frame;
use super::{Appearance, Camera, Sky};
use crate::colormap::{self, Scale};
use crate::material::Material;
use crate::progress::Progress;
use crate::random::PhotonRng;
use crate::raycast::{intersect, reflect, SurfaceHit};
use crate::scene::Scene;
use glam::DVec3;
use rayon::prelude::*;

/// Image size and sampling.
#[derive(Clone, Copy, Debug)]
pub struct RenderSettings {
    pub width: usize,
    pub height: usize,
    /// Samples (camera rays) per pixel.
    pub spp: u32,
    /// Bounces after which a path stops (contributing nothing more).
    pub max_depth: u32,
    pub seed: u64,
}

/// An X-ray sensor image shown on its sensor's face as emitted light.
#[derive(Clone, Debug)]
pub struct SensorTexture {
    /// Index of the sensor object in the scene.
    pub object: usize,
    pub size: [f64; 2],
    pub pixels: [usize; 2],
    /// Linear RGB radiance per pixel, row-major [iy][ix], iy along local +y.
    pub radiance: Vec<DVec3>,
}

impl SensorTexture {
    /// The image through viridis (`values` row-major, like the `.npy` files),
    /// as the sensor PNGs show it, scaled so that the brightest pixel emits
    /// `brightness`.
    pub fn viridis(
        object: usize,
        size: [f64; 2],
        pixels: [usize; 2],
        values: &[f64],
        scale: Scale,
        brightness: f64,
    ) -> SensorTexture {
        let max = colormap::max_value(values);
        let radiance = values
            .iter()
            .map(|&v| {
                // The colour map is sRGB; light adds in linear RGB.
                DVec3::from_array(colormap::viridis(v, max, scale).map(srgb_to_linear)) * brightness
            })
            .collect();
        SensorTexture {
            object,
            size,
            pixels,
            radiance,
        }
    }

    /// The image's radiance at a point of the sensor object, or None outside
    /// the sensor's active area: the object may be larger than the area its
    /// pixels cover (CAST's 24 mm chip carrier around the 14 mm active area), and
    /// clamping to the edge pixels there drew each edge pixel as a streak.
    fn at(&self, local: DVec3) -> Option<DVec3> {
        let fx = local.x / self.size[0] + 0.5;
        let fy = local.y / self.size[1] + 0.5;
        if !(0.0..=1.0).contains(&fx) || !(0.0..=1.0).contains(&fy) {
            return None;
        }
        // fx = 1 exactly lies on the far edge: the last pixel.
        let ix = ((fx * self.pixels[0] as f64) as usize).min(self.pixels[0] - 1);
        let iy = ((fy * self.pixels[1] as f64) as usize).min(self.pixels[1] - 1);
        Some(self.radiance[iy * self.pixels[0] + ix])
    }
}

fn srgb_to_linear(c: u8) -> f64 {
    let c = c as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Renders the scene: linear RGB radiance per pixel, row-major from the top row.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    sky: &Sky,
    textures: &[SensorTexture],
    s: &RenderSettings,
) -> Vec<DVec3> {
    render_with_progress(scene, camera, sky, textures, s, &())
}

/// [`render`], telling `progress` of every row finished.
pub fn render_with_progress(
    scene: &Scene,
    camera: &Camera,
    sky: &Sky,
    textures: &[SensorTexture],
    s: &RenderSettings,
    progress: &dyn Progress,
) -> Vec<DVec3> {
    render_rows(scene, camera, sky, textures, s, (0, s.spp), progress)
}

/// One sample per pixel of a progressive render (pass `pass` = 0, 1, ...): pixel
/// k of pass p draws from the stream (seed, p·width·height + k), so the passes
/// average to a render of as many samples. Linear RGB, row-major from the top.
pub fn render_pass(
    scene: &Scene,
    camera: &Camera,
    textures: &[SensorTexture],
    s: &RenderSettings,
    pass: u64,
) -> Vec<DVec3> {
    let first = pass * (s.width * s.height) as u64;
    render_rows(scene, camera, &scene.sky, textures, s, (first, 1), &())
}

/// The picture with `samples` per pixel, pixel k drawing from the stream
/// (seed, `first` + k).
fn render_rows(
    scene: &Scene,
    camera: &Camera,
    sky: &Sky,
    textures: &[SensorTexture],
    s: &RenderSettings,
    (first, samples): (u64, u32),
    progress: &dyn Progress,
) -> Vec<DVec3> {
    let frame = Frame::new(camera, s.width as f64 / s.height as f64);
    let mut image = vec![DVec3::ZERO; s.width * s.height];
    image
        .par_chunks_mut(s.width)
        .enumerate()
        .for_each(|(row, pixels)| {
            for (col, px) in pixels.iter_mut().enumerate() {
                let k = first + (row * s.width + col) as u64;
                let mut rng = PhotonRng::new(s.seed, k);
                let mut sum = DVec3::ZERO;
                for _ in 0..samples {
                    let u = (col as f64 + rng.uniform()) / s.width as f64;
                    let v = (row as f64 + rng.uniform()) / s.height as f64;
                    let (origin, dir) = frame.ray(u, v);
                    sum += radiance(scene, sky, textures, origin, dir, s.max_depth, &mut rng);
                }
                *px = sum / samples.max(1) as f64;
            }
            progress.advance(1);
        });
    image
}

/// A camera that shows the whole scene: from above the +x, +y side of its
/// bounding box, looking at its centre, with the box filling the view.
pub fn overview_camera(scene: &Scene) -> Camera {
    let (lo, hi) = scene
        .objects
        .iter()
        .map(|o| o.geometry.world_bounds())
        .filter(|(lo, hi)| lo.is_finite() && hi.is_finite())
        .fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(a, b), (lo, hi)| (a.min(lo), b.max(hi)),
        );
    let (centre, radius) = if lo.is_finite() && hi.is_finite() {
        (0.5 * (lo + hi), (0.5 * (hi - lo).length()).max(1.0))
    } else {
        (DVec3::ZERO, 100.0)
    };
    let vfov: f64 = 40.0;
    let distance = radius / (0.5 * vfov.to_radians()).sin();
    let dir = DVec3::new(1.0, 0.6, 0.8).normalize();
    Camera {
        look_from: centre + dir * distance,
        look_at: centre,
        up: DVec3::Y,
        vfov,
    }
}

/// Light arriving at `origin` from direction `-dir`.
fn radiance(
    scene: &Scene,
    sky: &Sky,
    textures: &[SensorTexture],
    mut origin: DVec3,
    mut dir: DVec3,
    max_depth: u32,
    rng: &mut PhotonRng,
) -> DVec3 {
    let mut throughput = DVec3::ONE;
    let mut start: Option<SurfaceHit> = None;
    for _ in 0..max_depth {
        let Some(hit) = intersect(scene, origin, dir, start.as_ref()) else {
            return throughput * sky.radiance(dir);
        };
        let object = &scene.objects[hit.object];
        let front = dir.dot(hit.geometric_normal) < 0.0;
        // An X-ray image glows on its sensor, on both faces: seen from behind
        // (looking past the detector towards the telescope and the Sun) it shows
        // mirrored, as through a translucent screen.
        if let Material::Sensor { .. } = object.material {
            if let Some(t) = textures.iter().find(|t| t.object == hit.object) {
                let local = object.transform.to_local.transform_point3(hit.point);
                if let Some(glow) = t.at(local) {
                    return throughput * glow;
                }
            }
        }
        // The shading normal on the side the ray comes from.
        let n = if dir.dot(hit.shading_normal) < 0.0 {
            hit.shading_normal
        } else {
            -hit.shading_normal
        };
        let next = match object.appearance {
            Appearance::Emitting { color } => return throughput * color,
            Appearance::Diffuse { color } => {
                throughput *= color;
                (n + unit_vector(rng)).try_normalize().unwrap_or(n)
            }
            Appearance::Metal { color, roughness } => {
                throughput *= color;
                let d = (reflect(dir, n) + in_unit_sphere(rng) * roughness)
                    .try_normalize()
                    .unwrap_or(n);
                // A blurred direction into the surface is mirrored back out, so the
                // metal reflects all of `color` (energy is conserved).
                if d.dot(n) < 0.0 {
                    reflect(d, n)
                } else {
                    d
                }
            }
            Appearance::Glass { ior } => {
                let eta = if front { 1.0 / ior } else { ior };
                let cos = (-dir.dot(n)).min(1.0);
                let sin = (1.0 - cos * cos).sqrt();
                let r0 = ((1.0 - eta) / (1.0 + eta)).powi(2);
                let schlick = r0 + (1.0 - r0) * (1.0 - cos).powi(5);
                if eta * sin > 1.0 || schlick > rng.uniform() {
                    reflect(dir, n)
                } else {
                    let perp = (dir + n * cos) * eta;
                    let par = -n * (1.0 - perp.length_squared()).abs().sqrt();
                    (perp + par).normalize()
                }
            }
        };
        origin = hit.point;
        dir = next;
        start = Some(hit);
    }
    DVec3::ZERO
}

/// Uniform on the unit sphere.
fn unit_vector(rng: &mut PhotonRng) -> DVec3 {
    let z = 2.0 * rng.uniform() - 1.0;
    let (s, c) = (std::f64::consts::TAU * rng.uniform()).sin_cos();
    let r = (1.0 - z * z).sqrt();
    DVec3::new(r * c, r * s, z)
}

/// Uniform in the unit ball.
fn in_unit_sphere(rng: &mut PhotonRng) -> DVec3 {
    unit_vector(rng) * rng.uniform().cbrt()
}

/// The PNG bytes' values: sRGB-encoded, clamped to [0, 1].
pub fn to_srgb8(c: DVec3) -> [u8; 3] {
    c.to_array().map(|v| {
        let v = v.clamp(0.0, 1.0);
        let e = if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (e * 255.0 + 0.5) as u8
    })
}
