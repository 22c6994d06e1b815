//! `traxer render`: a visible-light picture of a scene (see `traxer::render`),
//! optionally with X-ray sensor images glowing on their sensors.

use super::args::{QuietArg, SamplingArgs, SceneArgs};
use super::{load_scene, progress, InputError};
use anyhow::Context;
use glam::DVec3;
use serde_json::json;
use std::path::{Path, PathBuf};
use traxer::files::check_output_file;
use traxer::output::{
    draw_labels, read_image, sidecar_path, write_rgb_png, write_sidecar, Provenance, Scale,
};
use traxer::render::{
    part_labels, render_with_progress, to_srgb8, Camera, RenderSettings, SensorTexture,
};
use traxer::scene::Scene;
use traxer::studies::pick_sensor;

/// Render a scene in visible light (path tracing) to a PNG.
///
/// The camera is the scene's [cameras.NAME] (--camera, or the only one), with
/// --look-from/--look-at/--up/--vfov overriding its fields; a scene without
/// cameras needs --look-from and --look-at. Objects look as their `appearance`
/// says (default: mirrors metallic, absorbers grey, sensors dark), lit by the
/// scene's [sky]. --sensor-image shows X-ray images on the sensors' faces: a trace's
/// output folder (NAME.npy for each sensor NAME) or one .npy for --sensor.
/// Writes the PNG and, next to it, OUT.json with the provenance and settings.
/// Example:
///   traxer render scenes/spheres.toml --width 600 --height 400 --spp 64 --out spheres.png
#[derive(clap::Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Output PNG.
    #[arg(value_name = "PNG", short, long)]
    pub out: PathBuf,
    /// Camera of the scene's [cameras] table.
    #[arg(value_name = "NAME", long)]
    pub camera: Option<String>,
    /// Camera position x,y,z (mm).
    #[arg(value_name = "X,Y,Z", long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub look_from: Option<DVec3>,
    /// Point the camera looks at, x,y,z (mm).
    #[arg(value_name = "X,Y,Z", long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub look_at: Option<DVec3>,
    /// Up direction x,y,z.
    #[arg(value_name = "X,Y,Z", long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub up: Option<DVec3>,
    /// Vertical field of view (degrees).
    #[arg(value_name = "DEG", long)]
    pub vfov: Option<f64>,
    #[arg(value_name = "PX", long, default_value_t = 800)]
    pub width: usize,
    #[arg(value_name = "PX", long, default_value_t = 450)]
    pub height: usize,
    /// Samples per pixel.
    #[arg(value_name = "N", long, default_value_t = 64)]
    pub spp: u32,
    /// Maximum bounces per path.
    #[arg(value_name = "N", long, default_value_t = 12)]
    pub max_depth: u32,
    #[command(flatten)]
    pub sampling: SamplingArgs,
    /// X-ray image(s) to show on the sensors: a trace output folder or a .npy.
    #[arg(value_name = "DIR|NPY", long)]
    pub sensor_image: Option<PathBuf>,
    /// The sensor a single .npy belongs to (default: the scene's only sensor).
    #[arg(value_name = "NAME", long)]
    pub sensor: Option<String>,
    /// Show sensor images on a log scale over this many decades.
    #[arg(value_name = "N", long)]
    pub log_decades: Option<u32>,
    /// Radiance of the brightest sensor pixel (1 = as bright as a white sky).
    #[arg(value_name = "B", long, default_value_t = 1.5)]
    pub brightness: f64,
    /// Name the parts of the scene on the picture (the objects, a telescope as
    /// one part, the Sun): a dot on each part seen in at least 0.02 % of the
    /// pixels, its name beside it.
    #[arg(long)]
    pub labels: bool,
    #[command(flatten)]
    pub quiet: QuietArg,
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
        let k = pick_sensor(scene, a.sensor.as_deref()).map_err(|e| InputError(e.to_string()))?;
        picks.push((k, path.to_path_buf()));
    }
    let scale = match a.log_decades {
        Some(decades) => Scale::Log { decades },
        None => Scale::Linear,
    };
    picks
        .into_iter()
        .map(|(k, f)| {
            let spec = &scene.sensors[k];
            let img = read_image(&f).map_err(|e| InputError(e.to_string()))?;
            let (nx, ny) = (spec.pixels[0] as usize, spec.pixels[1] as usize);
            if (img.ny, img.nx) != (ny, nx) || img.summed.is_empty() {
                return Err(InputError(format!(
                    "{}: shape {:?} does not match sensor `{}` ({ny} × {nx} pixels)",
                    f.display(),
                    img.shape,
                    spec.name
                )));
            }
            Ok(SensorTexture::viridis(
                spec.object,
                spec.size,
                [nx, ny],
                &img.summed,
                scale,
                a.brightness,
            ))
        })
        .collect()
}

pub fn run(a: RenderArgs) -> anyhow::Result<()> {
    check_settings(&a)?;
    check_output_file(&a.out)?;
    check_output_file(&sidecar_path(&a.out))?;
    let (device, scene) = load_scene(&a.scene)?;
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
        seed: a.sampling.seed,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.sampling.threads)
        .build()
        .context("cannot start the worker threads")?;
    let bar = progress::bar(a.height as u64, "rows", a.quiet.quiet);
    let start = std::time::Instant::now();
    let image = pool.install(|| {
        render_with_progress(&scene, &cam, &scene.sky, &textures, &settings, &|n| {
            bar.inc(n)
        })
    });
    let seconds = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let png = picture(&a, &scene, &cam, &image);
    write_rgb_png(&a.out, &png).with_context(|| format!("cannot write {}", a.out.display()))?;
    let threads = pool.current_num_threads();
    let provenance = Provenance::of_picture(
        &super::invocation(),
        device.info().version,
        &scene,
        a.sampling.seed,
        threads,
    );
    write_sidecar(&a.out, &provenance, details(&a, &cam, seconds))
        .with_context(|| format!("cannot write the sidecar of {}", a.out.display()))?;
    if !a.quiet.quiet {
        let rays = (a.width * a.height) as f64 * a.spp as f64;
        say!(
            "rendered {}×{} at {} spp in {:.2} s ({:.2} M camera rays/s, {} threads) → {} (settings and provenance beside it: {})",
            a.width,
            a.height,
            a.spp,
            seconds,
            rays / seconds / 1e6,
            threads,
            a.out.display(),
            sidecar_path(&a.out).display()
        );
    }
    Ok(())
}

/// The rendered radiance as an sRGB picture, with the parts' names on it if asked.
fn picture(a: &RenderArgs, scene: &Scene, cam: &Camera, image: &[DVec3]) -> image::RgbImage {
    let mut png = image::RgbImage::new(a.width as u32, a.height as u32);
    for (p, c) in png.pixels_mut().zip(image) {
        *p = image::Rgb(to_srgb8(*c));
    }
    if a.labels {
        let labels = part_labels(scene, cam, a.width, a.height);
        let texts: Vec<(&str, (usize, usize))> =
            labels.iter().map(|l| (l.text.as_str(), l.pixel)).collect();
        let left_out = draw_labels(&mut png, &texts);
        if !left_out.is_empty() {
            tell!(
                "note: {} of {} labels found no free place in the picture and were left out: {} (a larger --width/--height, or a camera nearer the parts, makes room)",
                left_out.len(),
                texts.len(),
                traxer::text::shorten(&left_out.join(", "), 300)
            );
        }
    }
    png
}

/// The image size, samples, depth and brightness checked.
fn check_settings(a: &RenderArgs) -> Result<(), InputError> {
    if a.width == 0 || a.height == 0 || a.width * a.height > 1 << 26 {
        return Err(InputError(
            "--width and --height must be positive (at most 2^26 pixels)".into(),
        ));
    }
    if a.spp == 0 || a.max_depth == 0 {
        return Err(InputError(
            "--spp and --max-depth must be at least 1".into(),
        ));
    }
    if !(a.brightness.is_finite() && a.brightness >= 0.0) {
        return Err(InputError("--brightness must be a number ≥ 0".into()));
    }
    Ok(())
}

/// The render's settings for its sidecar.
fn details(a: &RenderArgs, cam: &traxer::render::Camera, seconds: f64) -> serde_json::Value {
    json!({
        "camera": {
            "look_from": cam.look_from.to_array(),
            "look_at": cam.look_at.to_array(),
            "up": cam.up.to_array(),
            "vfov": cam.vfov,
        },
        "width": a.width,
        "height": a.height,
        "samples_per_pixel": a.spp,
        "max_depth": a.max_depth,
        "sensor_image": a.sensor_image.as_ref().map(|p| p.display().to_string()),
        "labels": a.labels,
        "seconds": seconds,
    })
}
