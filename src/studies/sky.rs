//! Where the sky images on a sensor of a Sun scene, measured by tracing: the
//! helioprojective frame of `trace --fits` (FITS WCS `S`).
//!
//! A focusing telescope maps an offset on the sky to a position on its focal
//! plane; x = f·θ holds only for an ideal full telescope in a parallel beam.
//! The LLNL segments image an off-axis source at 92–96 % of f·θ, the bore and
//! the detector's gas change it again, the detector's turn rotates it, and the
//! on-axis image does not land at the sensor's centre. So the map is measured:
//! the scene's Sun is traced at its own offset and at ±`STEP_ARCMIN` along
//! each of the target frame's axes (e1, e2: the scene's `offset_arcmin`
//! axes), with the same photons each time (common random numbers, so the
//! differences are the shifts, not noise), and each image's centre is found
//! with `analysis::centre::windowed_centroid` (which the sensor's edge cannot
//! pull). The centre of the Sun's own image is where its centre images (the
//! emission is round); the central differences give the 2 × 2 Jacobian
//! ∂(x, y)/∂(θx, θy) in mm per arcsec — plate scale, rotation and any shear in
//! one matrix. Its statistical error is half the difference between the even
//! and the odd photon chunks' results.
//!
//! The calibration depends only on the scene (a fixed seed): a run, its shards
//! merged and a resumed run give the same header.
//!
//! Data flow: `run::write_results` calls [`calibrate`] when FITS is asked for;
//! `output::fits` turns the result into the WCS.

use crate::analysis::centre::windowed_centroid;
use crate::random::PhotonRng;
use crate::scene::Scene;
use crate::source::Source;
use crate::trace::{convert_in_magnet, map_chunks, trace_photon, AtItsEnergy, Statistics};

/// Photons traced at each of the five pointings.
pub const CALIBRATION_PHOTONS: u64 = 500_000;
/// The pointing step (arcmin): small against the Sun's 16′ radius, so the map
/// is linear over it, and large enough to move the image by many pixels.
pub const STEP_ARCMIN: f64 = 2.0;
/// The calibration's own seed: it depends on the scene, not on the run.
const SEED: u64 = 20_261_127;

/// Where the sky images on one sensor.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SkyCalibration {
    /// Where the Sun's centre images, sensor-local mm, and its 1σ error.
    pub centre_mm: [f64; 2],
    pub centre_error_mm: [f64; 2],
    /// ∂(x, y)/∂(θx, θy): mm per arcsec; row 0 is x, column 0 is θx (along e1,
    /// the scene's offset_arcmin[0]), with its 1σ errors.
    pub mm_per_arcsec: [[f64; 2]; 2],
    pub mm_per_arcsec_error: [[f64; 2]; 2],
    /// The Sun's offset in the scene (arcmin): the frame's origin.
    pub sun_offset_arcmin: [f64; 2],
    /// Sun–target distance, mm (for DSUN_OBS).
    pub sun_distance_mm: f64,
    pub step_arcmin: f64,
    pub photons_per_pointing: u64,
    /// The radius of the disk the image centres are taken in (mm).
    pub window_radius_mm: f64,
}

impl SkyCalibration {
    /// The mean plate scale √|det J|, mm per arcmin.
    pub fn plate_scale_mm_per_arcmin(&self) -> f64 {
        let j = self.mm_per_arcsec;
        (j[0][0] * j[1][1] - j[0][1] * j[1][0]).abs().sqrt() * 60.0
    }

    /// Its 1σ error, from the errors of J's entries (taken independent).
    pub fn plate_scale_error(&self) -> f64 {
        let (j, e) = (self.mm_per_arcsec, self.mm_per_arcsec_error);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let var = (j[1][1] * e[0][0]).powi(2)
            + (j[0][0] * e[1][1]).powi(2)
            + (j[1][0] * e[0][1]).powi(2)
            + (j[0][1] * e[1][0]).powi(2);
        // d√|det| = d|det| / (2√|det|).
        var.sqrt() / (2.0 * det.abs().sqrt()) * 60.0
    }

    /// The angle (degrees, counter-clockwise on the sensor) of the image of
    /// the sky's +θx direction.
    pub fn rotation_deg(&self) -> f64 {
        let j = self.mm_per_arcsec;
        j[1][0].atan2(j[0][0]).to_degrees()
    }
}

/// Measures where the sky images on sensor `sensor` of `scene`, whose only
/// source must be a Sun (`None` otherwise, or when too little reaches the
/// sensor to measure).
pub fn calibrate(scene: &Scene, sensor: usize) -> Option<SkyCalibration> {
    let [Source::Sun(sun)] = scene.sources.as_slice() else {
        return None;
    };
    let spec = scene.sensors.get(sensor)?;
    let window = 0.2 * spec.size[0].min(spec.size[1]);
    let [ox, oy] = sun.offset_arcmin;
    let d = STEP_ARCMIN;
    let pointings = [
        [ox, oy],
        [ox + d, oy],
        [ox - d, oy],
        [ox, oy + d],
        [ox, oy - d],
    ];
    // Per pointing: the centres of all photons, the even chunks' and the odd's.
    let mut centres = [[[0.0; 2]; 5]; 3];
    for (k, offset) in pointings.iter().enumerate() {
        let source = sun.with_offset(*offset);
        let chunks: Vec<Vec<(f64, f64, f64)>> =
            map_chunks(0, CALIBRATION_PHOTONS, &(), &|photons| {
                let mut stats = Statistics::new(scene.objects.len(), scene.sensors.len());
                let mut points = Vec::new();
                for i in photons {
                    let mut rng = PhotonRng::new(SEED, i);
                    let photon = source.emit(&mut rng);
                    let axion = ((photon.origin, photon.dir), photon.energy);
                    let traced = trace_photon(
                        scene,
                        photon,
                        &mut rng,
                        &mut stats,
                        &mut (),
                        &mut AtItsEnergy,
                    );
                    if let Some((mut r, local, _)) =
                        traced.filter(|t| t.0.sensor as usize == sensor)
                    {
                        if let Some(m) = scene.magnet.as_deref() {
                            convert_in_magnet(m, axion, &mut r, &mut Vec::new());
                        }
                        points.push((local.x, local.y, r.weight));
                    }
                }
                points
            });
        for (set, parity) in [None, Some(0), Some(1)].into_iter().enumerate() {
            let points: Vec<(f64, f64, f64)> = chunks
                .iter()
                .enumerate()
                .filter(|(c, _)| parity.is_none_or(|p| c % 2 == p))
                .flat_map(|(_, p)| p.iter().copied())
                .collect();
            centres[set][k] = windowed_centroid(&points, window)?;
        }
    }
    let jacobian = |c: &[[f64; 2]; 5]| {
        let per = 2.0 * d * 60.0;
        [
            [(c[1][0] - c[2][0]) / per, (c[3][0] - c[4][0]) / per],
            [(c[1][1] - c[2][1]) / per, (c[3][1] - c[4][1]) / per],
        ]
    };
    let (all, even, odd) = (
        jacobian(&centres[0]),
        jacobian(&centres[1]),
        jacobian(&centres[2]),
    );
    let half = |a: f64, b: f64| 0.5 * (a - b).abs();
    let j = all;
    if !(j[0][0] * j[1][1] - j[0][1] * j[1][0]).is_normal() {
        return None;
    }
    Some(SkyCalibration {
        centre_mm: centres[0][0],
        centre_error_mm: [0, 1].map(|a| half(centres[1][0][a], centres[2][0][a])),
        mm_per_arcsec: j,
        mm_per_arcsec_error: [0, 1].map(|r| [0, 1].map(|c| half(even[r][c], odd[r][c]))),
        sun_offset_arcmin: sun.offset_arcmin,
        sun_distance_mm: sun.distance_mm,
        step_arcmin: d,
        photons_per_pointing: CALIBRATION_PHOTONS,
        window_radius_mm: window,
    })
}
