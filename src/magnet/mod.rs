//! The helioscope's magnet: where solar axions become X-rays. Each photon a
//! Sun emits is an axion that crossed the magnet's bore along the photon's
//! straight path; its weight is multiplied by the probability P that it
//! converted there, for the scene's axion mass, coupling and buffer gas.
//!
//! The field is uniform (`field_t` over the bore's length, the closed form)
//! or a field map (trilinear between its nodes, the amplitude integrated along
//! the path: `conversion`); a buffer gas gives the photon a mass and absorbs
//! it on the way out (`buffer_gas`).
//!
//! Data flow: `scene::magnet` builds a [`Magnet`] from the scene's `[magnet]`
//! table and the bore object; the photon loop (`trace`) calls
//! [`Magnet::convert`] for each recorded photon of the Sun: P depends only on
//! the axion's straight path and energy, so it is a factor on the weight the
//! photon arrives with, computed once for the photons that arrive.

pub mod buffer_gas;
pub mod campaign;
pub mod conversion;
pub mod exposure;
pub mod field_map;
pub mod helium_vapour;
pub mod legendre;
pub mod planner;
pub mod probe;

use crate::constants::{INV_EV_PER_METRE, TESLA_EV2};
use crate::geometry::Transform;
use buffer_gas::BufferGas;
use conversion::{momentum_transfer, uniform_probability, PathField};
use field_map::FieldMap;
use glam::DVec3;
use std::sync::Arc;

/// The magnet's field.
#[derive(Clone, Debug)]
pub enum Field {
    /// A uniform field of `tesla` along `direction` (a unit vector in the
    /// bore's frame) over the bore's length.
    Uniform { tesla: f64, direction: DVec3 },
    /// A field map; `to_map` carries the bore's frame (origin at its centre)
    /// into the map's.
    Map {
        map: Arc<FieldMap>,
        to_map: Box<Transform>,
        /// What the map is (its shipped name or file), for summaries.
        name: String,
    },
}

/// A magnet filling a cylindrical bore.
#[derive(Clone, Debug)]
pub struct Magnet {
    /// The bore object's name.
    pub bore: String,
    /// The bore's frame (its axis along z, its centre at the origin) → world.
    pub frame: Transform,
    /// The bore's half length along its axis, and its radius (mm).
    pub half_length_mm: f64,
    pub radius_mm: f64,
    pub field: Field,
    /// The sampling step along the path through a map (mm; for a uniform
    /// field, unused).
    pub step_mm: f64,
    pub gas: Option<BufferGas>,
    pub axion_mass_ev: f64,
    /// g_aγ in GeV⁻¹.
    pub g_agamma_gev: f64,
    /// The masses (eV) of a mass scan: each sensor also records an image per
    /// mass ([`Magnet::convert`]).
    pub scan_masses: Vec<f64>,
    /// The unit of a photon's conversion weight: P_max = (g_aγ B_peak L / 2)²,
    /// the vacuum P of the strongest field over the whole length, which no
    /// path exceeds ([`Magnet::peak_probability`]).
    pub weight_scale: f64,
    /// A data-taking campaign recorded from the same photons (none: the
    /// scene's one setting).
    pub campaign: Option<Arc<campaign::Campaign>>,
}

impl Magnet {
    /// What a magnet run assumed, for its printout, its pictures and
    /// summary.json: the axion mass, the gas setting (or vacuum), the field
    /// and the coupling, e.g. "m_a = 0 eV, vacuum, field map babyiaxo,
    /// g_aγ = 1e-10 GeV⁻¹".
    pub fn assumptions(&self) -> String {
        use crate::text::number;
        let gas = match &self.gas {
            None => "vacuum".to_string(),
            Some(g) => format!(
                "{} {} mbar at {} K (m_γ = {:.4} eV)",
                g.desc.mixture.keys().cloned().collect::<Vec<_>>().join("+"),
                number(g.desc.pressure_mbar),
                number(g.desc.temperature_k),
                g.photon_mass_ev()
            ),
        };
        let field = match &self.field {
            Field::Uniform { tesla, .. } => format!(
                "uniform {} T over {} m",
                number(*tesla),
                number(2e-3 * self.half_length_mm)
            ),
            Field::Map { name, .. } => format!("field map {name}"),
        };
        format!(
            "m_a = {} eV, {gas}, {field}, g_aγ = {} GeV⁻¹",
            number(self.axion_mass_ev),
            number(self.g_agamma_gev)
        )
    }

    /// P_max = (g_aγ B_peak L / 2)² for the field's strongest value B_peak and
    /// the bore's length L. A photon's weight carries P / P_max (≤ 1 in vacuum)
    /// and the Sun's rate per unit weight carries P_max: the sensors add
    /// weights in fixed point (`sensor::exact`, resolution 2⁻⁸⁰ ≈ 8e-25), where
    /// P itself (1e-19 at g_aγ = 1e-10, 1e-27 at 1e-12) would lose its digits.
    pub fn peak_probability(field: &Field, g_agamma_gev: f64, length_mm: f64) -> f64 {
        let peak = match field {
            Field::Uniform { tesla, .. } => *tesla,
            Field::Map { map, .. } => map.peak_tesla(),
        };
        let amplitude =
            0.5 * g_agamma_gev * 1e-9 * peak * TESLA_EV2 * length_mm * 1e-3 * INV_EV_PER_METRE;
        amplitude * amplitude
    }

    /// The path of the line through `origin` along the unit vector `dir`
    /// (world) between the bore's end planes: the distances along `dir` from
    /// `origin` where it enters and leaves; `None` for a line parallel to
    /// them.
    pub fn path(&self, origin: DVec3, dir: DVec3) -> Option<(f64, f64)> {
        let o = self.frame.to_local.transform_point3(origin);
        let d = self.frame.to_local.transform_vector3(dir);
        if d.z == 0.0 {
            return None;
        }
        let a = (-self.half_length_mm - o.z) / d.z;
        let b = (self.half_length_mm - o.z) / d.z;
        Some((a.min(b), a.max(b)))
    }

    /// The magnet for a run's summary: its bore, field, gas, mass and
    /// coupling, and P on the bore's axis at 1, 4 and 8 keV.
    pub fn describe(&self) -> serde_json::Value {
        let field = match &self.field {
            Field::Uniform { tesla, direction } => serde_json::json!({
                "uniform_t": tesla,
                "direction_in_bore_frame": direction.to_array(),
            }),
            Field::Map { name, .. } => serde_json::json!({
                "map": name,
                "step_mm": self.step_mm,
            }),
        };
        let (o, d) = probe::lines(self, probe::Where::Line([0.0, 0.0]))[0];
        let path = self.path_of(o, d);
        let on_axis: Vec<serde_json::Value> = [1.0, 4.0, 8.0]
            .iter()
            .map(|&e| serde_json::json!({"energy_keV": e, "probability": path.probability(self, e, self.axion_mass_ev)}))
            .collect();
        serde_json::json!({
            "bore": self.bore,
            "length_mm": 2.0 * self.half_length_mm,
            "radius_mm": self.radius_mm,
            "field": field,
            "axion_mass_ev": self.axion_mass_ev,
            "g_agamma_per_gev": self.g_agamma_gev,
            "masses_ev": self.scan_masses,
            "weight_scale": self.weight_scale,
            "weight_scale_is": "P_max = (g_aγ B_peak L / 2)²: each photon's weight carries P / P_max, rate_per_unit_weight carries P_max",
            "gas": self.gas.as_ref().map(|g| serde_json::json!({
                "mixture": g.desc.mixture,
                "pressure_mbar": g.desc.pressure_mbar,
                "temperature_k": g.desc.temperature_k,
                "photon_mass_ev": g.photon_mass_ev(),
                "attenuation": "total: Henke photoabsorption + NIST FFAST coherent and incoherent scattering",
            })),
            "probability_on_axis": on_axis,
            "what": "each photon's weight is times P(a→γ) of its axion along its straight path between the bore's end planes: images are X-rays per second",
        })
    }

    /// The transverse field along the photon's path, sampled for the
    /// amplitude integral (eV² on two axes ⊥ the path, step in eV⁻¹). The
    /// samples are evenly spaced along the bore's axis, `step_mm` apart there
    /// (a tilted path's samples lie on the same planes across the bore as an
    /// axial one's: on the map's node planes when the bore's ends are).
    /// Outside the map (a path leaving the bore, whose photon the bore's wall
    /// stops) the field counts as zero.
    pub fn path_field(&self, origin: DVec3, dir: DVec3) -> PathField {
        let Some((s0, s1)) = self.path(origin, dir) else {
            return PathField::default();
        };
        let length = s1 - s0;
        let steps = (2.0 * self.half_length_mm / self.step_mm - 1e-9)
            .ceil()
            .max(1.0) as usize;
        let h = length / steps as f64;
        let d_local = self.frame.to_local.transform_vector3(dir).normalize();
        // B⊥ · e for e ⊥ the path is B · e: the two axes take it directly.
        let (e1, e2) = d_local.any_orthonormal_pair();
        let mut samples = Vec::with_capacity(steps + 1);
        match &self.field {
            Field::Uniform { tesla, direction } => {
                let b = *direction * (*tesla * TESLA_EV2);
                samples.resize(steps + 1, [b.dot(e1), b.dot(e2)]);
            }
            Field::Map { map, to_map, .. } => {
                // The path is a straight line in the map's frame too: its start
                // and step there, in grid units.
                let start = to_map.point(self.frame.to_local.transform_point3(origin + dir * s0));
                let step = to_map.vector(self.frame.to_local.transform_vector3(dir * h));
                // The map's field is turned back into the bore's frame by
                // to_map's inverse, B_bore = M⁻¹ B_map, so B_bore · e is
                // B_map · (M⁻¹)ᵀ e.
                let back = to_map.to_local.matrix3.transpose();
                let row = |e: DVec3| (back * e * TESLA_EV2).to_array();
                map.sample_line(
                    (
                        map.to_grid(start.to_array()),
                        map.vector_to_grid(step.to_array()),
                    ),
                    steps + 1,
                    [row(e1), row(e2)],
                    &mut samples,
                );
            }
        }
        PathField {
            step: h * 1e-3 * INV_EV_PER_METRE,
            samples,
        }
    }

    /// The field along the line through `origin` along the unit vector
    /// `dir`: what P needs of the path, computed once for any energy and mass.
    pub fn path_of(&self, origin: DVec3, dir: DVec3) -> ConversionPath {
        match &self.field {
            Field::Uniform { tesla, direction } => {
                let Some((s0, s1)) = self.path(origin, dir) else {
                    return ConversionPath::Uniform {
                        b_ev2: 0.0,
                        length: 0.0,
                    };
                };
                let d = self.frame.to_local.transform_vector3(dir).normalize();
                let transverse = (*direction - d * direction.dot(d)).length() * tesla;
                ConversionPath::Uniform {
                    b_ev2: transverse * TESLA_EV2,
                    length: (s1 - s0) * 1e-3 * INV_EV_PER_METRE,
                }
            }
            Field::Map { .. } => ConversionPath::Sampled(self.path_field(origin, dir)),
        }
    }

    /// The conversion of a recorded photon's axion of `energy_kev` on `path`
    /// ([`Magnet::path_of`] its start and direction): returns P / P_max at the
    /// magnet's mass (the factor on the photon's weight, see
    /// [`Magnet::weight_scale`]) and appends, for each scan mass, P there over
    /// P at the magnet's mass (the factor that turns the photon's weight into
    /// its weight at that mass: the optics do not depend on the mass). One
    /// sampling of the path serves every mass. A path with P = 0 at the
    /// magnet's mass (no field along it) gives 0 at every mass.
    pub fn convert(&self, path: &ConversionPath, energy_kev: f64, scan: &mut Vec<f64>) -> f64 {
        let p = path.probability(self, energy_kev, self.axion_mass_ev);
        let start = scan.len();
        scan.extend(&self.scan_masses);
        let medium = medium(self.gas.as_ref(), energy_kev);
        path.probabilities_in_place(self.g_agamma_gev, medium, energy_kev, &mut scan[start..]);
        for ratio in &mut scan[start..] {
            *ratio = if p > 0.0 { *ratio / p } else { 0.0 };
        }
        p / self.weight_scale
    }

    /// P(a → γ) for an axion of `energy_kev` on the line through `origin`
    /// along the unit vector `dir`, at the magnet's mass and coupling.
    pub fn probability(&self, origin: DVec3, dir: DVec3, energy_kev: f64) -> f64 {
        self.path_of(origin, dir)
            .probability(self, energy_kev, self.axion_mass_ev)
    }
}

/// The field along one axion's path (see [`Magnet::path_of`]).
#[derive(Clone, Debug, PartialEq)]
pub enum ConversionPath {
    /// B⊥ (eV²) over a length (eV⁻¹): the closed form.
    Uniform { b_ev2: f64, length: f64 },
    /// A map's field sampled along the path: the integral.
    Sampled(PathField),
}

/// The photon mass squared (eV²) and the attenuation Γ (eV) at `energy_kev`
/// in `gas` (`None`: vacuum).
pub fn medium(gas: Option<&BufferGas>, energy_kev: f64) -> (f64, f64) {
    match gas {
        None => (0.0, 0.0),
        Some(g) => (
            g.photon_mass2_ev2,
            g.attenuation_ev(energy_kev).unwrap_or(f64::INFINITY),
        ),
    }
}

impl ConversionPath {
    /// P at `energy_kev` and axion mass `mass_ev` in `magnet` (its coupling
    /// and gas).
    pub fn probability(&self, magnet: &Magnet, energy_kev: f64, mass_ev: f64) -> f64 {
        let medium = medium(magnet.gas.as_ref(), energy_kev);
        self.probability_in(magnet.g_agamma_gev, medium, energy_kev, mass_ev)
    }

    /// P at coupling `g_agamma_gev` (GeV⁻¹) in a medium of photon mass
    /// squared and attenuation `(m_γ², Γ)` ([`medium`]): another gas setting
    /// of the same path.
    pub fn probability_in(
        &self,
        g_agamma_gev: f64,
        (m_gamma2, gamma): (f64, f64),
        energy_kev: f64,
        mass_ev: f64,
    ) -> f64 {
        let g = g_agamma_gev * 1e-9;
        let q = momentum_transfer(mass_ev, m_gamma2, energy_kev * 1e3);
        match self {
            ConversionPath::Uniform { b_ev2, length } => {
                uniform_probability(g, *b_ev2, *length, q, gamma)
            }
            ConversionPath::Sampled(field) => field.probability(g, q, gamma),
        }
    }

    /// [`ConversionPath::probability_in`] at each axion mass (eV) of
    /// `masses`, replaced by its P: one medium and energy for all, the same
    /// values as one call per mass, bit for bit, in a third of the time.
    pub fn probabilities_in_place(
        &self,
        g_agamma_gev: f64,
        (m_gamma2, gamma): (f64, f64),
        energy_kev: f64,
        masses: &mut [f64],
    ) {
        let g = g_agamma_gev * 1e-9;
        for m in masses.iter_mut() {
            *m = momentum_transfer(*m, m_gamma2, energy_kev * 1e3);
        }
        match self {
            ConversionPath::Uniform { b_ev2, length } => {
                for q in masses.iter_mut() {
                    *q = uniform_probability(g, *b_ev2, *length, *q, gamma);
                }
            }
            ConversionPath::Sampled(field) => field.probabilities_in_place(g, gamma, masses),
        }
    }
}
