//! The image's systematic uncertainty: the scene traced under each named
//! source of uncertainty (the mirror figure drawn from its fit's covariance,
//! the solar model, the pointing, the telescope's tilt, the detector gas, any
//! scene variable), every variation with the same photons (common random
//! numbers, so that a difference is the source's effect and not noise), and
//! each source's effect on the image quality, the flux and the image itself.
//!
//! Data flow: a front end loads the nominal scene and asks [`plan::plan`] for
//! the variations; [`run`] traces them one after another (each loaded through
//! the front end's `load` with its `-D` overrides; a stopped study resumes
//! from the variations it recorded) and [`summary`] turns them into each
//! source's standard deviation; `output::systematics` writes the files.

mod kind;
pub use kind::SystematicsStudy;
pub mod plan;
pub mod summary;

pub use plan::{plan, Kind, Plan, Request, SourcePlan, Variation, SOURCES};
pub use summary::{summarise, Effect, SourceEffect, Systematics, METRICS};

use super::fit::set_figure_error_where;
use super::{pick_sensor, Diameters, PointOrigin, StudyError};
use crate::analysis::FinishedImage;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::sensor::SensorSpec;
use crate::trace::{self, RunConfig};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The largest side of the maps the study keeps of each variation: a sensor
/// without a detector pixel grid is binned down to it.
pub const MAP_SIDE: usize = 256;

/// How every variation is traced and measured. Serialised, part of the
/// study's identity (the keys its record has always had).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Settings {
    /// Photons per variation, seed, threads, and the sensor.
    #[serde(flatten)]
    pub sampling: crate::studies::Sampling,
    /// The side (mm) of the central square whose flux the table gives,
    /// centred on the sensor's centre; with `central_circle`, the radius of a
    /// circle there instead (a signal region).
    pub central_mm: f64,
    pub central_circle: bool,
}

impl Settings {
    /// The central region in words, for tables and plots.
    pub fn central_words(&self) -> String {
        central_words(self.central_mm, self.central_circle)
    }
}

/// The central region (`size` mm: a square's side or a circle's radius) in
/// words.
pub fn central_words(size: f64, circle: bool) -> String {
    match circle {
        true => format!("circle of radius {size} mm"),
        false => format!("{size} × {size} mm square"),
    }
}

/// One traced variation, measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    pub source: String,
    pub label: String,
    /// The flux on the sensor (axions s⁻¹ with a Sun, else summed weights).
    pub flux: f64,
    /// The flux in the central square.
    pub central_flux: f64,
    pub photons_recorded: u64,
    /// HPD, 80 % and 90 % diameters (arcsec); `None` without flux or focal length.
    pub diameters: Option<Diameters>,
    /// The flux-weighted centroid (mm, sensor frame); `None` without flux.
    pub centroid_mm: Option<[f64; 2]>,
    /// The image on the study's map (see [`MapFrame`]), [iy][ix].
    pub map: Vec<f64>,
    /// The same from each half of the photons (the first and the second
    /// half of the streams), each scaled as a whole run's estimate: two
    /// independent estimates of `map`, whose σ maps differ by the Monte Carlo
    /// noise alone. Empty in records written before they were kept.
    #[serde(default)]
    pub halves: Vec<Vec<f64>>,
}

/// The frame of the maps: the sensor's detector pixel grid if it has one (the
/// readout a limit calculation bins in), else the sensor's image binned to at
/// most [`MAP_SIDE`] pixels a side.
#[derive(Clone, Debug, Serialize)]
pub struct MapFrame {
    /// Pixels along x and y.
    pub pixels: [usize; 2],
    /// The first pixel's centre and the pitch (mm), in the grid's frame
    /// (from its centre, along its axes) or the sensor's.
    pub first_mm: [f64; 2],
    pub step_mm: [f64; 2],
    /// The detector grid, if the map is on it.
    pub grid: Option<crate::sensor::PixelGrid>,
    /// Sensor pixels per map pixel along each side (1 on a grid: rebinned).
    pub binning: usize,
}

impl MapFrame {
    /// The frame for sensor `spec`.
    pub fn of(spec: &SensorSpec) -> MapFrame {
        if let Some(g) = spec.pixel_grid {
            let n = g.pixels.map(|n| n as usize);
            let p = g.pitch_mm;
            return MapFrame {
                pixels: n,
                first_mm: n.map(|n| -0.5 * n as f64 * p + 0.5 * p),
                step_mm: [p, p],
                grid: Some(g),
                binning: 1,
            };
        }
        let n = spec.pixels.map(|n| n as usize);
        let b = n[0].max(n[1]).div_ceil(MAP_SIDE).max(1);
        let pitch = spec.pitch();
        MapFrame {
            pixels: n.map(|n| n.div_ceil(b)),
            first_mm: std::array::from_fn(|k| -0.5 * spec.size[k] + 0.5 * b as f64 * pitch[k]),
            step_mm: pitch.map(|p| b as f64 * p),
            grid: None,
            binning: b,
        }
    }

    /// The map of a finished image.
    fn map(&self, spec: &SensorSpec, f: &FinishedImage) -> Vec<f64> {
        if let Some((_, r)) = f.on_grid(spec) {
            return r.flux;
        }
        let nx = spec.pixels[0] as usize;
        let mut out = vec![0.0; self.pixels[0] * self.pixels[1]];
        for (i, v) in f.summed().iter().enumerate() {
            let (ix, iy) = (i % nx / self.binning, i / nx / self.binning);
            out[iy * self.pixels[0] + ix] += v;
        }
        out
    }
}

/// The flux of `f` in the square of side `side` (mm) around the sensor's
/// centre: each pixel counted by the share of its area inside.
fn central_flux(f: &FinishedImage, side: f64, circle: bool) -> f64 {
    let g = &f.geometry;
    if circle {
        return crate::analysis::flux_within(f.summed(), g, [0.0, 0.0], &[side])[0];
    }
    let overlap = |k: usize, i: usize| {
        let a = g.origin_mm[k] + i as f64 * g.pitch[k];
        let b = a + g.pitch[k];
        ((b.min(0.5 * side) - a.max(-0.5 * side)) / g.pitch[k]).max(0.0)
    };
    let wx: Vec<f64> = (0..g.nx).map(|i| overlap(0, i)).collect();
    let mut sum = 0.0;
    for iy in 0..g.ny {
        let wy = overlap(1, iy);
        if wy > 0.0 {
            let row = &f.summed()[iy * g.nx..(iy + 1) * g.nx];
            sum += wy * row.iter().zip(&wx).map(|(v, w)| v * w).sum::<f64>();
        }
    }
    sum
}

/// Checks the settings (front ends call it before loading the scene).
pub fn check(s: &Settings) -> Result<(), StudyError> {
    if s.sampling.photons < 2 {
        return Err(StudyError::Input(
            "photons: at least 2 per variation (each is traced as two halves, for the Monte Carlo noise)".into(),
        ));
    }
    if !(s.central_mm.is_finite() && s.central_mm > 0.0) {
        return Err(StudyError::Input(format!(
            "central = {} mm: the central region's size must be a positive length",
            s.central_mm
        )));
    }
    Ok(())
}

/// Traces the plan's variations. `nominal`: the scene as loaded with the
/// study's own overrides (its figure draws are set on it in turn); `load`
/// loads the scene with extra `-D` overrides; `replay`: the variations a
/// stopped study of the same settings recorded.
pub fn run(
    nominal: &mut Scene,
    load: &dyn Fn(&[String]) -> Result<Scene, StudyError>,
    plan: &Plan,
    s: &Settings,
    replay: &[Outcome],
    progress: &dyn Progress,
    mut on_point: impl FnMut(&Outcome, PointOrigin),
) -> Result<Systematics, StudyError> {
    check(s)?;
    let sensor = pick_sensor(nominal, s.sampling.sensor.as_deref())?;
    let spec = nominal.sensors[sensor].clone();
    let frame = MapFrame::of(&spec);
    let cfg = RunConfig {
        threads: s.sampling.threads,
        ..RunConfig::new(s.sampling.photons, s.sampling.seed)
    };
    check_variations(load, plan, replay, &spec)?;
    let start = Instant::now();
    let nominal_figure = figure_of(nominal);
    let mut outcomes = Vec::new();
    let mut threads = 0;
    for (k, v) in plan.variations.iter().enumerate() {
        let recorded = replay
            .get(k)
            .filter(|o| o.source == v.source && o.label == v.label);
        let origin = match recorded {
            Some(_) => PointOrigin::Record,
            None => PointOrigin::Traced,
        };
        let outcome = match recorded {
            Some(o) => o.clone(),
            None => {
                let o = if let Some(f) = v.figure {
                    set_figure_error_where(nominal, nominal_figure, Some(f));
                    let o = measure(nominal, sensor, (&frame, s), &cfg, progress);
                    let drawn = Some(f).filter(|f| !f.is_perfect());
                    set_figure_error_where(nominal, drawn, nominal_figure);
                    o
                } else if v.defines.is_empty() {
                    measure(nominal, sensor, (&frame, s), &cfg, progress)
                } else {
                    let scene = load(&v.defines)?;
                    check_same_sensor(&scene, &spec, v)?;
                    measure(&scene, sensor, (&frame, s), &cfg, progress)
                };
                let (mut o, t) = o?;
                threads = t;
                o.source.clone_from(&v.source);
                o.label.clone_from(&v.label);
                o
            }
        };
        on_point(&outcome, origin);
        outcomes.push(outcome);
        if progress.stop_requested() && outcomes.len() < plan.variations.len() {
            return Err(StudyError::Stopped);
        }
    }
    Ok(summarise(
        plan,
        outcomes,
        frame,
        summary::RunFacts {
            sensor: spec.name.clone(),
            central_mm: s.central_mm,
            central_circle: s.central_circle,
            absolute: nominal.rate_per_unit_weight(s.sampling.photons).is_some(),
            counted: nominal.counted(),
            seconds: start.elapsed().as_secs_f64(),
            threads,
        },
    ))
}

/// Loads every variation's scene that is still to be traced (each set of
/// overrides once) before the first photon: a range end the scene refuses is
/// found now, not after hours of tracing with a record that can never be
/// resumed.
fn check_variations(
    load: &dyn Fn(&[String]) -> Result<Scene, StudyError>,
    plan: &Plan,
    replay: &[Outcome],
    spec: &SensorSpec,
) -> Result<(), StudyError> {
    let mut checked: Vec<&[String]> = Vec::new();
    for (k, v) in plan.variations.iter().enumerate() {
        let recorded = replay
            .get(k)
            .is_some_and(|o| o.source == v.source && o.label == v.label);
        if recorded || v.defines.is_empty() || checked.contains(&v.defines.as_slice()) {
            continue;
        }
        let scene = load(&v.defines).map_err(|e| {
            StudyError::Input(format!(
                "{} ({}): the scene refuses this variation, so nothing was traced: {e}",
                v.source,
                v.defines.join(" ")
            ))
        })?;
        check_same_sensor(&scene, spec, v)?;
        checked.push(&v.defines);
    }
    Ok(())
}

/// The figure error the scene's mirrors have (the first mirror's).
fn figure_of(scene: &Scene) -> Option<crate::xray::FigureError> {
    scene.objects.iter().find_map(|o| match &o.material {
        crate::material::Material::Mirror { figure_error, .. } => Some(*figure_error),
        _ => None,
    })?
}

/// A variation must image on the nominal scene's sensor.
fn check_same_sensor(scene: &Scene, spec: &SensorSpec, v: &Variation) -> Result<(), StudyError> {
    let same = scene.sensors.iter().any(|o| {
        o.name == spec.name
            && o.pixels == spec.pixels
            && o.size == spec.size
            && o.pixel_grid == spec.pixel_grid
    });
    if same {
        return Ok(());
    }
    Err(StudyError::Input(format!(
        "{} ({}) changes sensor `{}`'s pixels or size: the variations' images must lie on the same pixels",
        v.source,
        v.defines.join(" "),
        spec.name
    )))
}

/// Traces `scene` and measures sensor `sensor`; returns the outcome (source
/// and label to fill in) and the worker threads.
fn measure(
    scene: &Scene,
    sensor: usize,
    (frame, s): (&MapFrame, &Settings),
    cfg: &RunConfig,
    progress: &dyn Progress,
) -> Result<(Outcome, usize), StudyError> {
    // Two halves of the photons, traced apart and added exactly: the whole
    // image is the one run's to the bit, and each half is an independent
    // estimate for the Monte Carlo noise of the σ maps.
    let first = cfg.photons / 2;
    let parts = [
        (cfg.first_photon, first),
        (cfg.first_photon + first, cfg.photons - first),
    ];
    let mut halves = Vec::with_capacity(2);
    let mut images = Vec::with_capacity(2);
    let mut threads = 0;
    for (start, photons) in parts {
        let part = RunConfig {
            photons,
            first_photon: start,
            ..cfg.clone()
        };
        let result = trace::run_with_progress(scene, &part, progress)?;
        threads = result.threads;
        images.push(result.images.into_iter().nth(sensor).expect("the sensor"));
    }
    let spec = &scene.sensors[sensor];
    for (image, (_, photons)) in images.iter().zip(parts) {
        // Scaled as an estimate of the whole run's image: axions per second
        // with a Sun, else the weights times (all photons / these photons).
        let rate = scene
            .rate_per_unit_weight(photons)
            .or(Some(cfg.photons as f64 / photons as f64));
        let f = FinishedImage::of(spec, image, rate);
        halves.push(frame.map(spec, &f));
    }
    let mut whole = images.swap_remove(0);
    whole.add(&images[0]);
    let image = &whole;
    let f = FinishedImage::of(spec, image, scene.rate_per_unit_weight(cfg.photons));
    let q = f.image_quality();
    Ok((
        Outcome {
            source: String::new(),
            label: String::new(),
            flux: f.total_flux(),
            central_flux: central_flux(&f, s.central_mm, s.central_circle),
            photons_recorded: image.total_counts(),
            diameters: q.and_then(Diameters::of),
            centroid_mm: q.map(|q| q.centroid_mm),
            map: frame.map(spec, &f),
            halves,
        },
        threads,
    ))
}
