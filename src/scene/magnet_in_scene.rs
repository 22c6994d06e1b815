//! The magnet in its scene: the bore found among the scene's objects (before
//! they are built), the magnet built on the built bore and handed to the
//! scene's Sun, and the mass scan the sensors record. `magnet` reads the
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
            "magnet: masses_ev (a mass scan) needs the magnet on: enabled = false leaves the axions unconverted (-D magnet=true in the shipped scenes)",
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

/// Builds the magnet on the built bore and hands it to the scene's Sun.
pub(super) fn attach(
    at: SceneText,
    desc: &SceneDesc,
    bore: Option<(usize, CylinderDesc)>,
    objects: &[Object],
    sources: &mut [crate::source::Source],
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
            sun.magnet = Some(magnet.clone())
        }
        _ => {
            return Err(fail(
                "a magnet converts axions: the scene's source must be a `sun`".into(),
            ))
        }
    }
    Ok(Some(magnet))
}
