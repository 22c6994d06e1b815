//! What the parallel-beam studies (effective area, PSF library) ask of a
//! scene before they trace: its one source, a parallel beam, and off-axis
//! angles whose image stays on the sensor.

use super::StudyError;
use crate::scene::Scene;
use crate::sensor::SensorSpec;
use crate::source::{ParallelBeam, Source};

/// The beam of the scene, checked: the only source, parallel.
pub(super) fn beam<'a>(scene: &'a Scene, study: &str) -> Result<&'a ParallelBeam, StudyError> {
    match scene.sources.as_slice() {
        [Source::Parallel(b)] => Ok(b),
        _ => Err(StudyError::Input(format!(
            "{}: {study} needs exactly one source, of type \"parallel\", whose aperture covers the telescope's entrance (the beam is tilted to each off-axis angle)",
            scene.path.display()
        ))),
    }
}

/// Refuses off-axis angles whose image lands beyond the sensor's edge: f·tan θ
/// (f the sensor's `focal_length`) farther from the axis than half the sensor's
/// shorter side, for a sensor centred on the beam's axis. The area there would
/// count only the X-rays that stray onto the sensor, a plausible but wrong
/// small number.
pub(super) fn image_stays_on_the_sensor(
    scene: &Scene,
    beam: &ParallelBeam,
    spec: &SensorSpec,
    angles_arcmin: &[f64],
) -> Result<(), StudyError> {
    let Some(f) = spec.focal_length else {
        return Ok(());
    };
    // A sensor placed off the axis (to catch an off-axis image) is left alone.
    let centre = scene.objects[spec.object]
        .transform
        .to_world
        .transform_point3(glam::DVec3::ZERO);
    let from_axis = centre - beam.aperture.center;
    if from_axis.reject_from_normalized(beam.axis).length() > 1.0 {
        return Ok(());
    }
    let half = 0.5 * spec.size[0].min(spec.size[1]);
    for &a in angles_arcmin {
        let offset = f * (a / 60.0).to_radians().tan().abs();
        if offset > half {
            return Err(StudyError::Input(format!(
                "at {a}′ off axis the image lies {offset:.1} mm from the axis (f · tan θ with the sensor's focal_length {f} mm), beyond the edge of sensor `{}` ({half} mm from its centre): the area would count only what strays onto the sensor. Give a larger sensor or smaller --angles (up to {:.1}′)",
                spec.name,
                (half / f).atan().to_degrees() * 60.0
            )));
        }
    }
    Ok(())
}
