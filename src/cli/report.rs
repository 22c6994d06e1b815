//! What a finished trace says on stdout: its statistics and each sensor's image
//! quality (`trace`, `trace --resume`, `merge`).

use traxer::analysis::FinishedImage;
use traxer::trace::RunResult;

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
    for (spec, img) in scene.sensors.iter().zip(&result.images) {
        match scene.rate_per_unit_weight(s.photons_emitted) {
            Some(k) => say!(
                "  sensor {}: {} photons, {:.4e} axions/s",
                spec.name,
                img.total_counts(),
                img.total_flux() * k
            ),
            None => say!(
                "  sensor {}: {} photons, flux {:.6e}",
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
