//! One traced run measured on one sensor: the sensor to measure, and its image
//! quality in mm or arcseconds.

use super::StudyError;
use crate::analysis::{FinishedImage, ImageQuality};
use crate::progress::Progress;
use crate::scene::Scene;
use crate::trace::{self, RunConfig};

/// The sensor to measure: the one named, or the scene's only sensor.
pub fn pick_sensor(scene: &Scene, name: Option<&str>) -> Result<usize, StudyError> {
    let names: Vec<&str> = scene.sensors.iter().map(|s| s.name.as_str()).collect();
    match name {
        Some(n) => names.iter().position(|s| *s == n).ok_or_else(|| {
            StudyError::Input(format!(
                "sensor `{n}`: the scene has no sensor of that name (have: {names:?})"
            ))
        }),
        None => match names.len() {
            1 => Ok(0),
            0 => Err(StudyError::Input(format!(
                "{}: the scene has no sensor to measure",
                scene.path.display()
            ))),
            _ => Err(StudyError::Input(format!(
                "the scene has several sensors ({names:?}): choose one by its name"
            ))),
        },
    }
}

/// One traced run, measured on one sensor.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Measured {
    /// `None` when no flux reached the sensor.
    pub quality: Option<ImageQuality>,
    pub emitted: u64,
    /// Photons recorded on this sensor.
    pub on_sensor: u64,
    /// Tracing time (scene building excluded).
    pub seconds: f64,
    /// Worker threads used.
    pub threads: usize,
}

impl Measured {
    pub fn photons_per_second(&self) -> f64 {
        self.emitted as f64 / self.seconds
    }
}

/// Traces `scene` and measures the image of sensor number `sensor`.
pub fn trace_and_measure(
    scene: &Scene,
    sensor: usize,
    cfg: &RunConfig,
    progress: &dyn Progress,
) -> Result<Measured, StudyError> {
    let result = trace::run_with_progress(scene, cfg, progress)?;
    let spec = &scene.sensors[sensor];
    let image = &result.images[sensor];
    let quality = FinishedImage::of(spec, image, None).quality.map(|(q, _)| q);
    Ok(Measured {
        quality,
        emitted: result.stats.photons_emitted,
        on_sensor: image.total_counts(),
        seconds: result.seconds,
        threads: result.threads,
    })
}

/// Measured (or wanted) diameters in arcseconds.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Diameters {
    pub hpd: f64,
    pub d80: f64,
    pub d90: f64,
}

impl Diameters {
    /// The diameters of an image in arcseconds (`None` without a focal length).
    pub fn of(q: &ImageQuality) -> Option<Diameters> {
        Some(Diameters {
            hpd: q.hpd_arcsec?,
            d80: q.d80_arcsec?,
            d90: q.d90_arcsec?,
        })
    }

    /// Sum of squared relative differences to `target`.
    pub fn error_to(&self, target: &Diameters) -> f64 {
        (self.hpd / target.hpd - 1.0).powi(2)
            + (self.d80 / target.d80 - 1.0).powi(2)
            + (self.d90 / target.d90 - 1.0).powi(2)
    }
}

/// Traces the scene as it is and measures sensor `sensor` in arcseconds (`None`
/// without flux or without a focal length).
pub fn measure_arcsec(
    scene: &Scene,
    sensor: usize,
    cfg: &RunConfig,
    progress: &dyn Progress,
) -> Result<Option<Diameters>, StudyError> {
    let q = trace_and_measure(scene, sensor, cfg, progress)?.quality;
    Ok(q.as_ref().and_then(Diameters::of))
}
