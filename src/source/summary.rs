//! The sources as a run's summary.json describes them: each source's kind,
//! geometry, spectrum and what one photon's weight means; for the Sun its
//! emission, couplings, rates and magnet. Beside the sources so that a new
//! field is described where it is added; `output` writes it.

use super::{AnnulusSector, Source};
use serde_json::{json, Value};

/// The sources as `summary.json` describes them, for a run of `photons`; a
/// Sun with the scene's `magnet` (its rate per unit weight in X-rays).
pub fn sources_json(
    sources: &[Source],
    photons: u64,
    magnet: Option<&crate::magnet::Magnet>,
) -> Value {
    Value::Array(
        sources
            .iter()
            .map(|s| match s {
                Source::Parallel(p) => json!({
                    "type": "parallel",
                    "aperture": sector_json(&p.aperture),
                    "direction": p.direction.to_array(),
                    "spectrum_keV": p.spectrum,
                    "weight": s.describe_weight(false),
                }),
                Source::Point(p) => json!({
                    "type": "point",
                    "position_mm": p.position.to_array(),
                    "radius_mm": p.radius,
                    "target": sector_json(&p.target),
                    "spectrum_keV": p.spectrum,
                    "weight": s.describe_weight(false),
                }),
                Source::Sun(sun) => json!({
                    "type": "sun",
                    "emission": sun.emission,
                    "coupling": sun.coupling,
                    "productions": sun.productions.iter().map(|(p, g)| json!({
                        "process": p,
                        "coupling": if p == "primakoff" { "g_agamma" } else { "g_ae" },
                        "value": g,
                    })).collect::<Vec<_>>(),
                    "couplings_not_used": sun.couplings_not_used,
                    "distance_au": sun.distance_mm / (crate::constants::AU_CM * 10.0),
                    "toward_sun": sun.toward_sun.to_array(),
                    "offset_arcmin": sun.offset_arcmin,
                    "target": sector_json(&sun.target),
                    "energy_range_keV": [sun.energy_range.0, sun.energy_range.1],
                    "luminosity_per_s": sun.emission_draw.luminosity,
                    "flux_at_target_per_cm2_s": sun.flux_per_mm2() * 100.0,
                    "rate_through_target_per_s": sun.rate_through_target(),
                    "rate_per_unit_weight_per_s": sun.rate_per_unit_weight(photons)
                        * magnet.map_or(1.0, |m| m.weight_scale),
                    "weight": s.describe_weight(magnet.is_some()),
                    "magnet": magnet.map(crate::magnet::Magnet::describe),
                }),
            })
            .collect(),
    )
}

fn sector_json(a: &AnnulusSector) -> Value {
    json!({
        "center_mm": a.center.to_array(),
        "radius_mm": a.radius,
        "inner_radius_mm": a.inner_radius,
        "azimuth_deg": [a.phi_start.to_degrees(), (a.phi_start + a.phi_span).to_degrees()],
        "area_mm2": a.area(),
    })
}
