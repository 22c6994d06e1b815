//! `traxer render`: a visible-light picture of a scene (see `traxer::render`),
//! optionally with X-ray sensor images glowing on their sensors.

use super::eef::read_npy;
use super::{load_scene, parse_define, InputError};
use anyhow::Context;
use glam::DVec3;
use std::path::{Path, PathBuf};
use traxer::files::atomic_write;
use traxer::render::{render, to_srgb8, Camera, RenderSettings, SensorTexture};
use traxer::scene::Scene;

/// Render a scene in visible light (path tracing) to a PNG.
///
/// The camera is the scene's [cameras.NAME] (--camera, or the only one), with
/// --look-from/--look-at/--up/--vfov overriding its fields; a scene without
/// cameras needs --look-from and --look-at. Objects look as their `appearance`
/// says (default: mirrors metallic, absorbers grey, sensors dark), lit by the
/// scene's [sky]. --sensor-image shows X-ray images on the sensors' faces: a trace's
/// output folder (NAME.npy for each sensor NAME) or one .npy for --sensor.
/// Example:
///   traxer render scenes/spheres.toml --width 600 --height 400 --spp 64 --out spheres.png
#[derive(clap::Args)]
pub struct RenderArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Output PNG.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Camera of the scene's [cameras] table.
    #[arg(long)]
    pub camera: Option<String>,
    /// Camera position x,y,z (mm).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub look_from: Option<DVec3>,
    /// Point the camera looks at, x,y,z (mm).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub look_at: Option<DVec3>,
    /// Up direction x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: Option<DVec3>,
    /// Vertical field of view (degrees).
    #[arg(long)]
    pub vfov: Option<f64>,
    #[arg(long, default_value_t = 800)]
    pub width: usize,
    #[arg(long, default_value_t = 450)]
    pub height: usize,
    /// Samples per pixel.
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Maximum bounces per path.
    #[arg(long, default_value_t = 12)]
    pub max_depth: u32,
    /// Random seed (the same seed gives the same picture for any --threads).
    #[arg(short, long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (0 = one per core).
    #[arg(short = 'j', long, default_value_t = 0, value_parser = super::parse_threads)]
    pub threads: usize,
    /// X-ray image(s) to show on the sensors: a trace output folder or a .npy.
    #[arg(long)]
    pub sensor_image: Option<PathBuf>,
    /// The sensor a single .npy belongs to (default: the scene's only sensor).
    #[arg(long)]
    pub sensor: Option<String>,
    /// Show sensor images on a log scale over this many decades.
    #[arg(long)]
    pub log_decades: Option<u32>,
    /// Radiance of the brightest sensor pixel (1 = as bright as a white sky).
    #[arg(long, default_value_t = 1.5)]
    pub brightness: f64,
    /// Override a scene variable: -D name=value (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<String>,
}

fn parse_vec3(s: &str) -> Result<DVec3, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected x,y,z numbers, got `{s}`"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(DVec3::new(x, y, z)),
        _ => Err(format!("expected three numbers x,y,z, got `{s}`")),
    }
}

/// The camera: the scene's (chosen or only one) with the command line's fields.
fn camera(a: &RenderArgs, scene: &Scene) -> Result<Camera, InputError> {
    let base = match &a.camera {
        Some(name) => Some(*scene.cameras.get(name).ok_or_else(|| {
            let known: Vec<&String> = scene.cameras.keys().collect();
            InputError(format!(
                "--camera {name}: no such camera in the scene (have: {known:?})"
            ))
        })?),
        None if scene.cameras.len() == 1 => scene.cameras.values().next().copied(),
        None if a.look_from.is_none() || a.look_at.is_none() => {
            let known: Vec<&String> = scene.cameras.keys().collect();
            return Err(InputError(if known.is_empty() {
                "the scene has no [cameras]: give --look-from x,y,z and --look-at x,y,z".into()
            } else {
                format!("the scene has several cameras: choose one with --camera (have: {known:?})")
            }));
        }
        None => None,
    };
    let c = Camera {
        look_from: a
            .look_from
            .or(base.map(|c| c.look_from))
            .unwrap_or(DVec3::Z),
        look_at: a.look_at.or(base.map(|c| c.look_at)).unwrap_or(DVec3::ZERO),
        up: a.up.or(base.map(|c| c.up)).unwrap_or(DVec3::Y),
        vfov: a.vfov.or(base.map(|c| c.vfov)).unwrap_or(40.0),
    };
    c.validate()
        .map_err(|m| InputError(format!("camera: {m}")))?;
    Ok(c)
}

/// Sensor textures from a trace folder (every sensor with a NAME.npy) or one .npy.
fn textures(a: &RenderArgs, scene: &Scene, path: &Path) -> Result<Vec<SensorTexture>, InputError> {
    let mut picks: Vec<(usize, PathBuf)> = Vec::new();
    if path.is_dir() {
        for (k, s) in scene.sensors.iter().enumerate() {
            let f = path.join(format!("{}.npy", traxer::output::file_stem(&s.name)));
            if f.is_file() {
                picks.push((k, f));
            }
        }
        if picks.is_empty() {
            return Err(InputError(format!(
                "--sensor-image {}: no NAME.npy for any sensor of the scene in that folder",
                path.display()
            )));
        }
    } else {
        let k = super::measure::pick_sensor(scene, a.sensor.as_deref())?;
        picks.push((k, path.to_path_buf()));
    }
    picks
        .into_iter()
        .map(|(k, f)| {
            let spec = &scene.sensors[k];
            let (shape, data) = read_npy(&f)?;
            let (nx, ny) = (spec.pixels[0] as usize, spec.pixels[1] as usize);
            // (ny, nx), or (bands, ny, nx): summed over the bands.
            let plane = ny * nx;
            let ok = match shape[..] {
                [y, x] => y as usize == ny && x as usize == nx,
                [_, y, x] => y as usize == ny && x as usize == nx,
                _ => false,
            };
            if !ok || data.is_empty() || data.len() % plane != 0 {
                return Err(InputError(format!(
                    "{}: shape {shape:?} does not match sensor `{}` ({ny} × {nx} pixels)",
                    f.display(),
                    spec.name
                )));
            }
            let mut summed = vec![0.0; plane];
            for chunk in data.chunks(plane) {
                for (s, v) in summed.iter_mut().zip(chunk) {
                    *s += v;
                }
            }
            Ok(SensorTexture::viridis(
                spec.object,
                spec.size,
                [nx, ny],
                &summed,
                a.log_decades,
                a.brightness,
            ))
        })
        .collect()
}

pub fn run(a: RenderArgs) -> anyhow::Result<()> {
    if a.width == 0 || a.height == 0 || a.width * a.height > 1 << 26 {
        return Err(InputError(
            "--width and --height must be positive (at most 2^26 pixels)".into(),
        )
        .into());
    }
    if a.spp == 0 || a.max_depth == 0 {
        return Err(InputError("--spp and --max-depth must be at least 1".into()).into());
    }
    if !(a.brightness.is_finite() && a.brightness >= 0.0) {
        return Err(InputError("--brightness must be a number ≥ 0".into()).into());
    }
    let (_device, scene) = load_scene(&a.scene, &a.define)?;
    let cam = camera(&a, &scene)?;
    let textures = match &a.sensor_image {
        Some(p) => textures(&a, &scene, p)?,
        None => Vec::new(),
    };
    let settings = RenderSettings {
        width: a.width,
        height: a.height,
        spp: a.spp,
        max_depth: a.max_depth,
        seed: a.seed,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads)
        .build()
        .context("cannot start the worker threads")?;
    let start = std::time::Instant::now();
    let image = pool.install(|| render(&scene, &cam, &scene.sky, &textures, &settings));
    let seconds = start.elapsed().as_secs_f64();
    let mut png = image::RgbImage::new(a.width as u32, a.height as u32);
    for (p, c) in png.pixels_mut().zip(&image) {
        *p = image::Rgb(to_srgb8(*c));
    }
    let mut bytes = Vec::new();
    png.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .context("cannot encode the PNG")?;
    atomic_write(&a.out, &bytes).with_context(|| format!("cannot write {}", a.out.display()))?;
    let rays = (a.width * a.height) as f64 * a.spp as f64;
    say!(
        "rendered {}×{} at {} spp in {:.2} s ({:.2} M camera rays/s, {} threads) → {}",
        a.width,
        a.height,
        a.spp,
        seconds,
        rays / seconds / 1e6,
        pool.current_num_threads(),
        a.out.display()
    );
    Ok(())
}
