//! The magnet in its scene: the bore found among the scene's objects (before
//! they are built), the magnet built on the built bore for the scene (the
//! photon loop applies it to the Sun's photons), and the mass scan the sensors record. `magnet` reads the
//! `[magnet]` table and builds the field; this file is the scene build's
//! part of it (`scene::build` calls it).

use super::desc::{ObjectDesc, SceneDesc};
use super::error::{SceneError, SceneText};
use super::inputs::InputFiles;
use super::magnet;
use super::shapes::{CylinderDesc, ShapeDesc};
use super::Object;
use crate::magnet::Magnet;
use std::path::Path;
use std::sync::Arc;
use toml::Spanned;

/// The mass scan the sensors record: the `[magnet]` table's `masses_ev` when
/// the magnet is on (`enabled`, with its bore found).
pub(super) fn scan_masses(desc: &SceneDesc, enabled: bool) -> Vec<f64> {
    match (&desc.magnet, enabled) {
        (Some(m), true) => m.get_ref().masses_ev.clone(),
        _ => Vec::new(),
    }
}

/// The bore's index among the scene's objects and its cylinder, when the
/// scene has a magnet (found before the objects are built).
pub(super) fn find_bore(
    at: SceneText,
    desc: &SceneDesc,
) -> Result<Option<(usize, CylinderDesc)>, SceneError> {
    if let Some(m) = desc
        .magnet
        .as_ref()
        .filter(|m| !m.get_ref().enabled && !m.get_ref().masses_ev.is_empty())
    {
        return Err(at.error(
            m.span(),
            "magnet: masses_ev (a mass scan) needs the magnet on: enabled = false leaves the axions unconverted (on by default in the shipped Sun scenes: drop -D magnet=false)",
        ));
    }
    if let Some(m) = desc.magnet.as_ref().filter(|m| {
        let t = m.get_ref();
        !t.enabled && t.campaign.as_ref().is_some_and(|c| c.enabled)
    }) {
        return Err(at.error(
            m.span(),
            "magnet: a campaign (campaign.enabled) needs the magnet on: enabled = false leaves the axions unconverted (on by default in the shipped Sun scenes: drop -D magnet=false)",
        ));
    }
    let Some(m) = desc.magnet.as_ref().filter(|m| m.get_ref().enabled) else {
        return Ok(None);
    };
    let name = &m.get_ref().bore;
    let named = |o: &&Spanned<ObjectDesc>| o.get_ref().name.as_deref() == Some(name);
    let Some((k, object)) = desc.objects.iter().enumerate().find(|(_, o)| named(o)) else {
        let names: Vec<&str> = desc
            .objects
            .iter()
            .filter_map(|o| o.get_ref().name.as_deref())
            .take(12)
            .collect();
        return Err(at.error(
            m.span(),
            format!(
                "magnet: bore = \"{name}\" names no object (objects: {})",
                names.join(", ")
            ),
        ));
    };
    match object.get_ref().shape.get_ref() {
        ShapeDesc::Cylinder(c) if c.azimuth.is_none() => Ok(Some((k, c.clone()))),
        other => Err(at.error(
            m.span(),
            format!(
                "magnet: bore = \"{name}\" is a {}, not a bore: the field fills a whole cylinder (shape = {{ type = \"cylinder\", radius, z_start, z_end }}, no azimuth)",
                other.kind()
            ),
        )),
    }
}

/// Builds the magnet on the built bore, for the scene (whose Sun's photons it
/// converts).
pub(super) fn attach(
    at: SceneText,
    desc: &SceneDesc,
    bore: Option<(usize, CylinderDesc)>,
    objects: &[Object],
    sources: &[crate::source::Source],
    dir: &Path,
    inputs: &InputFiles,
) -> Result<Option<Arc<Magnet>>, SceneError> {
    let (Some(m), Some((k, c))) = (&desc.magnet, bore) else {
        return Ok(None);
    };
    let fail = |msg: String| at.error(m.span(), format!("magnet: {msg}"));
    let bore = magnet::Bore {
        name: &m.get_ref().bore,
        radius: c.radius,
        z_start: c.z_start,
        z_end: c.z_end,
        to_world: objects[k].transform,
    };
    let magnet =
        Arc::new(magnet::build(m.get_ref(), &bore, dir, &|p| inputs.note(p)).map_err(fail)?);
    match sources {
        [crate::source::Source::Sun(sun)] => {
            // One coupling produces and converts the Primakoff axions.
            if let Some((_, g)) = sun.productions.iter().find(|(p, _)| p == "primakoff") {
                if (g - magnet.g_agamma_gev).abs() > 1e-9 * g {
                    return Err(fail(format!(
                        "g_agamma = {:e} GeV⁻¹, but the Sun produces its Primakoff axions with g_agamma = {g:e}: one coupling makes and converts them (give both the same value, e.g. one scene variable)",
                        magnet.g_agamma_gev
                    )));
                }
            }
        }
        _ => {
            return Err(fail(
                "a magnet converts axions: the scene's source must be a `sun`".into(),
            ))
        }
    }
    Ok(Some(magnet))
}

/// What a scene's magnet makes doubtful, for the scene's warnings: a buffer
/// gas the magnet does not use, a helium setting that would be liquid, and
/// masses at which the magnet has lost its coherence (masses meant in meV,
/// or a gas far from every mass asked for).
pub(super) fn warnings(desc: &SceneDesc, magnet: Option<&Magnet>) -> Vec<String> {
    let mut out = Vec::new();
    let Some(table) = &desc.magnet else {
        return out;
    };
    let table = table.get_ref();
    if let Some(g) = table.gas.as_ref().filter(|g| g.pressure_mbar != 0.0) {
        if !table.enabled {
            out.push(format!(
                "magnet: the buffer gas ({} mbar at {} K) is ignored: the magnet is off (enabled = false), so the images are of axions before conversion; switch it on (on by default in the shipped Sun scenes: drop -D magnet=false)",
                crate::text::number(g.pressure_mbar),
                crate::text::number(g.temperature_k)
            ));
        }
        if g.mixture.len() == 1 && g.mixture.contains_key("He") {
            out.extend(crate::magnet::helium_vapour::liquid_helium(
                g.pressure_mbar,
                g.temperature_k,
            ));
        }
    }
    if let Some(m) = magnet {
        out.extend(coherence_warning(m));
    }
    out
}

/// Below this fraction of P at resonance (at 4 keV on the bore's axis) a
/// mass has lost the magnet's coherence: (qL/2)⁻² ≈ 1e-6 is qL/2 ≈ 1000.
const INCOHERENT: f64 = 1e-6;

/// Warns of masses far beyond coherence: P at 4 keV on the axis against P
/// at resonance (m_a = m_γ, the most this gas gives).
fn coherence_warning(m: &Magnet) -> Option<String> {
    let (o, d) = crate::magnet::probe::lines(m, crate::magnet::probe::Where::Line([0.0, 0.0]))[0];
    let path = m.path_of(o, d);
    let resonance = m.gas.as_ref().map_or(0.0, |g| g.photon_mass_ev());
    let best = path.probability(m, 4.0, resonance);
    let masses: Vec<f64> = std::iter::once(m.axion_mass_ev)
        .chain(m.scan_masses.iter().copied())
        .collect();
    let lost: Vec<f64> = masses
        .iter()
        .copied()
        .filter(|&x| path.probability(m, 4.0, x) < INCOHERENT * best)
        .collect();
    if lost.is_empty() || best <= 0.0 {
        return None;
    }
    let list = |v: &[f64]| {
        let shown: Vec<String> = v.iter().take(6).map(|x| crate::text::number(*x)).collect();
        format!(
            "{}{}",
            shown.join(", "),
            if v.len() > 6 { ", ..." } else { "" }
        )
    };
    let setting = match &m.gas {
        None => "in vacuum (coherent up to m_a ≈ 0.02 eV in a 10 m magnet)".to_string(),
        Some(g) => format!("with the buffer gas's m_γ = {:.4} eV", g.photon_mass_ev()),
    };
    Some(if lost.len() == masses.len() {
        format!(
            "magnet: every axion mass of the run ({} eV) is far from coherence {setting}: P at 4 keV is below {INCOHERENT:e} of its value at m_a = m_γ, so the images are nearly empty; masses are in eV (20 meV = 0.02), and a gas setting converts the masses near its m_γ",
            list(&masses)
        )
    } else {
        format!(
            "magnet: the axion masses {} eV are far from coherence {setting}: P at 4 keV is below {INCOHERENT:e} of its value at m_a = m_γ; masses are in eV (20 meV = 0.02)",
            list(&lost)
        )
    })
}
