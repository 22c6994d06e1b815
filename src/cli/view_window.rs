//! The live window of `traxer view`: a minifb software framebuffer (X11 or
//! Wayland, loaded at run time), the progressive path tracer
//! (`render::render_pass`), the X-ray feed in a background thread
//! (`trace::live::feed`), and the keys. Chosen over winit + softbuffer: minifb is made
//! for exactly this (a pixel buffer, keys and mouse, no GPU) and needs a tenth
//! of the code.

use super::args::SceneArgs;
use super::view::ViewArgs;
use super::view_controls::{labels, overlay, overlay_at, Controls, HELP};
use super::{load_scene, InputError};
use anyhow::Context;
use glam::DVec3;
use minifb::{Window, WindowOptions};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use traxer::analysis::FinishedImage;
use traxer::colormap::Scale;
use traxer::embree::Device;
use traxer::output::write_rgb_png;
use traxer::render::{
    overview_camera, part_labels, render_pass, to_srgb8, Camera, PartLabel, RenderSettings,
    SensorTexture,
};
use traxer::scene::Scene;
use traxer::trace::live::{feed, Published};
use traxer::trace::Tally;

/// Passes after which a still picture stops refining.
const MAX_PASSES: u64 = 1024;

/// The scene's cameras in order, the chosen one first; a view of the whole
/// scene if it has none.
fn cameras(a: &ViewArgs, scene: &Scene) -> Result<Vec<Camera>, InputError> {
    let mut list: Vec<(String, Camera)> =
        scene.cameras.iter().map(|(n, c)| (n.clone(), *c)).collect();
    if let Some(name) = &a.camera {
        let i = list.iter().position(|(n, _)| n == name).ok_or_else(|| {
            let known: Vec<&String> = scene.cameras.keys().collect();
            InputError(format!(
                "--camera {name}: no such camera in the scene (have: {known:?})"
            ))
        })?;
        list.rotate_left(i);
    }
    let mut cams: Vec<Camera> = list.into_iter().map(|(_, c)| c).collect();
    cams.push(overview_camera(scene));
    Ok(cams)
}

fn check(a: &ViewArgs) -> Result<(), InputError> {
    if a.width < 16 || a.height < 16 || a.width * a.height > 1 << 24 {
        return Err(InputError(
            "--width and --height: at least 16 pixels each, at most 2^24 in all".into(),
        ));
    }
    if a.max_depth == 0 || !(a.brightness.is_finite() && a.brightness >= 0.0) {
        return Err(InputError(
            "--max-depth must be at least 1 and --brightness a number ≥ 0".into(),
        ));
    }
    let display = |v: &str| std::env::var_os(v).is_some_and(|s| !s.is_empty());
    if !display("DISPLAY") && !display("WAYLAND_DISPLAY") {
        return Err(InputError(
            "no display to open a window on (neither DISPLAY nor WAYLAND_DISPLAY is set); for a picture without a window use `traxer render`, or run under a virtual X server (xvfb-run traxer view ...)".into(),
        ));
    }
    Ok(())
}

pub fn run(a: ViewArgs) -> anyhow::Result<()> {
    check(&a)?;
    let (device, scene) = load_scene(&a.scene)?;
    let cams = cameras(&a, &scene)?;
    let mut window = Window::new(
        &format!("traxer view: {}", a.scene.scene.display()),
        a.width,
        a.height,
        WindowOptions::default(),
    )
    .map_err(|e| InputError(format!("cannot open a window: {e}")))?;
    window.set_target_fps(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.sampling.threads)
        .build()
        .context("cannot start the worker threads")?;
    let stop = AtomicBool::new(false);
    let published = Mutex::new(Published::new(&scene));
    std::thread::scope(|s| {
        s.spawn(|| {
            feed(
                &scene,
                a.sampling.seed,
                a.photons,
                Duration::from_millis(500),
                &stop,
                &published,
            )
        });
        let result = window_loop(&a, &device, &scene, &cams, &mut window, &published, &pool);
        stop.store(true, Ordering::Relaxed);
        result
    })
}

/// What the window shows and has accumulated.
struct View<'a> {
    a: &'a ViewArgs,
    scene: &'a Scene,
    /// Renders run here (the window stays on its own thread).
    pool: &'a rayon::ThreadPool,
    sum: Vec<DVec3>,
    passes: u64,
    /// Frames rendered (also the seed offset of coarse frames).
    frames: u64,
    textures: Vec<SensorTexture>,
    version: u64,
    textures_at: Instant,
    title: String,
    /// Photons and image quality, drawn into the frame (ASCII: the 8×8 font).
    status: String,
    pixels: Vec<u32>,
    /// The part labels (L) and the camera they were found for.
    labels: Option<(Camera, Vec<PartLabel>)>,
}

impl View<'_> {
    fn settings(&self, scale: usize) -> RenderSettings {
        RenderSettings {
            width: (self.a.width / scale).max(1),
            height: (self.a.height / scale).max(1),
            spp: 1,
            max_depth: self.a.max_depth,
            seed: self.a.sampling.seed,
        }
    }

    /// One frame: a quarter-resolution picture while moving, else one more pass
    /// of the full one.
    fn render(&mut self, camera: &Camera, moving: bool) {
        let (w, h) = (self.a.width, self.a.height);
        if moving {
            let s = self.settings(4);
            let pass = 1_000_000 + self.frames;
            let small = self
                .pool
                .install(|| render_pass(self.scene, camera, &self.textures, &s, pass));
            for (k, p) in self.pixels.iter_mut().enumerate() {
                let (x, y) = ((k % w) * s.width / w, (k / w) * s.height / h);
                *p = pack(to_srgb8(small[y * s.width + x]));
            }
            self.sum.iter_mut().for_each(|v| *v = DVec3::ZERO);
            self.passes = 0;
        } else if self.passes < MAX_PASSES {
            let s = self.settings(1);
            let pass = self
                .pool
                .install(|| render_pass(self.scene, camera, &self.textures, &s, self.passes));
            self.passes += 1;
            let n = self.passes as f64;
            for ((acc, new), p) in self.sum.iter_mut().zip(pass).zip(&mut self.pixels) {
                *acc += new;
                *p = pack(to_srgb8(*acc / n));
            }
        } else {
            std::thread::sleep(Duration::from_millis(20));
        }
        self.frames += 1;
    }

    /// New sensor textures from the X-rays, at most every 2 s (each restarts the
    /// refinement); the title with photons and HPD.
    fn update_xrays(&mut self, published: &Mutex<Published>) {
        let Ok(p) = published.lock() else {
            return;
        };
        let due = self.version == 0 || self.textures_at.elapsed() > Duration::from_secs(2);
        if p.version == self.version || !(due || p.finished) {
            return;
        }
        self.version = p.version;
        self.textures_at = Instant::now();
        let scale = match self.a.log_decades {
            Some(decades) => Scale::Log { decades },
            None => Scale::Linear,
        };
        let mut quality = String::new();
        self.textures = self
            .scene
            .sensors
            .iter()
            .zip(&p.tally.images)
            .map(|(spec, img)| {
                let finished = FinishedImage::of(spec, img, None);
                let summed = finished.summed();
                if quality.is_empty() {
                    if let Some(q) = finished.image_quality() {
                        quality = match q.hpd_arcsec {
                            Some(v) => format!(", {}: HPD {v:.1} arcsec", spec.name),
                            None => format!(", {}: HPD {:.3} mm", spec.name, q.hpd_mm),
                        };
                    }
                }
                let px = [spec.pixels[0] as usize, spec.pixels[1] as usize];
                SensorTexture::viridis(spec.object, spec.size, px, summed, scale, self.a.brightness)
            })
            .collect();
        self.sum.iter_mut().for_each(|v| *v = DVec3::ZERO);
        self.passes = 0;
        self.status = format!("{} photons{quality}", p.tally.stats.photons_emitted);
        self.title = format!("traxer view: {}", self.status);
    }
}

impl View<'_> {
    /// The parts' names on the picture, found again only when the camera moved
    /// (one ray per pixel).
    fn draw_labels(&mut self, shown: &mut [u32], camera: &Camera) {
        let (w, h) = (self.a.width, self.a.height);
        if self.labels.as_ref().is_none_or(|(c, _)| c != camera) {
            let found = self.pool.install(|| part_labels(self.scene, camera, w, h));
            self.labels = Some((*camera, found));
        }
        let found: Vec<(&str, (usize, usize))> = self
            .labels
            .iter()
            .flat_map(|(_, l)| l)
            .map(|l| (l.text.as_str(), l.pixel))
            .collect();
        labels(shown, w, h, &found);
    }
}

fn pack([r, g, b]: [u8; 3]) -> u32 {
    (r as u32) << 16 | (g as u32) << 8 | b as u32
}

fn window_loop(
    a: &ViewArgs,
    device: &Device,
    scene: &Scene,
    cams: &[Camera],
    window: &mut Window,
    published: &Mutex<Published>,
    pool: &rayon::ThreadPool,
) -> anyhow::Result<()> {
    let (w, h) = (a.width, a.height);
    let mut v = View {
        a,
        scene,
        pool,
        sum: vec![DVec3::ZERO; w * h],
        passes: 0,
        frames: 0,
        textures: Vec::new(),
        version: 0,
        textures_at: Instant::now(),
        title: "traxer view: starting".into(),
        status: "starting".into(),
        pixels: vec![0; w * h],
        labels: None,
    };
    let started = Instant::now();
    let mut controls = Controls::new(window, &cams[0], a.show_help);
    let mut fps = 0.0;
    while window.is_open() {
        let keys = controls.poll(window, cams, h);
        if keys.quit {
            break;
        }
        v.update_xrays(published);
        let start = Instant::now();
        v.render(&controls.flight.camera(), controls.moving());
        fps = 0.8 * fps + 0.2 / start.elapsed().as_secs_f64().max(1e-3);
        let mut shown = v.pixels.clone();
        if controls.labels && !controls.moving() {
            v.draw_labels(&mut shown, &controls.flight.camera());
        }
        if controls.help {
            overlay(&mut shown, w, h, &HELP);
        }
        overlay_at(&mut shown, w, h, &[v.status.as_str()], true);
        window.set_title(&format!(
            "{} | {:.0} fps, {} spp | H: help",
            v.title, fps, v.passes
        ));
        window
            .update_with_buffer(&shown, w, h)
            .map_err(|e| anyhow::anyhow!("the window failed: {e}"))?;
        // A scripted run ends after its frames, once the X-rays are done (with
        // --photons) and the picture has refined since their last update.
        let scripted_end = a
            .frames
            .is_some_and(|n| v.frames >= n && v.passes >= n.min(32))
            && published
                .lock()
                .is_ok_and(|p| a.photons.is_none() || (p.finished && p.version == v.version));
        if keys.save || scripted_end {
            let tally = published.lock().map(|p| p.tally.clone()).ok();
            if let Some(t) = tally {
                save(
                    &a.save,
                    device,
                    &a.scene,
                    scene,
                    a.sampling.seed,
                    t,
                    &shown,
                    (w, h),
                )?;
            }
            if scripted_end {
                break;
            }
        }
    }
    let seconds = started.elapsed().as_secs_f64();
    say!(
        "{} frames in {seconds:.1} s ({:.1} frames/s at {w}×{h}; {} passes of the last picture)",
        v.frames,
        v.frames as f64 / seconds,
        v.passes
    );
    Ok(())
}

/// Saves the sensor images as `traxer trace` writes them (they are the trace of
/// the photons traced so far) and the frame as frame.png.
#[allow(clippy::too_many_arguments)]
fn save(
    dir: &Path,
    device: &Device,
    args: &SceneArgs,
    scene: &Scene,
    seed: u64,
    tally: Tally,
    frame: &[u32],
    (w, h): (usize, usize),
) -> anyhow::Result<()> {
    let mut png = image::RgbImage::new(w as u32, h as u32);
    for (p, c) in png.pixels_mut().zip(frame) {
        *p = image::Rgb([(c >> 16) as u8, (c >> 8) as u8, *c as u8]);
    }
    let frame_png = |dir: &Path| write_rgb_png(&dir.join("frame.png"), &png);
    let traced = traxer::run::save_traced(
        dir,
        scene,
        (device.info().version, &super::invocation()),
        (seed, tally),
        (&["frame.png"], frame_png),
    )?;
    say!(
        "saved the sensor images of {traced} photons and the frame into {} (scene {})",
        dir.display(),
        args.scene.display()
    );
    Ok(())
}
