//! What a finished trace says on stdout: its statistics and each sensor's image
//! quality (`trace`, `trace --resume`, `merge`).

use traxer::analysis::FinishedImage;
use traxer::trace::RunResult;

/// Warnings on stderr (shown even with `-q`) for each sensor no photon
/// reached (its images are all zeros, which is rarely what was meant) and for
/// the doubts of `analysis::doubts` (a sensor that sees the source directly,
/// circles beyond the sensor's edge).
pub fn warn_about_sensors(scene: &traxer::scene::Scene, result: &RunResult) {
    let mirrors = scene.has_mirrors();
    let rate = scene.rate_per_unit_weight(result.stats.photons_emitted);
    for (spec, img) in scene.sensors.iter().zip(&result.images) {
        let finished = FinishedImage::of(spec, img, rate);
        for d in traxer::analysis::doubts(spec, img, &finished, mirrors) {
            tell!("warning: {d}");
        }
        if img.total_counts() == 0 {
            tell!(
                "warning: NO PHOTON reached sensor `{}` ({} photons traced): its images are empty. Check that the source points at the telescope (a sun's `direction` points towards the Sun, a beam's is its direction of travel) and where the sensor sits.",
                spec.name,
                result.stats.photons_emitted
            );
        }
    }
}

/// The run's statistics and each sensor's image quality on stdout.
pub fn report(scene: &traxer::scene::Scene, result: &RunResult) {
    let s = &result.stats;
    say!(
        "traced {} photons in {:.2} s with {} threads ({:.0} photons/s)",
        s.photons_emitted,
        result.seconds,
        result.threads,
        s.photons_emitted as f64 / result.seconds
    );
    say!(
        "  reached a sensor {} ({:.2} %), absorbed {}, mirror backs {}, below surface (figure error) {}, escaped {}, outside sensor area {}, max interactions {}",
        s.reached_sensor,
        100.0 * s.reached_sensor as f64 / s.photons_emitted as f64,
        s.absorbed, s.absorbed_mirror_back, s.scattered_below_surface, s.escaped, s.sensor_outside_area, s.max_interactions_reached
    );
    if let Some(m) = scene.converting_magnet() {
        say!("  magnet: {}", m.assumptions());
    }
    for (spec, img) in scene.sensors.iter().zip(&result.images) {
        match scene.rate_per_unit_weight(s.photons_emitted) {
            Some(k) => say!(
                "  sensor {}: {} photons, {:.4e} {}/s{}",
                spec.name,
                img.total_counts(),
                img.total_flux() * k,
                scene.counted().particles(),
                match scene.counted() {
                    traxer::scene::Counted::XRays => {
                        format!(
                            " ({:.4e} per hour of tracking)",
                            img.total_flux() * k * 3600.0
                        )
                    }
                    _ => String::new(),
                }
            ),
            None => say!(
                "  sensor {}: {} photons, flux {:.6e} ph (sum of photon weights)",
                spec.name,
                img.total_counts(),
                img.total_flux()
            ),
        }
        let finished = FinishedImage::of(spec, img, None);
        if let Some(q) = finished.image_quality() {
            let arc = |a: Option<f64>| a.map(|v| format!(" ({v:.1}″)")).unwrap_or_default();
            say!(
                "    centroid ({:.4}, {:.4}) mm; HPD {:.4} mm{}, 80 % {:.4} mm{}, 90 % {:.4} mm{}",
                q.centroid_mm[0],
                q.centroid_mm[1],
                q.hpd_mm,
                arc(q.hpd_arcsec),
                q.d80_mm,
                arc(q.d80_arcsec),
                q.d90_mm,
                arc(q.d90_arcsec)
            );
        }
    }
}
