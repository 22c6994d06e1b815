//! The PSF library: the telescope's image of a source at infinity over a grid of
//! energies, off-axis angles and azimuths, the form X-ray simulators read (one
//! image per grid point, see `output::psf`).
//!
//! Each point traces the scene's parallel beam tilted to (θ, φ) at one energy,
//! with the trace's own photon loop and random streams (photon i with (seed, i)),
//! so that a point equals `traxer trace` of the scene set to that angle and
//! energy; a window of the sensor's image around the image's centroid is kept.
//!
//! Data flow: front ends check a [`PsfGrid`], [`library`] traces point after point
//! (a stopped library resumes from the points it recorded) and `output::psf`
//! writes the FITS file, the npy stack and the JSON description.

use super::area_sweep::{check as check_sweep, first_repeat, AreaSweep, MAX_SWEEP_POINTS};
use super::parallel_beam::{beam, image_stays_on_the_sensor};
use super::{pick_sensor, StudyError};
use super::{PointOrigin, Sampling};
use crate::analysis::{analyse, ImageGeometry};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::scene::TABLE_THETA_MAX;
use crate::source::{ParallelBeam, Source, Spectrum};
use crate::trace::{run_part_with, trace_chunk_from, Flow, RunConfig, Tally, WithTables};
use crate::xray::ReflectivityTable;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// What to trace. Serialised, it is the library's identity (the keys its
/// record has always had).
#[derive(Clone, Debug, Serialize)]
pub struct PsfGrid {
    /// Energies (keV), increasing.
    #[serde(rename = "energies_kev")]
    pub energies: Vec<f64>,
    /// Off-axis angles (arcmin), each once.
    pub angles_arcmin: Vec<f64>,
    /// Azimuths of the tilt (degrees, from the beam frame's e1 towards e2, as
    /// the source's `off_axis_azimuth`), each once.
    pub azimuths_deg: Vec<f64>,
    /// Photons per point, seed, threads, and the sensor.
    #[serde(flatten)]
    pub sampling: Sampling,
    /// Pixels per side of each image's window.
    pub window: u32,
}

/// One grid point: where its window lies on the sensor and what it holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PsfImage {
    pub energy_kev: f64,
    pub angle_arcmin: f64,
    pub azimuth_deg: f64,
    /// The window's first pixel (ix, iy) on the sensor.
    pub corner: [u32; 2],
    /// The sensor's image in the window ([iy][ix], `window` × `window`): sums
    /// of photon weights, as the trace's `NAME.npy`.
    pub flux: Vec<f64>,
    /// The whole sensor's flux, and the photons recorded on it.
    pub sensor_flux: f64,
    pub photons_recorded: u64,
    /// The flux-weighted centroid on the sensor (local mm).
    pub centroid_mm: [f64; 2],
}

impl PsfImage {
    /// The window's share of the sensor's flux.
    pub fn enclosed(&self) -> f64 {
        self.flux.iter().sum::<f64>() / self.sensor_flux
    }
}

/// The library: its images in the order of [`points`], and the sensor's frame.
#[derive(Clone, Debug)]
pub struct PsfLibrary {
    pub sensor: String,
    pub window: u32,
    /// Sensor pixel pitch (mm) along x and y.
    pub pitch_mm: [f64; 2],
    /// The sensor's active area (mm) along x and y.
    pub size_mm: [f64; 2],
    pub focal_length_mm: f64,
    pub images: Vec<PsfImage>,
    pub seconds: f64,
    pub threads: usize,
}

/// The grid's points in the order they are traced and stored: angle, then
/// azimuth, then energy (the last varies fastest).
pub fn points(g: &PsfGrid) -> Vec<(f64, f64, f64)> {
    let mut out = Vec::new();
    for &a in &g.angles_arcmin {
        for &phi in &g.azimuths_deg {
            for &e in &g.energies {
                out.push((a, phi, e));
            }
        }
    }
    out
}

/// Checks the grid's numbers (front ends call it before loading the scene).
pub fn check(g: &PsfGrid) -> Result<(), StudyError> {
    check_sweep(&AreaSweep {
        energies: g.energies.clone(),
        angles_arcmin: g.angles_arcmin.clone(),
        sampling: Sampling {
            sensor: None,
            ..g.sampling.clone()
        },
        radius_mm: None,
    })?;
    let bad = |m: String| Err(StudyError::Input(m));
    // SIXTE's PSF and vignetting readers take θ ≥ 0 (the off-axis angle) and
    // φ for the side; a negative θ would be a point they never look up.
    if let Some(a) = g.angles_arcmin.iter().find(|a| **a < 0.0) {
        return bad(format!(
            "angles: {}′ is negative: a PSF library's off-axis angle θ is ≥ 0 (as SIXTE reads THETA), and the side is the azimuth: give --angles {} --azimuths with 180 added",
            crate::text::number(*a),
            crate::text::number(-*a)
        ));
    }
    if g.azimuths_deg.is_empty() || g.azimuths_deg.iter().any(|p| !p.is_finite()) {
        return bad("azimuths are angles in degrees".into());
    }
    if g.azimuths_deg.len() as u64 > MAX_SWEEP_POINTS {
        return bad(format!(
            "{} azimuths: at most {MAX_SWEEP_POINTS}",
            g.azimuths_deg.len()
        ));
    }
    if let Some(k) = first_repeat(&g.azimuths_deg) {
        return bad(format!(
            "azimuths: {}° is given twice (number {}); each azimuth once",
            g.azimuths_deg[k],
            k + 1
        ));
    }
    if !(1..=4096).contains(&g.window) {
        return bad(format!(
            "window = {} pixels: expected 1 to 4096 pixels per side",
            g.window
        ));
    }
    let n = points(g).len() as u64;
    let values = n.saturating_mul(g.window as u64 * g.window as u64);
    if n > MAX_SWEEP_POINTS || values > crate::sensor::MAX_TOTAL_PIXELS {
        return bad(format!(
            "{n} points of {w} × {w} pixels: more than the {} values a library may hold; use fewer points or a smaller window",
            crate::sensor::MAX_TOTAL_PIXELS,
            w = g.window
        ));
    }
    Ok(())
}

/// Traces the library. `replay`: the points a stopped library of the same
/// settings finished (taken instead of traced); `on_point` sees each finished
/// point; `progress` hears of every chunk of photons.
pub fn library(
    scene: &Scene,
    g: &PsfGrid,
    replay: &[PsfImage],
    progress: &dyn Progress,
    mut on_point: impl FnMut(&PsfImage, PointOrigin),
) -> Result<PsfLibrary, StudyError> {
    check(g)?;
    let base = beam(scene, "psf")?;
    let sensor = pick_sensor(scene, g.sampling.sensor.as_deref())?;
    let spec = &scene.sensors[sensor];
    let Some(f) = spec.focal_length else {
        return Err(StudyError::Input(format!(
            "sensor `{}` has no focal_length: a PSF library places each image at f · tan θ from the axis; give the sensor its focal_length (mm)",
            spec.name
        )));
    };
    if g.window > spec.pixels[0] || g.window > spec.pixels[1] {
        return Err(StudyError::Input(format!(
            "a window of {w} × {w} pixels does not fit on sensor `{}` ({} × {} pixels); use a smaller --window",
            spec.name,
            spec.pixels[0],
            spec.pixels[1],
            w = g.window
        )));
    }
    image_stays_on_the_sensor(scene, base, spec, &g.angles_arcmin)?;
    let mut threads = match g.sampling.threads {
        0 => rayon::current_num_threads(),
        n => n,
    };
    let start = Instant::now();
    let mut images: Vec<PsfImage> = Vec::new();
    for (k, (angle, azimuth, energy)) in points(g).into_iter().enumerate() {
        let same = |r: &&PsfImage| {
            [r.angle_arcmin, r.azimuth_deg, r.energy_kev].map(f64::to_bits)
                == [angle, azimuth, energy].map(f64::to_bits)
        };
        let recorded = replay.get(k).filter(same);
        let origin = match recorded {
            Some(_) => PointOrigin::Record,
            None => PointOrigin::Traced,
        };
        let image = match recorded {
            Some(r) => r.clone(),
            None => {
                let tilted = Source::Parallel(ParallelBeam::new(
                    base.aperture.clone(),
                    base.axis,
                    angle / 60.0,
                    azimuth,
                    Spectrum::Line(energy),
                ));
                let tables = tables_at(scene, energy)?;
                let (tally, used) = trace_point(scene, (&tilted, &tables), g, progress)?;
                threads = used;
                let flux = tally.images[sensor].flux_summed(spec);
                let counts = tally.images[sensor].total_counts();
                windowed(spec, &flux, counts, g.window, (angle, azimuth, energy))?
            }
        };
        on_point(&image, origin);
        images.push(image);
        if progress.stop_requested() && images.len() < points(g).len() {
            return Err(StudyError::Stopped);
        }
    }
    Ok(PsfLibrary {
        sensor: spec.name.clone(),
        window: g.window,
        pitch_mm: spec.pitch(),
        size_mm: spec.size,
        focal_length_mm: f,
        images,
        seconds: start.elapsed().as_secs_f64(),
        threads,
    })
}

/// The scene's reflectivity tables as the scene builds them for a source of
/// energy `energy` alone; refuses an energy a foil or a gas cannot describe.
fn tables_at(scene: &Scene, energy: f64) -> Result<Vec<ReflectivityTable>, StudyError> {
    let bad = |what: String, e: String| StudyError::Input(format!("{energy} keV: {what}: {e}"));
    for f in &scene.foils {
        f.attenuation_per_nm(energy)
            .map_err(|e| bad(format!("foil of {}", f.material.name), e.to_string()))?;
    }
    for s in &scene.sensors {
        if let Some(gas) = &s.gas {
            gas.attenuation_per_mm(energy)
                .map_err(|e| bad(format!("the gas of sensor `{}`", s.name), e.to_string()))?;
        }
    }
    scene
        .reflectivity
        .iter()
        .map(|t| {
            ReflectivityTable::cached(&t.coating, energy, energy, TABLE_THETA_MAX)
                .map_err(|e| bad(format!("coating `{}`", t.coating.name), e.to_string()))
        })
        .collect()
}

/// Traces one point's photons (photon i with the stream (seed, i), as a trace
/// of the scene set to that angle and energy) through the one photon driver
/// ([`crate::trace::run_part_with`]), with the point's beam and tables.
fn trace_point(
    scene: &Scene,
    (source, tables): (&Source, &[ReflectivityTable]),
    g: &PsfGrid,
    progress: &dyn Progress,
) -> Result<(Tally, usize), StudyError> {
    let cfg = RunConfig {
        threads: g.sampling.threads,
        ..RunConfig::new(g.sampling.photons, g.sampling.seed)
    };
    let sources = std::slice::from_ref(source);
    let chunk = |range, list_cap| {
        let att = &mut WithTables(tables);
        trace_chunk_from(scene, (sources, att), cfg.seed, range, list_cap, &mut ())
    };
    let (tally, threads) = run_part_with(
        scene,
        &cfg,
        Tally::new(scene),
        progress,
        &mut |_| Flow::Continue,
        &chunk,
    )?;
    Ok((tally, threads))
}

/// The window of `window` pixels around the image's centroid (moved inwards
/// where it would cross the sensor's edge), or a refusal when no photon
/// reached the sensor.
fn windowed(
    spec: &crate::sensor::SensorSpec,
    flux: &[f64],
    counts: u64,
    window: u32,
    (angle, azimuth, energy): (f64, f64, f64),
) -> Result<PsfImage, StudyError> {
    let Some((q, _)) = analyse(flux, &ImageGeometry::of_sensor(spec), spec.focal_length) else {
        return Err(StudyError::Input(format!(
            "no X-ray reached sensor `{}` at {energy} keV, {angle}′ off axis, azimuth {azimuth}°: there is no PSF to write; leave out that point",
            spec.name
        )));
    };
    let corner: [u32; 2] = std::array::from_fn(|k| {
        let centre_pixel = ((q.centroid_mm[k] / spec.size[k] + 0.5) * spec.pixels[k] as f64)
            .floor()
            .clamp(0.0, (spec.pixels[k] - 1) as f64) as u32;
        centre_pixel
            .saturating_sub(window / 2)
            .min(spec.pixels[k] - window)
    });
    let nx = spec.pixels[0] as usize;
    let w = window as usize;
    let mut out = Vec::with_capacity(w * w);
    for iy in corner[1] as usize..corner[1] as usize + w {
        let row = iy * nx + corner[0] as usize;
        out.extend_from_slice(&flux[row..row + w]);
    }
    Ok(PsfImage {
        energy_kev: energy,
        angle_arcmin: angle,
        azimuth_deg: azimuth,
        corner,
        flux: out,
        sensor_flux: flux.iter().sum(),
        photons_recorded: counts,
        centroid_mm: q.centroid_mm,
    })
}

impl super::StudyKind for PsfGrid {
    type Point = PsfImage;
    type Output = PsfLibrary;
    const NAME: &'static str = "psf";
    const POINTS: &'static str = "points";

    fn sampling(&self) -> &Sampling {
        &self.sampling
    }

    fn check(&self) -> Result<(), StudyError> {
        check(self)
    }

    fn photons_total(&self, _scene: &Scene) -> u64 {
        self.sampling
            .photons
            .saturating_mul(points(self).len() as u64)
    }

    fn run(
        &self,
        scene: &Scene,
        replay: &[PsfImage],
        progress: &dyn Progress,
        on_point: &mut dyn FnMut(&PsfImage, PointOrigin),
    ) -> Result<PsfLibrary, StudyError> {
        library(scene, self, replay, progress, on_point)
    }

    fn threads_used(output: &PsfLibrary) -> usize {
        output.threads
    }
}
