//! The life of one photon: emit, intersect, interact, repeat.

use super::stats::Statistics;
use crate::history::History;
use crate::material::Material;
use crate::random::PhotonRng;
use crate::raycast::{intersect_query, query_leaving, reflect, QueryHook, SurfaceHit};
use crate::scene::Scene;
use crate::sensor::conversion::ConversionRecord;
use crate::source::Photon;
use crate::xray::figure_error::Perturbed;
use crate::xray::roughness::{to_grazing_angle, Scatter};
use glam::DVec3;

/// A photon recorded by a sensor.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Record {
    pub sensor: u32,
    pub pixel: u32,
    pub weight: f64,
    pub energy: f64,
    pub history: History,
    /// Where a gas detector's photon converted (`None` for other sensors).
    pub conversion: Option<ConversionRecord>,
    /// Which part and cell of the source's emission it came from
    /// ([`Photon::process`], [`Photon::cell`]).
    #[serde(default)]
    pub process: u8,
    #[serde(default)]
    pub cell: u32,
}

/// Everything known about a recorded photon, for photon lists.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RecordedPhoton {
    /// The photon's index in the run (its random stream).
    pub index: u64,
    pub record: Record,
    /// Where it hit, in the sensor's local frame (mm).
    pub local: DVec3,
    /// Its direction of travel (world frame, unit vector).
    pub dir: DVec3,
}

/// How reflections and foils change a photon's weight: at once, at the photon's
/// energy ([`AtItsEnergy`], a trace), or written down to be evaluated later at
/// many energies (the effective area: the path does not depend on the energy).
pub trait Attenuation {
    /// A reflection on a mirror with reflectivity table `table` at grazing angle
    /// `theta` (rad).
    fn mirror(&mut self, scene: &Scene, table: usize, photon: &mut Photon, theta: f64);
    /// A passage through foil `foil` at cos θ = `cos` to its normal.
    fn foil(&mut self, scene: &Scene, foil: usize, photon: &mut Photon, cos: f64);
}

/// Weights multiplied at the photon's own energy.
pub struct AtItsEnergy;

/// Weights multiplied at the photon's own energy, with these reflectivity
/// tables (one per scene table, in its order) in place of the scene's: a study
/// tracing energies the scene's sources do not emit builds them as the scene
/// would for a source of those energies.
pub struct WithTables<'a>(pub &'a [crate::xray::ReflectivityTable]);

impl Attenuation for WithTables<'_> {
    #[inline]
    fn mirror(&mut self, _: &Scene, table: usize, photon: &mut Photon, theta: f64) {
        photon.weight *= self.0[table].reflectivity(photon.energy, theta);
    }

    #[inline]
    fn foil(&mut self, scene: &Scene, foil: usize, photon: &mut Photon, cos: f64) {
        AtItsEnergy.foil(scene, foil, photon, cos);
    }
}

impl Attenuation for AtItsEnergy {
    #[inline]
    fn mirror(&mut self, scene: &Scene, table: usize, photon: &mut Photon, theta: f64) {
        photon.weight *= scene.reflectivity[table].reflectivity(photon.energy, theta);
    }

    #[inline]
    fn foil(&mut self, scene: &Scene, foil: usize, photon: &mut Photon, cos: f64) {
        photon.weight *= scene.foils[foil].transmission(photon.energy, cos);
    }
}

/// Traces one photon to its end, updating `stats` and reporting a sensor record
/// with the photon's local position on the sensor and final direction.
#[inline]
pub fn trace_photon<H: QueryHook, A: Attenuation>(
    scene: &Scene,
    mut photon: Photon,
    rng: &mut PhotonRng,
    stats: &mut Statistics,
    hook: &mut H,
    att: &mut A,
) -> Option<(Record, DVec3, DVec3)> {
    stats.photons_emitted += 1;
    let mut history = History::default();
    let mut start: Option<SurfaceHit> = None;
    for _ in 0..scene.max_interactions {
        let q = query_leaving(photon.origin, photon.dir, start.as_ref());
        stats.embree_queries += 1;
        let Some(hit) = intersect_query(scene, &q, hook) else {
            stats.escaped += 1;
            return None;
        };
        stats.hits_per_object[hit.object] += 1;
        let object = &scene.objects[hit.object];
        match object.material {
            Material::Mirror {
                side,
                reflectivity,
                figure_error,
                roughness,
            } => {
                let from_front = photon.dir.dot(hit.geometric_normal) < 0.0;
                if !side.reflects(from_front) {
                    stats.absorbed_mirror_back += 1;
                    return None;
                }
                // Grazing angle between the ray and the (refined) surface.
                let theta = match reflectivity.is_some() || roughness.is_some() {
                    true => photon.dir.dot(hit.shading_normal).abs().min(1.0).asin(),
                    false => 0.0,
                };
                if let Some(table) = reflectivity {
                    att.mirror(scene, table, &mut photon, theta);
                }
                let mut out = reflect(photon.dir, hit.shading_normal).normalize();
                if let Some(r) = roughness {
                    // Two draws, always: streams stay aligned across settings.
                    let (u1, u2) = (rng.uniform(), rng.uniform());
                    let e = photon.energy;
                    if let Scatter::Scattered { theta_s } =
                        scene.roughness[r].draw(e, theta, u1, u2)
                    {
                        out = to_grazing_angle(out, hit.shading_normal, theta_s);
                    }
                }
                if let Some(fe) = &figure_error {
                    match fe.perturb(out, hit.shading_normal, rng) {
                        Perturbed::Direction(d) => out = d,
                        Perturbed::BelowSurface => {
                            stats.scattered_below_surface += 1;
                            return None;
                        }
                    }
                }
                // With interpolated normals the reflection can point into the facet.
                let arrival_side = if from_front { 1.0 } else { -1.0 };
                if hit.on_mesh && out.dot(hit.geometric_normal) * arrival_side <= 0.0 {
                    stats.reflected_into_surface += 1;
                    return None;
                }
                history.reflect(hit.object, object.stage);
                photon.origin = hit.point;
                photon.dir = out;
                start = Some(hit);
            }
            Material::Absorber => {
                stats.absorbed += 1;
                if history.reflections > 0 {
                    stats.stopped_after_reflection[hit.object] += 1;
                }
                return None;
            }
            Material::Foil { foil } => {
                let cos = photon.dir.dot(hit.geometric_normal);
                att.foil(scene, foil, &mut photon, cos);
                // Straight on, leaving the foil's surface behind.
                photon.origin = hit.point;
                start = Some(hit);
            }
            Material::Sensor { sensor } => {
                return record_on_sensor(scene, sensor, &hit, &photon, history, rng, stats);
            }
        }
    }
    stats.max_interactions_reached += 1;
    None
}

/// A photon reaching sensor `sensor` at `hit`: its record, with its local position
/// and direction, or `None` (outside the active area or the energy bands, or for
/// a gas detector, arriving from behind the readout).
#[inline]
fn record_on_sensor(
    scene: &Scene,
    sensor: usize,
    hit: &SurfaceHit,
    photon: &Photon,
    history: History,
    rng: &mut PhotonRng,
    stats: &mut Statistics,
) -> Option<(Record, DVec3, DVec3)> {
    let spec = &scene.sensors[sensor];
    let object = &scene.objects[hit.object];
    let Some(band) = spec.band(photon.energy) else {
        stats.sensor_outside_energy_range += 1;
        return None;
    };
    let (mut weight, mut point, mut conversion) = (photon.weight, hit.point, None);
    if let Some(gas) = &spec.gas {
        // The gas lies on the side the readout's normal points to; the photon
        // crossed it on its way here and converted at a sampled depth, whose
        // electrons drift along the normal onto the readout.
        let cos = photon.dir.dot(hit.geometric_normal);
        if cos >= 0.0 {
            stats.absorbed += 1;
            return None;
        }
        let c = gas.convert(photon.energy, cos, rng.uniform());
        point = hit.point - photon.dir * c.remaining_mm;
        weight *= c.probability;
        conversion = Some(ConversionRecord {
            entered: photon.weight,
            depth_mm: c.depth_mm,
        });
    }
    let local = object.transform.to_local.transform_point3(point);
    match spec.pixel(local) {
        Some(pixel) => {
            let pixel = pixel + band * spec.pixel_count() as u32;
            stats.reached_sensor += 1;
            stats.recorded_per_sensor[sensor] += 1;
            let record = Record {
                sensor: sensor as u32,
                pixel,
                weight,
                energy: photon.energy,
                history,
                conversion,
                process: photon.process,
                cell: photon.cell,
            };
            Some((record, local, photon.dir))
        }
        None => {
            stats.sensor_outside_area += 1;
            None
        }
    }
}
