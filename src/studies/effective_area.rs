//! The telescope's effective area A_eff(E, θ) and its off-axis image quality.
//!
//! A parallel beam (the scene's only source, of type `parallel`, whose aperture
//! must fill the telescope's entrance) is tilted to each off-axis angle. At each
//! angle N photons are traced once: the path a photon takes (reflections, figure
//! errors, which objects it meets) does not depend on its energy, only its weight
//! does. So the loop writes down each photon's reflections (coating table, grazing
//! angle) and foil passages (foil, cos θ) — [`Attenuation`] — and the weight at
//! every energy of the sweep is the product of R(E, θᵢ) and T(E, θⱼ) along that
//! path. This is exact (the same estimator as tracing each energy on its own, with
//! the same photons at every energy, so the curve is smooth) and costs one trace
//! per angle instead of one per energy and angle. Mirrors with roughness scatter
//! (`xray::roughness`) break the premise, as their scattering angles depend on
//! energy: a scene with them is traced once per energy and angle instead
//! ([`per_energy`]), with the same photons at every energy.
//!
//! A_eff(E) = A_beam · Σ w(E) / N, with A_beam the beam's cross-section through
//! the aperture and the sum over photons recorded on the sensor (or within a
//! radius of the image centre); its standard error is A_beam · s/√N with s the
//! standard deviation of the N per-photon contributions (zeros included).
//!
//! Data flow: the CLI loads the scene; [`sweep`] traces through
//! `trace::trace_photon`, measures with `analysis`, and returns an
//! [`AreaResult`] that `output::write_effective_area` writes.

pub use super::area_sweep::{check, AreaSweep, MAX_SWEEP_POINTS};
use super::parallel_beam::{beam, image_stays_on_the_sensor};
use super::{pick_sensor, PointOrigin, StudyError};
use crate::analysis::{analyse, ImageGeometry, ImageQuality};
use crate::history::PathClass;
use crate::progress::Progress;
use crate::random::PhotonRng;
use crate::scene::{Scene, TABLE_THETA_MAX};
use crate::source::{ParallelBeam, Photon};
use crate::trace::{map_chunks, trace_photon, Attenuation, Statistics};
use crate::xray::{AngleCell, EnergyCell, ReflectivityTable};
use rayon::prelude::*;
use std::time::Instant;

/// The area at one energy and angle.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AreaPoint {
    pub energy_kev: f64,
    pub area_cm2: f64,
    /// Standard error (Monte Carlo) of `area_cm2`.
    pub error_cm2: f64,
    /// The area by path class, in [`PathClass::ALL`] order.
    pub by_class_cm2: [f64; 5],
}

/// Everything at one off-axis angle.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AngleResult {
    pub off_axis_arcmin: f64,
    pub points: Vec<AreaPoint>,
    /// Image quality of the image weighted by the mean weight over the sweep's
    /// energies (a flat spectrum over them); `None` without flux.
    pub quality: Option<ImageQuality>,
    /// Photons recorded on the sensor, and within the radius.
    pub on_sensor: u64,
    pub counted: u64,
    /// Centre of the counting region (mm, sensor frame): the photons' centroid.
    pub centre_mm: [f64; 2],
    /// The area with every reflectivity and transmission 1 (geometry only).
    pub geometric_area_cm2: f64,
}

/// A finished sweep.
#[derive(Clone, Debug)]
pub struct AreaResult {
    pub sensor: String,
    /// The scene's name for people (its title), which names the optic in plots.
    pub optic: String,
    /// What the area counts, in words: X-rays reaching the sensor, or, on a gas
    /// detector, X-rays converting in its gas (the trace's rate on that sensor).
    pub counts: String,
    /// The beam's cross-section on axis (cm²).
    pub aperture_cm2: f64,
    /// The azimuth (degrees) the beam is tilted towards, the source's
    /// `off_axis_azimuth`.
    pub azimuth_deg: f64,
    pub angles: Vec<AngleResult>,
    pub seconds: f64,
    pub threads: usize,
}

/// A reflection or foil passage written down for later evaluation.
#[derive(Clone, Copy, Debug)]
enum Step {
    /// Reflectivity table index, grazing angle (rad).
    Mirror(u32, f64),
    /// Foil index, cos θ to the foil's normal.
    Foil(u32, f64),
}

/// The attenuation of the photon being traced, written down.
struct Recorder(Vec<Step>);

impl Attenuation for Recorder {
    fn mirror(&mut self, _: &Scene, table: usize, _: &mut Photon, theta: f64) {
        self.0.push(Step::Mirror(table as u32, theta));
    }

    fn foil(&mut self, _: &Scene, foil: usize, _: &mut Photon, cos: f64) {
        self.0.push(Step::Foil(foil as u32, cos));
    }
}

/// A photon recorded on the sensor: where, its class, and its steps
/// (`steps[start..end]` of the angle's step list).
struct Hit {
    pixel: u32,
    x: f64,
    y: f64,
    class: PathClass,
    start: u32,
    end: u32,
    /// The gas's conversion probability at the traced energy (1 without gas;
    /// with gas every energy is traced on its own, see [`per_energy_paths`]).
    conversion: f64,
}

/// The photons one angle's trace put on the sensor.
struct Hits {
    hits: Vec<Hit>,
    steps: Vec<Step>,
}

/// Traces the sweep. `progress` hears of every chunk of photons.
///
/// `replay`: the angles a stopped sweep of the same settings finished; they are
/// taken instead of traced (each angle depends only on the settings and the
/// seed). `on_angle` sees every finished angle.
pub fn sweep(
    scene: &Scene,
    s: &AreaSweep,
    replay: &[AngleResult],
    progress: &dyn Progress,
    mut on_angle: impl FnMut(&AngleResult, PointOrigin),
) -> Result<AreaResult, StudyError> {
    check(s)?;
    let base = beam(scene, "effective-area")?;
    let sensor = pick_sensor(scene, s.sampling.sensor.as_deref())?;
    let spec = &scene.sensors[sensor];
    if spec.energy_bins.is_some() {
        return Err(StudyError::Input(format!(
            "sensor `{}` has energy_bins: effective-area counts every energy of the sweep on the whole sensor; use a sensor without bins",
            spec.name
        )));
    }
    image_stays_on_the_sensor(scene, base, spec, &s.angles_arcmin)?;
    // Reflectivity over the sweep's energies, table for table as the scene's.
    let (e_min, e_max) = s
        .energies
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &e| (a.min(e), b.max(e)));
    let tables = scene
        .reflectivity
        .iter()
        .map(|t| ReflectivityTable::cached(&t.coating, e_min, e_max, TABLE_THETA_MAX))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| StudyError::Input(format!("energies: {e}")))?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(s.sampling.threads)
        .build()?;
    let start = Instant::now();
    let mut angles = Vec::new();
    for (i, &angle) in s.angles_arcmin.iter().enumerate() {
        let recorded = replay
            .get(i)
            .filter(|r| r.off_axis_arcmin.to_bits() == angle.to_bits() && i == angles.len());
        let origin = match recorded {
            Some(_) => PointOrigin::Record,
            None => PointOrigin::Traced,
        };
        let result = match recorded {
            Some(r) => r.clone(),
            None => {
                let beam = base.tilted(angle / 60.0);
                let result = pool.install(|| match per_energy_paths(scene, sensor) {
                    false => {
                        let hits = trace_angle(scene, &beam, sensor, s, None, progress);
                        let (result, image) = evaluate(scene, &tables, &beam, sensor, s, &hits);
                        finish(scene, sensor, result, &image)
                    }
                    true => per_energy(scene, &tables, &beam, sensor, s, progress),
                });
                AngleResult {
                    off_axis_arcmin: angle,
                    ..result
                }
            }
        };
        on_angle(&result, origin);
        angles.push(result);
        if progress.stop_requested() && angles.len() < s.angles_arcmin.len() {
            return Err(StudyError::Stopped);
        }
    }
    let counts = match &spec.gas {
        None => format!("X-rays reaching sensor `{}`", spec.name),
        Some(g) => format!(
            "X-rays converting in the gas of sensor `{}` ({} at {} mbar, {} mm): the area times the conversion probability, as a trace counts them",
            spec.name, g.material.name, g.desc.pressure_mbar, g.desc.drift_mm
        ),
    };
    Ok(AreaResult {
        sensor: spec.name.clone(),
        optic: scene.name_for_people(),
        counts,
        aperture_cm2: base.tilted(0.0).cross_section() / 100.0,
        azimuth_deg: base.off_axis_azimuth,
        angles,
        seconds: start.elapsed().as_secs_f64(),
        threads: pool.current_num_threads(),
    })
}

/// Traces one angle's photons (photon i with the stream (seed, i), whatever the
/// angle, so the angles share their random numbers) and keeps those on the sensor.
fn trace_angle(
    scene: &Scene,
    beam: &ParallelBeam,
    sensor: usize,
    s: &AreaSweep,
    energy: Option<f64>,
    progress: &dyn Progress,
) -> Hits {
    let chunks: Vec<Hits> = map_chunks(0, s.sampling.photons, progress, &|photons| {
        let mut stats = Statistics::new(scene.objects.len(), scene.sensors.len());
        let mut out = Hits {
            hits: Vec::new(),
            steps: Vec::new(),
        };
        let mut rec = Recorder(Vec::new());
        for i in photons {
            let mut rng = PhotonRng::new(s.sampling.seed, i);
            let mut photon = beam.emit(&mut rng);
            if let Some(e) = energy {
                photon.energy = e;
            }
            rec.0.clear();
            let traced = trace_photon(scene, photon, &mut rng, &mut stats, &mut (), &mut rec);
            if let Some((r, local, _)) = traced.filter(|t| t.0.sensor as usize == sensor) {
                let conversion = match &r.conversion {
                    Some(c) if c.entered > 0.0 => r.weight / c.entered,
                    Some(_) => 0.0,
                    None => 1.0,
                };
                let start = out.steps.len() as u32;
                out.steps.extend_from_slice(&rec.0);
                out.hits.push(Hit {
                    pixel: r.pixel,
                    x: local.x,
                    y: local.y,
                    class: r.history.class(),
                    start,
                    end: out.steps.len() as u32,
                    conversion,
                });
            }
        }
        out
    });
    // In chunk order, with step ranges moved to the joined list.
    let mut all = Hits {
        hits: Vec::new(),
        steps: Vec::new(),
    };
    for c in chunks {
        let offset = all.steps.len() as u32;
        all.steps.extend(c.steps);
        all.hits.extend(c.hits.into_iter().map(|h| Hit {
            start: h.start + offset,
            end: h.end + offset,
            ..h
        }));
    }
    all
}

/// Sums of one group of photons: per energy Σw, Σw², Σw per class; per pixel hit,
/// the sum of the photons' mean weights over the energies (ascending pixels, each
/// summed in photon order: added to the angle's image group by group, this gives
/// the same numbers as one whole image per group, without allocating one).
struct Sums {
    w: Vec<f64>,
    w2: Vec<f64>,
    class: Vec<[f64; 5]>,
    pixels: Vec<(u32, f64)>,
}

impl Sums {
    fn new(energies: usize) -> Sums {
        Sums {
            w: vec![0.0; energies],
            w2: vec![0.0; energies],
            class: vec![[0.0; 5]; energies],
            pixels: Vec::new(),
        }
    }

    /// Sets `pixels` from the group's (pixel, mean weight) in photon order.
    fn set_pixels(&mut self, mut hits: Vec<(u32, f64)>) {
        hits.sort_by_key(|&(pixel, _)| pixel); // stable: photon order per pixel
        self.pixels.clear();
        for (pixel, v) in hits {
            match self.pixels.last_mut() {
                Some(last) if last.0 == pixel => last.1 += v,
                _ => self.pixels.push((pixel, v)),
            }
        }
    }

    /// Adds another group's sums; its pixels go into `image`.
    fn add(&mut self, o: &Sums, image: &mut [f64]) {
        for k in 0..self.w.len() {
            self.w[k] += o.w[k];
            self.w2[k] += o.w2[k];
            for c in 0..5 {
                self.class[k][c] += o.class[k][c];
            }
        }
        for &(pixel, v) in &o.pixels {
            image[pixel as usize] += v;
        }
    }
}

/// A recorded step with its table cell located: what multiplies the weight.
#[derive(Clone, Copy)]
enum Factor {
    /// Reflectivity table index and the reflection's angle cell.
    Mirror(usize, AngleCell),
    /// Foil index, cos θ to the foil's normal.
    Foil(usize, f64),
}

/// The areas and the image of one angle from its recorded photons (the
/// result's `quality` is left for [`finish`], from the image).
fn evaluate(
    scene: &Scene,
    tables: &[ReflectivityTable],
    beam: &ParallelBeam,
    sensor: usize,
    s: &AreaSweep,
    hits: &Hits,
) -> (AngleResult, Vec<f64>) {
    let spec = &scene.sensors[sensor];
    let n_hits = hits.hits.len().max(1) as f64;
    let centre = hits.hits.iter().fold([0.0, 0.0], |c, h| {
        [c[0] + h.x / n_hits, c[1] + h.y / n_hits]
    });
    let inside = |h: &Hit| {
        s.radius_mm
            .is_none_or(|r| (h.x - centre[0]).hypot(h.y - centre[1]) <= r)
    };
    let n_e = s.energies.len();
    // Each table's cell of each energy, located once for the whole angle.
    let energy_cells: Vec<Vec<EnergyCell>> = tables
        .iter()
        .map(|t| s.energies.iter().map(|&e| t.energy_cell(e)).collect())
        .collect();
    // Fixed groups summed in order: the same result on any number of threads.
    let groups: Vec<Sums> = hits
        .hits
        .par_chunks(1024)
        .map(|group| {
            let mut sums = Sums::new(n_e);
            let mut pixels = Vec::with_capacity(group.len());
            let mut factors: Vec<Factor> = Vec::new();
            for h in group {
                // The image shows every photon; the areas count the region's.
                let counts = inside(h);
                factors.clear();
                factors.extend(
                    hits.steps[h.start as usize..h.end as usize]
                        .iter()
                        .map(|st| match *st {
                            Step::Mirror(t, theta) => {
                                Factor::Mirror(t as usize, tables[t as usize].angle_cell(theta))
                            }
                            Step::Foil(f, cos) => Factor::Foil(f as usize, cos),
                        }),
                );
                let mut mean = 0.0;
                for (k, &e) in s.energies.iter().enumerate() {
                    let w = factors.iter().fold(h.conversion, |w, f| match *f {
                        Factor::Mirror(t, ref angle) => {
                            w * tables[t].at(&energy_cells[t][k], angle)
                        }
                        Factor::Foil(f, cos) => w * scene.foils[f].transmission(e, cos),
                    });
                    if counts {
                        sums.w[k] += w;
                        sums.w2[k] += w * w;
                        sums.class[k][h.class as usize] += w;
                    }
                    mean += w;
                }
                pixels.push((h.pixel, mean / n_e as f64));
            }
            sums.set_pixels(pixels);
            sums
        })
        .collect();
    let mut total = Sums::new(n_e);
    let mut image = vec![0.0; spec.pixel_count()];
    for g in &groups {
        total.add(g, &mut image);
    }
    let n = s.sampling.photons as f64;
    let a_beam = beam.cross_section() / 100.0;
    let points = s
        .energies
        .iter()
        .enumerate()
        .map(|(k, &e)| {
            let mean = total.w[k] / n;
            let var = (total.w2[k] / n - mean * mean).max(0.0) * n / (n - 1.0);
            AreaPoint {
                energy_kev: e,
                area_cm2: a_beam * mean,
                error_cm2: a_beam * (var / n).sqrt(),
                by_class_cm2: total.class[k].map(|c| a_beam * c / n),
            }
        })
        .collect();
    let counted = hits.hits.iter().filter(|h| inside(h)).count();
    let result = AngleResult {
        off_axis_arcmin: 0.0,
        points,
        quality: None,
        on_sensor: hits.hits.len() as u64,
        counted: counted as u64,
        centre_mm: centre,
        geometric_area_cm2: a_beam * counted as f64 / n,
    };
    (result, image)
}

/// `result` with the image quality of `image` (the mean weight over the
/// sweep's energies per pixel).
fn finish(scene: &Scene, sensor: usize, result: AngleResult, image: &[f64]) -> AngleResult {
    let spec = &scene.sensors[sensor];
    let geometry = ImageGeometry::of_sensor(spec);
    AngleResult {
        quality: analyse(image, &geometry, spec.focal_length).map(|(q, _)| q),
        ..result
    }
}

/// Whether a mirror of the scene scatters from roughness: its photons' paths
/// then depend on their energy.
pub fn has_rough_mirrors(scene: &Scene) -> bool {
    scene.objects.iter().any(|o| {
        matches!(
            o.material,
            crate::material::Material::Mirror {
                roughness: Some(_),
                ..
            }
        )
    })
}

/// Whether a photon's path (or where it is recorded) depends on its energy, so
/// that each energy must be traced on its own: rough mirrors scatter each
/// energy its own way, and a gas detector converts each energy at its own depth
/// (where the photon is recorded, and whether within the sensor) with its own
/// probability.
pub fn per_energy_paths(scene: &Scene, sensor: usize) -> bool {
    has_rough_mirrors(scene) || scene.sensors[sensor].gas.is_some()
}

/// How many photons a sweep traces per off-axis angle (for progress bars):
/// `photons`, or `photons` at each energy with rough mirrors or a gas detector.
pub fn photons_per_angle(scene: &Scene, s: &AreaSweep) -> u64 {
    let sensor = pick_sensor(scene, s.sampling.sensor.as_deref()).unwrap_or(0);
    match scene.sensors.get(sensor).is_some() && per_energy_paths(scene, sensor) {
        false => s.sampling.photons,
        true => s.sampling.photons.saturating_mul(s.energies.len() as u64),
    }
}

/// One angle of a scene with rough mirrors or a gas detector: a rough mirror
/// scatters each energy its own way, and the gas converts each energy at its
/// own depth and rate, so one path per photon cannot serve every energy. Each
/// energy is traced on its own, photon i with the stream (seed, i) as at every
/// energy (the same photons, so the curve stays smooth), at the cost of one
/// trace per energy. The areas are each energy's (counted within the radius of
/// that energy's centroid); the image is the mean over the energies, as
/// without roughness; `on_sensor`, `counted` and the geometric area are the
/// means over the energies.
fn per_energy(
    scene: &Scene,
    tables: &[ReflectivityTable],
    beam: &ParallelBeam,
    sensor: usize,
    s: &AreaSweep,
    progress: &dyn Progress,
) -> AngleResult {
    let n_e = s.energies.len() as f64;
    let mut image = vec![0.0; scene.sensors[sensor].pixel_count()];
    let mut points = Vec::with_capacity(s.energies.len());
    let (mut on_sensor, mut counted, mut geometric, mut centre) = (0u64, 0u64, 0.0, [0.0; 2]);
    for &e in &s.energies {
        let one = AreaSweep {
            energies: vec![e],
            ..s.clone()
        };
        let hits = trace_angle(scene, beam, sensor, &one, Some(e), progress);
        let (r, img) = evaluate(scene, tables, beam, sensor, &one, &hits);
        image.iter_mut().zip(&img).for_each(|(a, b)| *a += b / n_e);
        points.extend(r.points);
        on_sensor += r.on_sensor;
        counted += r.counted;
        geometric += r.geometric_area_cm2 / n_e;
        centre = [
            centre[0] + r.centre_mm[0] / n_e,
            centre[1] + r.centre_mm[1] / n_e,
        ];
    }
    let result = AngleResult {
        off_axis_arcmin: 0.0,
        points,
        quality: None,
        on_sensor: (on_sensor as f64 / n_e).round() as u64,
        counted: (counted as f64 / n_e).round() as u64,
        centre_mm: centre,
        geometric_area_cm2: geometric,
    };
    finish(scene, sensor, result, &image)
}

impl super::StudyKind for AreaSweep {
    type Point = AngleResult;
    type Output = AreaResult;
    const NAME: &'static str = "effective_area";
    const POINTS: &'static str = "angles";

    fn sampling(&self) -> &super::Sampling {
        &self.sampling
    }

    fn check(&self) -> Result<(), StudyError> {
        check(self)
    }

    fn photons_total(&self, scene: &Scene) -> u64 {
        photons_per_angle(scene, self).saturating_mul(self.angles_arcmin.len() as u64)
    }

    fn run(
        &self,
        scene: &Scene,
        replay: &[AngleResult],
        progress: &dyn Progress,
        on_point: &mut dyn FnMut(&AngleResult, PointOrigin),
    ) -> Result<AreaResult, StudyError> {
        sweep(scene, self, replay, progress, on_point)
    }

    fn threads_used(output: &AreaResult) -> usize {
        output.threads
    }
}
