//! Focus scans: one scene variable (normally the sensor position) swept over a
//! range, the scene traced at each value with the same seed (the photons are the
//! same up to the sensor, so the curve is smooth), each image measured, and the
//! HPD, 80 % and 90 % diameters fitted with the defocus curve
//! (`analysis::focus::fit_defocus`). The HPD fit's z₀ is the best focus.

use super::{pick_sensor, trace_and_measure, PointOrigin, StudyError};
use crate::analysis::focus::{fit_defocus, DefocusFit, DefocusFitError};
use crate::analysis::ImageQuality;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::trace::RunConfig;

/// The most positions a scan may have: each is a full trace, and their results
/// are kept (ten thousand is days of tracing already).
pub const MAX_STEPS: usize = 10_000;

/// What to sweep.
#[derive(Clone, Debug)]
pub struct FocusSweep {
    /// The scene variable (declared in `[vars]`).
    pub var: String,
    pub from: f64,
    pub to: f64,
    /// Number of values, evenly spaced, ends included (at least 4).
    pub steps: usize,
    /// The sensor to measure (default: the scene's only one).
    pub sensor: Option<String>,
}

impl FocusSweep {
    /// The swept values, or what is wrong with the sweep.
    pub fn values(&self) -> Result<Vec<f64>, StudyError> {
        if !(4..=MAX_STEPS).contains(&self.steps) {
            return Err(StudyError::Input(format!(
                "--steps must be 4 (to fit a focus curve) to {MAX_STEPS} (each is a whole trace)"
            )));
        }
        if !self.from.is_finite() || !self.to.is_finite() || self.from == self.to {
            return Err(StudyError::Input(
                "--from and --to must be two different numbers".into(),
            ));
        }
        Ok((0..self.steps)
            .map(|i| self.from + (self.to - self.from) * i as f64 / (self.steps - 1) as f64)
            .collect())
    }
}

/// The image at one value of the variable.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FocusStep {
    pub value: f64,
    /// `None` when no flux reached the sensor.
    pub quality: Option<ImageQuality>,
    pub on_sensor: u64,
}

/// A finished sweep.
#[derive(Clone, Debug)]
pub struct FocusScan {
    pub steps: Vec<FocusStep>,
    pub sensor: String,
    pub focal_length: Option<f64>,
    /// Fits of the HPD, 80 % and 90 % diameters (mm) against the variable.
    pub fits: [(&'static str, Result<DefocusFit, DefocusFitError>); 3],
    /// Values where fewer photons reached the sensor than elsewhere (the image
    /// is probably larger than the sensor there).
    pub clipped: Vec<f64>,
    /// Worker threads the traces used.
    pub threads: usize,
}

impl FocusScan {
    /// (value, diameter) points of one measure of the image.
    pub fn points(&self, diameter: Diameter) -> Vec<(f64, f64)> {
        self.steps
            .iter()
            .filter_map(|s| s.quality.as_ref().map(|q| (s.value, diameter(q))))
            .collect()
    }
}

/// One measure of an image: a diameter in mm.
pub type Diameter = fn(&ImageQuality) -> f64;

/// The three diameters fitted, with their labels.
pub const DIAMETERS: [(&str, Diameter); 3] = [
    ("HPD", |q| q.hpd_mm),
    ("80 %", |q| q.d80_mm),
    ("90 %", |q| q.d90_mm),
];

/// Traces the scene at every value of the sweep and fits the focus. `load` builds
/// the scene with the given extra `-D` definitions (the variable's value);
/// `on_step` sees each step as it is measured, with the sensor's name.
pub fn scan(
    mut load: impl FnMut(&[String]) -> Result<Scene, StudyError>,
    sweep: &FocusSweep,
    cfg: &RunConfig,
    replay: &[FocusStep],
    progress: &dyn Progress,
    mut on_step: impl FnMut(&FocusStep, &str, PointOrigin),
) -> Result<FocusScan, StudyError> {
    let values = sweep.values()?;
    let n_values = values.len();
    let mut steps = Vec::with_capacity(values.len());
    let (mut focal_length, mut sensor_name, mut threads) = (None, String::new(), 0);
    for (i, value) in values.into_iter().enumerate() {
        let scene = load(&[format!("{}={value}", sweep.var)])?;
        super::require_sources(&scene)?;
        let sensor = pick_sensor(&scene, sweep.sensor.as_deref())?;
        focal_length = scene.sensors[sensor].focal_length;
        sensor_name.clone_from(&scene.sensors[sensor].name);
        // A step recorded by a stopped scan of the same settings is taken as is:
        // it depends only on its value and the seed.
        let recorded = replay
            .get(i)
            .filter(|r| r.value.to_bits() == value.to_bits() && i == steps.len());
        let (step, origin) = match recorded {
            Some(r) => (r.clone(), PointOrigin::Record),
            None => {
                let m = trace_and_measure(&scene, sensor, cfg, progress)?;
                threads = m.threads;
                let step = FocusStep {
                    value,
                    quality: m.quality,
                    on_sensor: m.on_sensor,
                };
                (step, PointOrigin::Traced)
            }
        };
        on_step(&step, &sensor_name, origin);
        steps.push(step);
        if progress.stop_requested() && steps.len() < n_values {
            return Err(StudyError::Stopped);
        }
    }
    // A sensor too small for the defocused image cuts off its outer rings and
    // makes the diameters there meaningless.
    let most = steps.iter().map(|s| s.on_sensor).max().unwrap_or(0);
    let clipped = steps
        .iter()
        .filter(|s| (s.on_sensor as f64) < 0.995 * most as f64)
        .map(|s| s.value)
        .collect();
    let mut scan = FocusScan {
        steps,
        sensor: sensor_name,
        focal_length,
        fits: DIAMETERS.map(|(label, _)| (label, Err(DefocusFitError::TooFewPoints(0)))),
        clipped,
        threads,
    };
    for (k, (_, diameter)) in DIAMETERS.iter().enumerate() {
        scan.fits[k].1 = fit_defocus(&scan.points(*diameter));
    }
    Ok(scan)
}

/// The focus scan as the study job runs it: serialised, its identity (the
/// variable, its values, the sampling); each position's scene comes from
/// `load`, the front end's scene with the variable set.
#[derive(serde::Serialize)]
pub struct FocusStudy<'a> {
    pub var: String,
    pub values: Vec<f64>,
    #[serde(flatten)]
    pub sampling: super::Sampling,
    #[serde(skip)]
    pub sweep: FocusSweep,
    #[serde(skip)]
    pub cfg: RunConfig,
    #[serde(skip)]
    pub load: super::SceneLoader<'a>,
    /// The sensor of the last position traced (for its line).
    #[serde(skip)]
    sensor: std::sync::Mutex<String>,
}

impl<'a> FocusStudy<'a> {
    /// The scan of `sweep` with `cfg`'s photons, seed and threads.
    pub fn new(
        sweep: FocusSweep,
        cfg: RunConfig,
        load: super::SceneLoader<'a>,
    ) -> Result<FocusStudy<'a>, StudyError> {
        Ok(FocusStudy {
            var: sweep.var.clone(),
            values: sweep.values()?,
            sampling: super::Sampling {
                photons: cfg.photons,
                seed: cfg.seed,
                threads: cfg.threads,
                sensor: sweep.sensor.clone(),
            },
            sweep,
            cfg,
            load,
            sensor: Default::default(),
        })
    }
}

impl super::StudyKind for FocusStudy<'_> {
    type Point = FocusStep;
    type Output = FocusScan;
    const NAME: &'static str = "focus";
    const POINTS: &'static str = "positions";

    fn sampling(&self) -> &super::Sampling {
        &self.sampling
    }

    fn check(&self) -> Result<(), StudyError> {
        self.sweep.values().map(|_| ())
    }

    fn photons_total(&self, _scene: &Scene) -> u64 {
        self.cfg.photons.saturating_mul(self.values.len() as u64)
    }

    /// Loads the scene at each position (the scene given is the user's, for
    /// the identity and provenance).
    fn run(
        &self,
        _scene: &Scene,
        replay: &[FocusStep],
        progress: &dyn Progress,
        on_point: &mut dyn FnMut(&FocusStep, PointOrigin),
    ) -> Result<FocusScan, StudyError> {
        let load = |extra: &[String]| (self.load)(extra);
        scan(
            load,
            &self.sweep,
            &self.cfg,
            replay,
            progress,
            |step, sensor, origin| {
                sensor.clone_into(&mut self.sensor.lock().expect("not poisoned"));
                on_point(step, origin);
            },
        )
    }

    fn threads_used(output: &FocusScan) -> usize {
        output.threads
    }

    fn describe(&self, step: &FocusStep) -> Option<String> {
        let q = step.quality.as_ref();
        Some(format!(
            "{} = {:>10.3}: HPD {:>8.4} mm, 80 % {:>8.4} mm, 90 % {:>8.4} mm ({} photons on {})",
            self.var,
            step.value,
            q.map_or(f64::NAN, |q| q.hpd_mm),
            q.map_or(f64::NAN, |q| q.d80_mm),
            q.map_or(f64::NAN, |q| q.d90_mm),
            step.on_sensor,
            self.sensor.lock().expect("not poisoned")
        ))
    }
}
