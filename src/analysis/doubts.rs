//! Setups a run computes correctly but a person hardly meant, said after the
//! run: a sensor that sees the source past the optic (in front of it, say:
//! every photon unreflected, the "HPD" that of the beam's footprint), and
//! diameters whose circles reach beyond the sensor (they hold 50/80/90 % of
//! the flux that landed, not of the flux there was).
//!
//! Data flow: the CLI's trace report calls [`doubts`] for each sensor with its
//! [`FinishedImage`].

use super::FinishedImage;
use crate::history::PathClass;
use crate::sensor::{SensorImage, SensorSpec};

/// What is doubtful about sensor `spec`'s image, in words; `mirrors`: whether
/// the scene has any mirror.
pub fn doubts(
    spec: &SensorSpec,
    image: &SensorImage,
    finished: &FinishedImage,
    mirrors: bool,
) -> Vec<String> {
    let mut out = Vec::new();
    let recorded = image.total_counts();
    let direct = image.paths.class_counts[PathClass::Direct as usize];
    if mirrors && recorded > 0 && direct == recorded {
        out.push(format!(
            "sensor `{}`: none of the {recorded} photons it recorded was reflected by a mirror: it sees the source directly. Is it in front of the optic, or beside it? (The diameters are those of the beam's footprint.)",
            spec.name
        ));
    }
    if let Some(q) = finished.image_quality() {
        let g = &finished.geometry;
        let half = [
            0.5 * g.nx as f64 * g.pitch[0],
            0.5 * g.ny as f64 * g.pitch[1],
        ];
        let centre = [g.origin_mm[0] + half[0], g.origin_mm[1] + half[1]];
        let inside = |d: f64| {
            (0..2).all(|k| (q.centroid_mm[k] - centre[k]).abs() + 0.5 * d <= half[k] * (1.0 + 1e-9))
        };
        if let Some((name, d)) = [("80 %", q.d80_mm), ("90 %", q.d90_mm)]
            .into_iter()
            .find(|(_, d)| !inside(*d))
        {
            out.push(format!(
                "sensor `{}`: its {name} circle ({} mm across, about the centroid) reaches beyond the sensor's {} × {} mm: the diameters hold shares of the flux that landed on it, not of all the flux; a larger sensor gives the image's true diameters",
                spec.name,
                crate::text::number((d * 1e3).round() / 1e3),
                crate::text::number(2.0 * half[0]),
                crate::text::number(2.0 * half[1])
            ));
        }
    }
    out
}
