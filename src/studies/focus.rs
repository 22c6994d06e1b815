//! Focus scans: one scene variable (normally the sensor position) swept over a
//! range, the scene traced at each value with the same seed (the photons are the
//! same up to the sensor, so the curve is smooth), each image measured, and the
//! HPD, 80 % and 90 % diameters fitted with the defocus curve
//! (`analysis::focus::fit_defocus`). The HPD fit's z₀ is the best focus.

use super::{pick_sensor, trace_and_measure, StudyError};
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
    mut on_step: impl FnMut(&FocusStep, &str),
) -> Result<FocusScan, StudyError> {
    let values = sweep.values()?;
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
        let step = match recorded {
            Some(r) => r.clone(),
            None => {
                let m = trace_and_measure(&scene, sensor, cfg, progress)?;
                threads = m.threads;
                FocusStep {
                    value,
                    quality: m.quality,
                    on_sensor: m.on_sensor,
                }
            }
        };
        on_step(&step, &sensor_name);
        steps.push(step);
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
