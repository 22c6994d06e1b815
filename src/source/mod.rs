//! Photon sources: where photons start, in which direction, with which energy and
//! weight.
//!
//! Data flow: the scene file's `[[sources]]` entries are parsed into
//! [`SourceDesc`]s; each variant checks its own parameters next to its definition
//! and becomes a [`Source`]; `trace` calls [`Source::emit`] with photon i's own
//! random stream.

mod annulus;
mod parallel;
mod point;
mod spectrum;
mod summary;
pub mod sun;

pub use annulus::{AnnulusSector, ApertureDesc};
pub use parallel::{ParallelBeam, ParallelDesc};
pub use point::{PointDesc, PointSource};
pub use spectrum::{EnergyDesc, Spectrum, SpectrumTable};
pub use sun::{ProcessWeights, SunDesc, SunEmission, SunSource};

pub use summary::sources_json;

use crate::geometry::{within_world, WORLD_LIMIT_MM};
use crate::random::PhotonRng;
use glam::DVec3;
use serde::Deserialize;

message_error!(
    /// A source whose parameters describe no source, with what is wrong.
    InvalidSource
);

/// Photon sources. With several sources, photon i comes from source i mod n.
///
/// ```toml
/// [[sources]]
/// type = "parallel"                 # plane wave filling an aperture disk
/// direction = [0.0, 0.0, -1.0]      # nominal direction of travel (default −z)
/// off_axis = 0.0                    # degrees between the beam and `direction`
/// off_axis_azimuth = 0.0            # degrees, about `direction`, from the x–z plane
/// aperture = { center = [0, 0, 300], radius = 110.0, inner_radius = 0.0 }
/// energy = { line = 1.49 }          # keV; or { band = [1.48, 1.50] } (uniform)
///
/// [[sources]]
/// type = "point"                    # disk of `radius` emitting isotropically
/// position = [0, 0, 130297.0]
/// radius = 0.42                     # 0 for a true point
/// target = { center = [0, 0, 300], radius = 110.0, inner_radius = 55.0, azimuth = [-16, 16] }
///                                   # disk, annulus or sector the photons are aimed at
/// energy = { band = [1.48, 1.50] }
///
/// [[sources]]
/// type = "sun"                      # solar axions converted to X-rays (SPEC §3)
/// emission = "primakoff"            # built in (B16-AGSS09met, g_aγ = 1e-10 GeV⁻¹), or
///                                   # an emission table CSV (Radius, Energy [keV], emRates)
/// coupling = "g_ae = 1e-13"         # with a CSV: what it is computed for (reported)
/// solar_model = "b16_agss09met"     # built in: or "b16_gs98" (the solar-model systematic)
/// distance_au = 0.989               # Sun–Earth distance (default 0.989)
/// direction = [0, 0, 1]             # from the target towards the Sun (the bore axis)
/// offset_arcmin = [0.0, 0.0]        # pointing offset of the Sun's centre
/// target = { center = [83.6, 0, 9500], radius = 21.5 }   # the bore's Sun-side opening
/// energy_range = [0.5, 10.0]        # optional, keV: only this part of the emission
/// ```
/// A scene with a `sun` source has no other source: its images are in absolute
/// units (axions per second per pixel).
#[derive(Debug, Deserialize, Clone)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum SourceDesc {
    Parallel(ParallelDesc),
    Point(PointDesc),
    Sun(SunDesc),
}

impl SourceDesc {
    /// The source, or what is wrong with its parameters; files it names are
    /// relative to `dir`.
    pub fn build(&self, dir: &std::path::Path) -> Result<Source, InvalidSource> {
        Ok(match self {
            SourceDesc::Parallel(p) => Source::Parallel(p.build(dir)?),
            SourceDesc::Point(p) => Source::Point(p.build(dir)?),
            SourceDesc::Sun(s) => Source::Sun(s.build(dir)?),
        })
    }

    /// The files it reads (relative to `dir`): a Sun's emission table, a lab
    /// source's energy table.
    pub fn files(&self, dir: &std::path::Path) -> Vec<std::path::PathBuf> {
        match self {
            SourceDesc::Sun(s) => s.emission_file(dir).into_iter().collect(),
            SourceDesc::Parallel(p) => p.energy.file(dir).into_iter().collect(),
            SourceDesc::Point(p) => p.energy.file(dir).into_iter().collect(),
        }
    }
}

/// Why sources must start near the origin: Embree works in float32.
fn far_message() -> InvalidSource {
    InvalidSource(format!("source positions, centres and radii must lie within ±{WORLD_LIMIT_MM:e} mm of the origin (float32 geometry: start photons near the target)"))
}

/// Whether a point or a radius reaches beyond `geometry::WORLD_LIMIT_MM`.
fn far_from_origin(points: &[[f64; 3]], radii: &[f64]) -> bool {
    let points: Vec<DVec3> = points.iter().map(|&p| DVec3::from(p)).collect();
    !within_world(&points) || radii.iter().any(|&r| r > WORLD_LIMIT_MM)
}

/// A photon as it leaves a source.
#[derive(Clone, Copy, Debug)]
pub struct Photon {
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
    /// keV.
    pub energy: f64,
    /// Starts at the source's sampling weight; interactions only multiply it.
    pub weight: f64,
    /// Which part of the source's emission it was drawn from (a Sun's coupling,
    /// see [`SunEmission`]; 0 for every other source) …
    pub process: u8,
    /// … and which cell of that part's emission table (0 for other sources).
    pub cell: u32,
}

#[derive(Clone, Debug)]
pub enum Source {
    Parallel(ParallelBeam),
    Point(PointSource),
    Sun(SunSource),
}

impl Source {
    #[inline]
    pub fn emit(&self, rng: &mut PhotonRng) -> Photon {
        match self {
            Source::Parallel(s) => s.emit(rng),
            Source::Point(s) => s.emit(rng),
            Source::Sun(s) => s.emit(rng),
        }
    }

    /// Lowest and highest energy emitted (keV).
    pub fn energy_range(&self) -> (f64, f64) {
        match self {
            Source::Parallel(s) => s.spectrum.range(),
            Source::Point(s) => s.spectrum.range(),
            Source::Sun(s) => s.energy_range,
        }
    }

    /// The processes whose images a trace records beside the total (a Sun with
    /// Primakoff and ABC: "primakoff", "abc"); empty for one process.
    pub fn process_names(&self) -> Vec<String> {
        match self {
            Source::Sun(s) => s.emission_draw.process_names(),
            _ => Vec::new(),
        }
    }

    /// What one photon's weight means, for the JSON summary (a Sun's with
    /// the scene's magnet on or not).
    pub fn describe_weight(&self, magnet: bool) -> &'static str {
        match self {
            Source::Parallel(_) => {
                "weight 1 per photon; each photon stands for aperture.area_mm2 / photons of the beam"
            }
            Source::Point(_) => {
                "weight = fraction of the full sphere; the image is the expected photons per pixel if the source emitted `photons` photons isotropically"
            }
            Source::Sun(_) if magnet => {
                "weight = cos θ · D_min² / |target − emission point|² (≈ 1), times, when two emissions are drawn half the photons each (primakoff+abc), twice the drawn emission's share of the luminosity, times the axion's conversion probability P(a→γ) along its path through the magnet; images are the summed weights × rate_per_unit_weight: X-ray photons per second per pixel"
            }
            Source::Sun(_) => {
                "weight = cos θ · D_min² / |target − emission point|² (≈ 1), times, when two emissions are drawn half the photons each (primakoff+abc), twice the drawn emission's share of the luminosity; images are the summed weights × rate_per_unit_weight: axions per second per pixel, before the conversion probability in the magnet (the scene has none)"
            }
        }
    }
}

/// Two unit vectors completing `axis` to an orthonormal frame: `e1` is the part of
/// world +x perpendicular to the axis (world +y if the axis is along x), and
/// e2 = e1 × axis.
pub(crate) fn frame(axis: DVec3) -> (DVec3, DVec3) {
    let pick = if axis.x.abs() < 0.9 {
        DVec3::X
    } else {
        DVec3::Y
    };
    let e1 = (pick - axis * pick.dot(axis)).normalize();
    (e1, e1.cross(axis))
}
