//! The Sun as a source of axions converted to X-rays (SPEC §3): a sphere of radius
//! R_sun at a distance D, whose emission point and energy follow an emission table
//! (the built-in Primakoff table, or a CSV of the predecessor's format).
//!
//! Sampling: an emission cell is drawn in proportion to its axion rate, a point
//! uniformly in that shell's volume and direction, a point T uniformly on the
//! target disk (the magnet bore's Sun-side opening); the photon starts at T, aimed
//! from the emission point P. Everything is in f64 relative to the target centre
//! (|P| ≈ 1.5e14 mm: the direction is exact to ~1e-16 rad); nothing travels the
//! astronomical unit in float32.
//!
//! Units: the rate through the target is ∫∫ ε(P) cos θ / (4π |T − P|²) dV dA, so
//! with P drawn from the emission (luminosity L in the energy range) and T uniform
//! on the area A, each photon carries weight w = cos θ · D_min² / |T − P|² (≤ 1,
//! D_min = D − R_sun − target radius, w = 1 − O(1e-3)) and stands for
//! L·A/(4π D_min² N) axions per second, N the photons of the run. Trace outputs
//! multiply the summed weights by that factor: images are in axions per second
//! reaching each pixel (before the conversion probability in the magnet).
//!
//! Data flow: `SourceDesc::Sun` → [`SunDesc::build`] (reads the table) →
//! `Source::Sun`; trace outputs ask [`SunSource::rate_per_unit_weight`].

pub mod abc;
pub mod builtin;
pub mod emission;
mod mixture;
pub mod model;
pub mod opacity_project;
pub mod primakoff;
pub mod sampler;
pub mod shares;
pub mod tables;

pub use emission::EmissionTable;
pub use mixture::{ProcessWeights, SunEmission};
pub use model::{SolarDataError, SolarModel};
pub use sampler::EmissionSampler;

use super::{far_from_origin, frame, AnnulusSector, ApertureDesc, InvalidSource, Photon};
use crate::constants::{AU_CM, R_SUN_CM};
use crate::random::PhotonRng;
use glam::DVec3;
use serde::Deserialize;
use std::path::Path;
use std::sync::Arc;

/// The default emission in scene files.
pub const BUILTIN: &str = "primakoff";

/// The solar radius in mm.
const R_SUN_MM: f64 = R_SUN_CM * 10.0;
/// Distances from the Sun (AU) a source or spectrum may be placed at: Mercury's
/// perihelion to beyond Neptune; the Earth is at 0.983–1.017.
pub const DISTANCE_AU_RANGE: (f64, f64) = (0.3, 50.0);

/// Whether `au` is a distance from the Sun traxer accepts; else what is wrong
/// (`what` names the parameter).
pub fn check_distance_au(what: &str, au: f64) -> Result<(), String> {
    let (lo, hi) = DISTANCE_AU_RANGE;
    if au.is_finite() && (lo..=hi).contains(&au) {
        Ok(())
    } else {
        Err(format!("{what} {}: expected a distance from the Sun in astronomical units, {lo} to {hi} (the Earth is at 0.983 to 1.017)", crate::text::number(au)))
    }
}

/// `type = "sun"` in a scene file's `[[sources]]`.
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct SunDesc {
    /// "primakoff", "abc" or "primakoff+abc" (built in, computed from the
    /// B16-AGSS09met solar model), or the path of an emission table CSV, relative
    /// to the scene file.
    #[serde(default = "default_emission")]
    pub emission: String,
    /// The axion–photon coupling g_aγ in GeV⁻¹ of the built-in Primakoff
    /// emission (default 1e-10); its flux scales as g_aγ².
    #[serde(default)]
    pub g_agamma: Option<f64>,
    /// The axion–electron coupling g_ae of the built-in ABC emission (default
    /// 1e-13); its flux scales as g_ae².
    #[serde(default)]
    pub g_ae: Option<f64>,
    /// Both couplings at once, for a scene whose `emission` is a variable:
    /// each scales its process when the emission has it; one whose process the
    /// emission lacks is not used, and the run's summary.json says so
    /// (`sources[].couplings_not_used`). Instead of `g_agamma` and `g_ae`.
    #[serde(default)]
    pub couplings: Option<CouplingSet>,
    /// What coupling a CSV table is computed for (reported in summaries).
    #[serde(default)]
    pub coupling: Option<String>,
    /// The standard solar model of a built-in emission: "b16_agss09met" (the
    /// default) or "b16_gs98" (the solar-model systematic).
    #[serde(default)]
    pub solar_model: Option<String>,
    /// Sun–Earth distance in astronomical units.
    #[serde(default = "default_distance")]
    pub distance_au: f64,
    /// From the target towards the Sun's centre when pointing exactly (the magnet
    /// bore's axis).
    #[serde(default = "plus_z")]
    pub direction: [f64; 3],
    /// Pointing offset of the Sun's centre from `direction`, arcminutes, along the
    /// target frame's e1 (the part of +x perpendicular to `direction`) and e2.
    #[serde(default)]
    pub offset_arcmin: [f64; 2],
    /// The disk photons are aimed at and start on: the bore's Sun-side opening.
    pub target: ApertureDesc,
    /// Only emission between these energies (keV); default the whole table.
    #[serde(default)]
    pub energy_range: Option<[f64; 2]>,
}

/// `couplings = { g_agamma = ..., g_ae = ... }` of a `sun` source.
#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub struct CouplingSet {
    #[serde(default)]
    pub g_agamma: Option<f64>,
    #[serde(default)]
    pub g_ae: Option<f64>,
}

/// An emission: its table, what it is, its coupling, and its parts by coupling
/// when a trace draws from them separately (see [`SunEmission`]).
type Emission = (EmissionTable, String, String, Vec<builtin::CouplingPart>);

fn default_emission() -> String {
    BUILTIN.to_string()
}

fn default_distance() -> f64 {
    0.989
}

fn plus_z() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

#[derive(Clone, Debug)]
pub struct SunSource {
    pub target: AnnulusSector,
    /// Unit vector from the target centre to the Sun's centre (offset included).
    pub toward_sun: DVec3,
    /// Unit normal of the target (the nominal direction towards the Sun).
    pub target_normal: DVec3,
    /// Distance of the Sun's centre from the target centre, mm.
    pub distance_mm: f64,
    pub offset_arcmin: [f64; 2],
    /// The emission, restricted to the energy range.
    pub emission_draw: Arc<SunEmission>,
    pub energy_range: (f64, f64),
    /// What the emission is (built-in or the file read).
    pub emission: String,
    pub coupling: String,
    /// Couplings given in `couplings` for a process the emission does not have
    /// (e.g. "g_ae = 1e-13"): not used, and said so in summary.json.
    pub couplings_not_used: Vec<String>,
    /// The built-in emission's productions and their couplings' values:
    /// ("primakoff", g_aγ in GeV⁻¹) and ("abc", g_ae); empty for an emission
    /// table file (whose coupling is only text).
    pub productions: Vec<(String, f64)>,
    /// D_min² in mm² (see the module documentation).
    nearest_mm2: f64,
}

impl SunDesc {
    /// The emission table file it reads (none for a built-in emission).
    pub fn emission_file(&self, dir: &Path) -> Option<std::path::PathBuf> {
        builtin::parse_name(&self.emission)
            .is_none()
            .then(|| dir.join(&self.emission))
    }

    /// The emission table (read relative to `dir`), what it is, its coupling and
    /// (for a built-in emission with both couplings) its parts by coupling.
    fn emission_table(&self, dir: &Path) -> Result<Emission, InvalidSource> {
        if builtin::parse_name(&self.emission).is_some() {
            if self.coupling.is_some() {
                return Err("sun: coupling describes an emission table file; a built-in emission takes g_agamma (Primakoff) and g_ae (ABC)".into());
            }
            let (g_agamma, g_ae) = self.builtin_couplings()?;
            let model = match &self.solar_model {
                None => builtin::BuiltinModel::B16Agss09met,
                Some(m) => builtin::BuiltinModel::parse(m)
                    .map_err(|e| InvalidSource(format!("sun: solar_model = {e}")))?,
            };
            let e = builtin::builtin_emission_of(model, g_agamma, g_ae)
                .map_err(|e| InvalidSource(format!("sun: {e}")))?;
            return Ok((e.table, e.description, e.coupling, e.couplings));
        }
        let path = dir.join(&self.emission);
        if !path.is_file() {
            // A misspelt built-in name ("ABC", "primakof") reads as a file name:
            // say both what it is not and which names are built in.
            return Err(InvalidSource(format!(
                "sun: {}; nor is there an emission table file {}",
                builtin::unknown_emission(&self.emission, "emission", " = "),
                path.display()
            )));
        }
        if self.solar_model.is_some() {
            return Err("sun: solar_model picks the tables of a built-in emission (\"primakoff\", \"abc\", \"primakoff+abc\"); an emission table file is already computed from its own model".into());
        }
        if self.g_agamma.is_some() || self.g_ae.is_some() || self.couplings.is_some() {
            return Err("sun: g_agamma, g_ae and couplings scale the built-in emissions (\"primakoff\", \"abc\", \"primakoff+abc\"); for an emission table file, give its coupling as text in coupling".into());
        }
        let table = EmissionTable::read_csv(&path)
            .map_err(|e| InvalidSource(format!("sun: emission: {e}")))?;
        let coupling = self
            .coupling
            .clone()
            .unwrap_or_else(|| "the coupling the table was computed for".into());
        Ok((table, path.display().to_string(), coupling, Vec::new()))
    }

    /// The couplings to check for the built-in emission: `g_agamma` and `g_ae`
    /// as given, or those of `couplings` whose process the emission has.
    fn given_couplings(&self) -> Result<(Option<f64>, Option<f64>), InvalidSource> {
        let Some(set) = self.couplings else {
            return Ok((self.g_agamma, self.g_ae));
        };
        if self.g_agamma.is_some() || self.g_ae.is_some() {
            return Err("sun: give the couplings either as g_agamma and g_ae or in couplings = { g_agamma = ..., g_ae = ... }, not both".into());
        }
        let (primakoff, abc) = builtin::parse_name(&self.emission).unwrap_or((false, false));
        Ok((set.g_agamma.filter(|_| primakoff), set.g_ae.filter(|_| abc)))
    }

    /// A built-in emission's couplings as given, checked, with the defaults
    /// of the processes it has: (g_aγ, g_ae), `None` for a process it lacks.
    fn builtin_couplings(&self) -> Result<(Option<f64>, Option<f64>), InvalidSource> {
        let names = builtin::CouplingNames {
            assign: " = ",
            emission: "emission",
            g_agamma: "g_agamma",
            g_ae: "g_ae",
        };
        let (g_agamma, g_ae) = self.given_couplings()?;
        builtin::checked_couplings(&self.emission, g_agamma, g_ae, &names)
            .map_err(|e| InvalidSource(format!("sun: {e}")))
    }

    /// The built-in emission's productions with their couplings (see
    /// [`SunSource::productions`]).
    fn productions(&self) -> Result<Vec<(String, f64)>, InvalidSource> {
        if builtin::parse_name(&self.emission).is_none() {
            return Ok(Vec::new());
        }
        let (g_agamma, g_ae) = self.builtin_couplings()?;
        Ok([("primakoff", g_agamma), ("abc", g_ae)]
            .into_iter()
            .filter_map(|(n, g)| g.map(|g| (n.to_string(), g)))
            .collect())
    }

    /// The couplings of `couplings` the emission does not use, for the summary.
    fn couplings_not_used(&self) -> Vec<String> {
        let Some(set) = self.couplings else {
            return Vec::new();
        };
        let (primakoff, abc) = builtin::parse_name(&self.emission).unwrap_or((false, false));
        let mut out = Vec::new();
        if let (Some(g), false) = (set.g_agamma, primakoff) {
            out.push(format!(
                "g_agamma = {g:e}: the emission \"{}\" has no Primakoff part",
                self.emission
            ));
        }
        if let (Some(g), false) = (set.g_ae, abc) {
            out.push(format!(
                "g_ae = {g:e}: the emission \"{}\" has no ABC part",
                self.emission
            ));
        }
        out
    }

    /// The source, its table read relative to `dir`; or what is wrong.
    pub fn build(&self, dir: &Path) -> Result<SunSource, InvalidSource> {
        let p = self;
        if far_from_origin(&[p.target.center], &[p.target.radius]) {
            return Err(super::far_message());
        }
        if !p.target.is_valid() {
            return Err("sun: target needs finite center, 0 ≤ inner_radius < radius and azimuth = [from, to] with from < to ≤ from + 360".into());
        }
        check_distance_au("sun: distance_au =", p.distance_au).map_err(InvalidSource)?;
        let axis = DVec3::from(p.direction);
        if !axis.is_finite() || axis.length() == 0.0 {
            return Err(
                "sun: direction must be a non-zero vector (from the target towards the Sun)".into(),
            );
        }
        let axis = axis.normalize();
        if !p
            .offset_arcmin
            .iter()
            .all(|a| a.is_finite() && a.abs() < 600.0)
        {
            return Err("sun: offset_arcmin = [x, y] must be finite and below 600′ (10°)".into());
        }
        let (table, emission, coupling, couplings) = p.emission_table(dir)?;
        let (t_min, t_max) = (
            table.energy_edges()[0],
            *table.energy_edges().last().unwrap(),
        );
        let (e_min, e_max) = match p.energy_range {
            None => (t_min, t_max),
            Some([a, b]) if a.is_finite() && b.is_finite() && a < b => (a.max(t_min), b.min(t_max)),
            Some(_) => return Err("sun: energy_range = [min, max] with min < max (keV)".into()),
        };
        // One coupling: its table as it is (the sum of one), with ABC's shares.
        let draw = match couplings.as_slice() {
            [] => SunEmission::single(&table, (e_min, e_max), None),
            [one] => SunEmission::single(&table, (e_min, e_max), one.shares.clone()),
            _ => SunEmission::by_coupling(&couplings, e_min, e_max),
        };
        let emission_draw = draw.ok_or_else(|| {
            let luminosity = table.luminosity(e_min, e_max);
            InvalidSource(match luminosity.is_infinite() || luminosity.is_nan() {
                // Rates of 1e300 summed over the Sun's volume: not "nothing".
                true => "sun: the emission table's rates, summed over the Sun's volume, exceed the largest number a double holds: the table's `emRates` are per axion phase-space mode (keV), of order 1e-30 to 1e10 for real emissions: check their unit".to_string(),
                false => format!(
                    "sun: the emission table emits nothing between {e_min} and {e_max} keV"
                ),
            })
        })?;
        let toward_sun = toward_sun(axis, p.offset_arcmin);
        let distance_mm = p.distance_au * AU_CM * 10.0;
        let nearest = distance_mm - R_SUN_MM - p.target.radius;
        Ok(SunSource {
            target: AnnulusSector::new(
                DVec3::from(p.target.center),
                -axis,
                p.target.inner_radius,
                p.target.radius,
                p.target.azimuth,
            ),
            toward_sun,
            target_normal: axis,
            distance_mm,
            offset_arcmin: p.offset_arcmin,
            emission_draw: Arc::new(emission_draw),
            energy_range: (e_min, e_max),
            emission,
            coupling,
            couplings_not_used: p.couplings_not_used(),
            productions: p.productions()?,
            nearest_mm2: nearest * nearest,
        })
    }
}

/// The unit vector towards the Sun's centre offset by `offset_arcmin` along the
/// target frame's e1 and e2 from `axis`.
fn toward_sun(axis: DVec3, offset_arcmin: [f64; 2]) -> DVec3 {
    let (e1, e2) = frame(axis);
    let [ox, oy] = offset_arcmin.map(|a| (a / 60.0).to_radians().tan());
    (axis + e1 * ox + e2 * oy).normalize()
}

impl SunSource {
    /// The same Sun with its centre offset by `offset_arcmin` instead (along
    /// e1 and e2, as the scene's `offset_arcmin`): for measuring where the sky
    /// images.
    pub fn with_offset(&self, offset_arcmin: [f64; 2]) -> SunSource {
        SunSource {
            toward_sun: toward_sun(self.target_normal, offset_arcmin),
            offset_arcmin,
            ..self.clone()
        }
    }

    #[inline]
    pub fn emit(&self, rng: &mut PhotonRng) -> Photon {
        let ((r, energy), weight, (process, cell)) = self.emission_draw.sample(rng);
        // A uniform direction from the Sun's centre.
        let z = 2.0 * rng.uniform() - 1.0;
        let phi = std::f64::consts::TAU * rng.uniform();
        let s = (1.0 - z * z).max(0.0).sqrt();
        let radial = DVec3::new(s * phi.cos(), s * phi.sin(), z);
        // Relative to the target centre.
        let emission = self.toward_sun * self.distance_mm + radial * (r * R_SUN_MM);
        let on_target = self.target.sample(rng);
        let v = (on_target - self.target.center) - emission;
        let d2 = v.length_squared();
        let dir = v / d2.sqrt();
        Photon {
            origin: on_target,
            dir,
            energy,
            weight: dir.dot(self.target_normal).abs() * self.nearest_mm2 / d2 * weight,
            process,
            cell,
        }
    }

    /// Angular radius of the solar disk seen from the target, radians.
    pub fn angular_radius(&self) -> f64 {
        (R_SUN_CM * 10.0 / self.distance_mm).asin()
    }

    /// Axions per second that one unit of weight stands for, summed over a run of
    /// `photons` photons: L·A / (4π D_min²) / photons (with a magnet, the
    /// scene multiplies it by the magnet's weight scale).
    pub fn rate_per_unit_weight(&self, photons: u64) -> f64 {
        self.emission_draw.luminosity * self.target.area()
            / (4.0 * std::f64::consts::PI * self.nearest_mm2)
            / photons.max(1) as f64
    }

    /// Axions per second through the target (energy range only): L·A·cos θ/(4πD²)
    /// for the distant Sun, θ its angle from the target's normal.
    pub fn rate_through_target(&self) -> f64 {
        self.flux_per_mm2() * self.target.area() * self.toward_sun.dot(self.target_normal)
    }

    /// Axion flux at the target, per mm² and second, facing the Sun.
    pub fn flux_per_mm2(&self) -> f64 {
        self.emission_draw.luminosity / (4.0 * std::f64::consts::PI * self.distance_mm.powi(2))
    }
}
