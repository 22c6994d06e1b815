//! Shared by the commands that trace a scene several times and compare the
//! images (`focus`, `compare`): pick the sensor, trace, and measure its image.

use super::InputError;
use traxer::analysis::{analyse, ImageGeometry, ImageQuality};
use traxer::scene::Scene;
use traxer::trace::{self, RunConfig};

/// The run settings of one of several comparable traces: same seed, no progress
/// bar (the command prints a line per run instead).
pub fn run_config(photons: u64, seed: u64, threads: usize) -> Result<RunConfig, InputError> {
    if photons == 0 {
        return Err(InputError("--photons must be at least 1".into()));
    }
    Ok(RunConfig {
        photons,
        seed,
        threads,
        first_photon: 0,
    })
}

/// The sensor to measure: the one named, or the scene's only sensor.
pub fn pick_sensor(scene: &Scene, name: Option<&str>) -> Result<usize, InputError> {
    let names: Vec<&str> = scene.sensors.iter().map(|s| s.name.as_str()).collect();
    match name {
        Some(n) => names.iter().position(|s| *s == n).ok_or_else(|| {
            InputError(format!(
                "--sensor {n}: the scene has no sensor of that name (have: {names:?})"
            ))
        }),
        None => match names.len() {
            1 => Ok(0),
            0 => Err(InputError(format!(
                "{}: the scene has no sensor to measure",
                scene.path.display()
            ))),
            _ => Err(InputError(format!(
                "the scene has several sensors ({names:?}): choose one with --sensor"
            ))),
        },
    }
}

/// One traced run, measured on one sensor.
pub struct Measured {
    /// `None` when no flux reached the sensor.
    pub quality: Option<ImageQuality>,
    pub emitted: u64,
    /// Photons recorded on this sensor.
    pub on_sensor: u64,
    /// Tracing time (scene building excluded).
    pub seconds: f64,
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
) -> anyhow::Result<Measured> {
    let result = trace::run(scene, cfg)?;
    let spec = &scene.sensors[sensor];
    let image = &result.images[sensor];
    let quality = analyse(
        &image.flux_summed(spec),
        &ImageGeometry::of_sensor(spec),
        spec.focal_length,
    )
    .map(|(q, _)| q);
    Ok(Measured {
        quality,
        emitted: result.stats.photons_emitted,
        on_sensor: image.total_counts(),
        seconds: result.seconds,
    })
}
