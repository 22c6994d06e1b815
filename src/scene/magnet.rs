//! The scene's `[magnet]` table: a field (uniform, or a map shipped with
//! traxer or read from a file) filling a cylindrical bore object, an optional
//! buffer gas, the axion mass and the coupling. Built into a
//! [`crate::magnet::Magnet`] that the scene's Sun applies to every photon.
//!
//! Data flow: `scene::magnet_in_scene` finds the bore among the objects, calls
//! [`build`] and hands the magnet to the Sun source.

use super::placement::{transform, TransformStep};
use crate::magnet::buffer_gas::{BufferGas, BufferGasDesc};
use crate::magnet::campaign::{Campaign, CampaignDesc};
use crate::magnet::field_map::FieldMap;
use crate::magnet::{Field, Magnet};
use glam::{DAffine3, DVec3};
use serde::Deserialize;
use std::path::Path;
use std::sync::{Arc, OnceLock};
use toml::Spanned;

/// `[magnet]` in a scene file.
///
/// ```toml
/// [magnet]
/// enabled = true                   # optional: false leaves the axions unconverted
/// bore = "bore"                    # the cylinder object the field fills
/// field_t = 9.0                    # a uniform transverse field (T) over the bore, or
/// field_map = "bykovskiy_201906"   # a field map: shipped (data/magnets/) or FILE
/// field_map_transform = []         # optional: the map in the bore's frame (default:
///                                  # the map's origin at the bore's centre, z along its axis)
/// step_mm = 25.0                   # optional: the path integral's step through a map
///                                  # (default: the map's finest node spacing)
/// axion_mass_ev = 0.0
/// masses_ev = [0.01, 0.02]         # optional: also an image per mass, from the same photons
/// g_agamma = 1e-10                 # GeV⁻¹: the conversion's coupling (the Sun's g_aγ)
/// gas = { mixture = { He = 1.0 }, pressure_mbar = 10.0, temperature_k = 1.8 }
/// ```
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MagnetDesc {
    /// `false`: the scene as without the table (images of axions before
    /// conversion), for a scene variable that switches the magnet.
    #[serde(default = "yes")]
    pub enabled: bool,
    pub bore: String,
    #[serde(default)]
    pub field_t: Option<f64>,
    /// The uniform field's direction in the bore's frame (default +y).
    #[serde(default)]
    pub field_direction: Option<[f64; 3]>,
    #[serde(default)]
    pub field_map: Option<String>,
    #[serde(default)]
    pub field_map_transform: Vec<Spanned<TransformStep>>,
    #[serde(default)]
    pub step_mm: Option<f64>,
    #[serde(default)]
    pub axion_mass_ev: f64,
    /// A mass scan: the sensors also record one image per mass (eV), each
    /// photon's weight times its axion's P at that mass over P at
    /// `axion_mass_ev`.
    #[serde(default)]
    pub masses_ev: Vec<f64>,
    pub g_agamma: f64,
    #[serde(default)]
    pub gas: Option<BufferGasDesc>,
    /// A data-taking campaign from the same photons ([`CampaignDesc`]).
    #[serde(default)]
    pub campaign: Option<CampaignDesc>,
}

fn yes() -> bool {
    true
}

/// The shipped field maps, by name.
pub const SHIPPED_MAPS: [(&str, &str); 1] = [(
    "bykovskiy_201906",
    include_str!(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/magnets/Bykovskiy_201906.dat"
    )),
)];

/// A shipped map, parsed once per process.
fn shipped_map(name: &str) -> Option<Result<Arc<FieldMap>, String>> {
    type Parsed = OnceLock<Result<Arc<FieldMap>, String>>;
    static PARSED: [Parsed; SHIPPED_MAPS.len()] = [const { OnceLock::new() }; SHIPPED_MAPS.len()];
    let k = SHIPPED_MAPS.iter().position(|(n, _)| *n == name)?;
    let text = SHIPPED_MAPS[k].1;
    Some(
        PARSED[k]
            .get_or_init(|| {
                FieldMap::parse(&format!("data/magnets/{name}"), text)
                    .map(Arc::new)
                    .map_err(|e| e.0)
            })
            .clone(),
    )
}

/// The bore: a cylinder's radius and ends (its local frame) and its placement.
pub struct Bore<'a> {
    pub name: &'a str,
    pub radius: f64,
    pub z_start: f64,
    pub z_end: f64,
    pub to_world: crate::geometry::Transform,
}

/// Builds the magnet; `dir` is the scene file's folder (for a map file, which
/// `note` records as an input).
pub fn build(
    d: &MagnetDesc,
    bore: &Bore,
    dir: &Path,
    note: &dyn Fn(&Path),
) -> Result<Magnet, String> {
    let map = d
        .field_map
        .as_ref()
        .map(|name| load_map(name, dir, note))
        .transpose()?;
    assemble(d, bore, map)
}

/// A shipped map by name, or the map file `name` relative to `dir` (noted as
/// an input).
fn load_map(name: &str, dir: &Path, note: &dyn Fn(&Path)) -> Result<Arc<FieldMap>, String> {
    if let Some(m) = shipped_map(name) {
        return m;
    }
    let path = dir.join(name);
    if !path.is_file() {
        let shipped: Vec<&str> = SHIPPED_MAPS.iter().map(|m| m.0).collect();
        return Err(format!(
            "field_map = \"{name}\": not a shipped map ({}) and no file {}",
            shipped.join(", "),
            path.display()
        ));
    }
    note(&path);
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(Arc::new(
        FieldMap::parse(&path.display().to_string(), &text).map_err(|e| e.0)?,
    ))
}

/// The magnet of `d` in `bore`, its field map (if it names one) loaded.
fn assemble(d: &MagnetDesc, bore: &Bore, map: Option<Arc<FieldMap>>) -> Result<Magnet, String> {
    let centre = 0.5 * (bore.z_start + bore.z_end);
    let frame = crate::geometry::Transform::from_affine(DAffine3::from_translation(DVec3::new(
        0.0, 0.0, centre,
    )))
    .then(&bore.to_world);
    let half_length_mm = 0.5 * (bore.z_end - bore.z_start).abs();
    if let Some(step) = d.step_mm {
        check_step(step)?;
    }
    if !(d.axion_mass_ev.is_finite() && d.axion_mass_ev >= 0.0) {
        return Err(format!(
            "axion_mass_ev = {}: a mass is ≥ 0 (eV)",
            crate::text::number(d.axion_mass_ev)
        ));
    }
    if d.axion_mass_ev > MAX_MASS_EV {
        return Err(format!(
            "axion_mass_ev = {}: {MASS_BOUND}",
            crate::text::number(d.axion_mass_ev)
        ));
    }
    check_scan(
        "masses_ev",
        &d.masses_ev,
        (MAX_SCAN_MASSES, "each is an image on every sensor"),
    )?;
    check_coupling(d.g_agamma)?;
    let field = match (d.field_t, &d.field_map, map) {
        (Some(b), None, _) => uniform(b, d.field_direction)?,
        (None, Some(name), Some(map)) => {
            if d.field_direction.is_some() {
                return Err("field_direction is for a uniform field (field_t); a map gives its own".into());
            }
            let to_map = transform(&d.field_map_transform)
                .map_err(|(_, m)| format!("field_map_transform: {m}"))?;
            // The steps place the map in the bore's frame; points go the other way.
            let to_map = crate::geometry::Transform::from_affine(to_map.to_local);
            check_coverage(&map, &to_map, bore.radius, half_length_mm, name)?;
            if map.peak_component_tesla() > MAX_FIELD_T {
                return Err(format!(
                    "field_map \"{name}\": a node's field reaches {} T, beyond {MAX_FIELD_T} T: {FIELD_BOUND} (is the map in tesla?)",
                    crate::text::number(map.peak_component_tesla())
                ));
            }
            Field::Map {
                map,
                to_map: Box::new(to_map),
                name: name.clone(),
            }
        }
        _ => return Err("give the field as field_t = TESLA (uniform over the bore) or field_map = NAME|FILE, one of them".into()),
    };
    // No pressure is vacuum (a scene variable may set the gas phase's 0).
    let gas = d
        .gas
        .as_ref()
        .filter(|g| g.pressure_mbar != 0.0)
        .map(|g| BufferGas::new(g).map_err(|e| format!("gas: {}", e.0)))
        .transpose()?;
    // The map's node spacing by default: the samples then lie on the map's
    // node planes across the bore (when its ends do, as BabyIAXO's), where
    // along a path parallel to the bore's axis the trilinear map is linear
    // between samples and Filon's rule is exact; a tilted path crosses the
    // cells' sides between samples, where the map has kinks. Halving this
    // step changes BabyIAXO's traced P by ~5e-5 (asked: < 1e-4,
    // tests/it/magnet.rs); every photon's P is within 1e-3 of the converged
    // integral (the same file).
    let step_mm = d.step_mm.unwrap_or(match &field {
        Field::Map { map, .. } => map.finest_spacing(),
        Field::Uniform { .. } => 1000.0,
    });
    let weight_scale = Magnet::peak_probability(&field, d.g_agamma, 2.0 * half_length_mm);
    let magnet = Magnet {
        bore: bore.name.to_string(),
        frame,
        half_length_mm,
        radius_mm: bore.radius,
        field,
        step_mm,
        gas,
        axion_mass_ev: d.axion_mass_ev,
        g_agamma_gev: d.g_agamma,
        scan_masses: d.masses_ev.clone(),
        weight_scale,
        campaign: None,
    };
    check_magnet(&magnet)?;
    let campaign = d
        .campaign
        .as_ref()
        .filter(|c| c.enabled)
        .map(|c| Campaign::plan(c, &magnet).map_err(|e| format!("campaign: {}", e.0)))
        .transpose()?;
    Ok(Magnet {
        campaign: campaign.map(Arc::new),
        ..magnet
    })
}

/// `m` with another coupling and path step (`traxer conversion`'s options),
/// checked as a scene's magnet is.
pub fn revised(m: &Magnet, g_agamma: Option<f64>, step_mm: Option<f64>) -> Result<Magnet, String> {
    let mut m = m.clone();
    if let Some(g) = g_agamma {
        check_coupling(g)?;
        m.g_agamma_gev = g;
        m.weight_scale = Magnet::peak_probability(&m.field, g, 2.0 * m.half_length_mm);
    }
    if let Some(step) = step_mm {
        check_step(step)?;
        m.step_mm = step;
    }
    check_magnet(&m)?;
    Ok(m)
}

/// The most masses of one table of P.
pub const MAX_PROBE_MASSES: usize = 100_000;

/// Checks the masses of a table of P (`traxer conversion --masses`, Python's
/// `conversion_probability`), named `key`, as a scene's mass scan is checked.
pub fn check_probe_masses(m: &Magnet, key: &str, masses: &[f64]) -> Result<(), String> {
    check_scan(
        key,
        masses,
        (
            MAX_PROBE_MASSES,
            "each is a row of the table at every energy",
        ),
    )?;
    let probe = Magnet {
        scan_masses: masses.to_vec(),
        ..m.clone()
    };
    check_representable(&probe).map_err(|e| e.replacen("masses_ev", key, 1))
}

/// A coupling is a number > 0.
fn check_coupling(g: f64) -> Result<(), String> {
    match g.is_finite() && g > 0.0 {
        true => Ok(()),
        false => Err(format!(
            "g_agamma = {}: a coupling is > 0 (GeV⁻¹)",
            crate::text::number(g)
        )),
    }
}

/// A path step is a length > 0 (its upper bound on the samples is
/// `check_magnet`'s).
fn check_step(step: f64) -> Result<(), String> {
    match step.is_finite() && step > 0.0 {
        true => Ok(()),
        false => Err(format!(
            "step_mm = {}: the path integral's step is a length > 0 (mm)",
            crate::text::number(step)
        )),
    }
}

/// The most samples of the field along one path: a 10 m bore at 1 mm steps,
/// a hundred times finer than any map's nodes need (Filon's rule is exact
/// for the trilinear map between node planes), and 10⁴ complex terms per
/// photon and mass.
pub const MAX_PATH_SAMPLES: f64 = 10_000.0;

/// The checks every magnet passes, however it was made: the path's samples
/// bounded, P far below one, and P a finite number on the axis.
fn check_magnet(m: &Magnet) -> Result<(), String> {
    if matches!(m.field, Field::Map { .. }) {
        let samples = 2.0 * m.half_length_mm / m.step_mm;
        if samples.is_nan() || samples > MAX_PATH_SAMPLES {
            return Err(format!(
                "step_mm = {}: {:.3e} samples of the field along each {} m path, more than {MAX_PATH_SAMPLES} (each photon integrates them for every mass); a step of {} mm or more (the default, the map's finest node spacing, is exact for paths along the axis)",
                crate::text::number(m.step_mm),
                samples,
                crate::text::number(2e-3 * m.half_length_mm),
                crate::text::number(2.0 * m.half_length_mm / MAX_PATH_SAMPLES)
            ));
        }
    }
    check_peak(m)?;
    check_representable(m)
}

/// Refuses a coupling whose P may come near one (see [`MAX_PEAK_PROBABILITY`]).
fn check_peak(m: &Magnet) -> Result<(), String> {
    if m.weight_scale <= MAX_PEAK_PROBABILITY {
        return Ok(());
    }
    let peak = match &m.field {
        Field::Uniform { tesla, .. } => *tesla,
        Field::Map { map, .. } => map.peak_tesla(),
    };
    Err(format!(
        "g_agamma = {:e} GeV⁻¹: P(a→γ) may reach (g_aγ B_peak L / 2)² = {:.3e} on the strongest path (B_peak = {:.4} T, L = {} m); traxer's P is the weak-mixing amplitude, which overstates the exact two-state P by about P/3 and passes 1 as g grows, so it refuses P above {MAX_PEAK_PROBABILITY:e} (an error below 4e-7). Helioscope couplings give P ~ 1e-19 (g_aγ = 1e-10): trace there and scale the counts by (g_aγ / 1e-10)⁴",
        m.g_agamma_gev,
        m.weight_scale,
        peak,
        crate::text::number(2e-3 * m.half_length_mm)
    ))
}

/// The most masses one scan takes: each is a whole image (and one per
/// process) on every sensor.
pub const MAX_SCAN_MASSES: usize = 1000;

/// The heaviest axion traxer converts (eV). P uses q = m_a² / 2E, the
/// relativistic limit of E − √(E² − m_a²), whose relative error m_a² / 4E² is
/// 2.5e-5 at 10 eV and 1 keV; a helioscope has lost all coherence long before
/// (CAST's heaviest helium setting reached 1.17 eV).
pub const MAX_MASS_EV: f64 = 10.0;
const MASS_BOUND: &str = "traxer converts axions up to 10 eV (q = m_a²/2E is the relativistic limit, good to m_a²/4E² = 2.5e-5 at 10 eV and 1 keV; no helioscope sees axions that heavy); masses are in eV (20 meV = 0.02)";

/// The strongest field traxer takes (T), far above any magnet's (the strongest
/// steady laboratory fields are about 45 T): a larger value is a map in other
/// units, or not a field.
pub const MAX_FIELD_T: f64 = 1000.0;
const FIELD_BOUND: &str =
    "no magnet's field (the strongest steady laboratory fields are about 45 T)";

/// The largest P(a→γ) bound traxer converts with (see `assemble`): the
/// weak-mixing P differs from the exact two-state sin²(g B L / 2) by P/3.
pub const MAX_PEAK_PROBABILITY: f64 = 1e-6;

/// Refuses a mass scan with a mass that is not a mass, one given twice, or
/// too many.
fn check_scan(key: &str, masses: &[f64], (max, each): (usize, &str)) -> Result<(), String> {
    if masses.len() > max {
        return Err(format!(
            "{key}: {} masses, more than {max} ({each})",
            masses.len()
        ));
    }
    if let Some(m) = masses.iter().find(|m| !(m.is_finite() && **m >= 0.0)) {
        return Err(format!(
            "{key}: {} is not a mass ≥ 0 (eV)",
            crate::text::number(*m)
        ));
    }
    if let Some(m) = masses.iter().find(|m| **m > MAX_MASS_EV) {
        return Err(format!("{key}: {}: {MASS_BOUND}", crate::text::number(*m)));
    }
    for (k, m) in masses.iter().enumerate() {
        if masses[..k].contains(m) {
            return Err(format!(
                "{key}: {} is given twice: give each mass once",
                crate::text::number(*m)
            ));
        }
    }
    Ok(())
}

/// Refuses a coupling or mass whose P is below the smallest normal double on
/// the bore's axis at 1, 4 and 10 keV (images of zeros, not a result), and
/// any mass of the scene or its scan whose P there is not a finite number
/// (the bounds above are meant to make that impossible; this is the proof).
fn check_representable(m: &Magnet) -> Result<(), String> {
    let (o, d) = crate::magnet::probe::lines(m, crate::magnet::probe::Where::Line([0.0, 0.0]))[0];
    let path = m.path_of(o, d);
    for (key, mass) in std::iter::once(("axion_mass_ev", m.axion_mass_ev))
        .chain(m.scan_masses.iter().map(|&x| ("masses_ev", x)))
    {
        for e in [1.0, 4.0, 10.0] {
            let p = path.probability(m, e, mass);
            if !(p.is_finite() && (0.0..=1.0).contains(&p)) {
                return Err(format!(
                    "{key}: at m_a = {} eV, P(a→γ) on the bore's axis at {e} keV is {}, not a probability: traxer cannot convert at this mass, coupling and gas",
                    crate::text::number(mass),
                    crate::text::number(p)
                ));
            }
        }
    }
    // No field across the bore on its axis: nothing converts, whatever the
    // coupling (a longitudinal map, or one turned the wrong way).
    let transverse = match &path {
        crate::magnet::ConversionPath::Uniform { b_ev2, .. } => *b_ev2 != 0.0,
        crate::magnet::ConversionPath::Sampled(f) => {
            f.samples.iter().any(|b| b[0] != 0.0 || b[1] != 0.0)
        }
    };
    if !transverse {
        let what = match &m.field {
            crate::magnet::Field::Map { name, .. } => format!("the field map {name}"),
            crate::magnet::Field::Uniform { .. } => "the uniform field".into(),
        };
        return Err(format!(
            "{what} has no component across the bore along its axis (B⊥ = 0 at every sample: a field along the bore, or a map turned the wrong way by field_map_transform): an axion converts only in a transverse field"
        ));
    }
    if [1.0, 4.0, 10.0]
        .iter()
        .all(|&e| path.probability(m, e, m.axion_mass_ev) < f64::MIN_POSITIVE)
    {
        return Err(format!(
            "P(a→γ) underflows (below 2.2e-308 on the bore's axis at 1–10 keV) for g_aγ = {:e} GeV⁻¹ and m_a = {} eV: the images would be zeros; P scales as g_aγ², so trace at a coupling near 1e-10 and scale the counts by (g_aγ / 1e-10)⁴ (production and conversion)",
            m.g_agamma_gev, m.axion_mass_ev
        ));
    }
    Ok(())
}

/// A uniform field of `b` tesla along `direction` (default +y).
fn uniform(b: f64, direction: Option<[f64; 3]>) -> Result<Field, String> {
    if !(b.is_finite() && b > 0.0) {
        return Err(format!(
            "field_t = {}: a field is > 0 (T)",
            crate::text::number(b)
        ));
    }
    if b > MAX_FIELD_T {
        return Err(format!(
            "field_t = {}: beyond {MAX_FIELD_T} T, {FIELD_BOUND}",
            crate::text::number(b)
        ));
    }
    let d = DVec3::from(direction.unwrap_or([0.0, 1.0, 0.0]));
    let Some(direction) = d.try_normalize() else {
        return Err("field_direction must not be zero".into());
    };
    if direction.z.abs() > 1.0 - 1e-12 {
        return Err("field_direction is along the bore's axis: an axial field converts no axions (give a transverse direction)".into());
    }
    Ok(Field::Uniform {
        tesla: b,
        direction,
    })
}

/// Refuses a map that does not hold the whole bore (a cylinder of `radius`
/// and `half_length` about the origin of the bore's frame), saying how far
/// the bore reaches beyond it.
fn check_coverage(
    map: &FieldMap,
    to_map: &crate::geometry::Transform,
    radius: f64,
    half_length: f64,
    name: &str,
) -> Result<(), String> {
    let (lo, hi) = (map.origin, map.end());
    let mut beyond = [0.0f64; 3];
    for k in 0..720 {
        let phi = k as f64 * std::f64::consts::TAU / 720.0;
        for z in [-half_length, half_length] {
            let p = to_map.point(DVec3::new(radius * phi.cos(), radius * phi.sin(), z));
            for a in 0..3 {
                beyond[a] = beyond[a].max(lo[a] - p[a]).max(p[a] - hi[a]);
            }
        }
    }
    // 1 µm: the map's nodes are read from text, the bore from the scene.
    if let Some(a) = (0..3).find(|&a| beyond[a] > 1e-3) {
        let axis = ["x", "y", "z"][a];
        return Err(format!(
            "field_map \"{name}\" does not cover the bore: the bore reaches {:.1} mm beyond the map in {axis} (the map spans {axis} = {} to {} mm; bore radius {radius} mm, length {} mm, in the map's frame); move the map with field_map_transform, or use a map that holds the bore",
            beyond[a], lo[a], hi[a], 2.0 * half_length
        ));
    }
    Ok(())
}

/// A magnet without a scene (`traxer conversion`): a uniform field over
/// `length_mm` in a bore of 1 m radius, or a field map filling the largest
/// cylinder its grid holds (its axis the grid's z axis, through the grid's
/// centre).
pub fn standalone(d: &MagnetDesc, length_mm: Option<f64>) -> Result<Magnet, String> {
    let identity = crate::geometry::Transform::default();
    match (&d.field_map, length_mm) {
        (Some(_), Some(_)) => {
            Err("a field map sets its own length (its z extent): leave out the length".into())
        }
        (None, None) => Err("a uniform field needs the magnet's length".into()),
        (None, Some(l)) if !(l.is_finite() && l > 0.0) => {
            Err(format!("length {l} mm: a length is > 0"))
        }
        (None, Some(l)) => {
            let bore = Bore {
                name: "bore",
                radius: 1000.0,
                z_start: -0.5 * l,
                z_end: 0.5 * l,
                to_world: identity,
            };
            build(d, &bore, Path::new("."), &|_| {})
        }
        (Some(name), None) => {
            let map = load_map(name, Path::new("."), &|_| {})?;
            let (lo, hi) = (map.origin, map.end());
            let centre: [f64; 3] = std::array::from_fn(|a| 0.5 * (lo[a] + hi[a]));
            let bore = Bore {
                name: "bore",
                radius: 0.5 * (hi[0] - lo[0]).min(hi[1] - lo[1]),
                z_start: lo[2] - centre[2],
                z_end: hi[2] - centre[2],
                to_world: identity,
            };
            let placed = MagnetDesc {
                field_map_transform: vec![Spanned::new(
                    0..0,
                    TransformStep::Translate(centre.map(|c| -c)),
                )],
                ..d.clone()
            };
            assemble(&placed, &bore, Some(map))
        }
    }
}
