//! The build step: a parsed scene description checked and instantiated, concern by
//! concern (materials, assemblies, objects, sources, reflectivity tables, the
//! Embree scene, cameras and sky), into a complete, immutable [`Scene`].

use super::assemblies;
use super::error::{SceneError, SceneText};
use super::inputs::InputFiles;
use super::load::LoadedScene;
use super::materials::Materials;
use super::objects::ObjectBuilder;
use super::placement::transform;
use super::shapes::ShapeDesc;
use super::{embree_binding, load, Camera, Representation, Scene, Sky};
use crate::embree::Device;
use crate::geometry::{Resolution, Shape, Transform};
use crate::source::Source;
use crate::xray::figure_presets::FigureErrorLibrary;
use crate::xray::{Coating, CoatingLibrary, Foil, ReflectivityTable};
use std::collections::BTreeMap;
use std::path::Path;

/// Largest grazing angle (rad) kept in reflectivity tables (X-ray telescopes work
/// below ~3°); steeper reflections are evaluated directly.
/// Grazing angles up to which reflectivity is tabulated (beyond: evaluated).
pub const TABLE_THETA_MAX: f64 = 4.0 * std::f64::consts::PI / 180.0;

/// Builds the scene read from `path` with the analytic objects represented as
/// `representation` says.
pub(super) fn build(
    device: &Device,
    path: &Path,
    loaded: LoadedScene,
    representation: Representation,
) -> Result<Scene, SceneError> {
    let LoadedScene {
        text,
        original,
        sha256,
        overrides,
        vars,
        mut desc,
    } = loaded;
    let at = SceneText {
        path,
        text: &text,
        original: &original,
        overrides: &overrides,
    };
    let max_interactions = max_interactions(at, &desc)?;
    let figure_errors = FigureErrorLibrary::shipped().merged(&desc.figure_errors);
    let mut materials = Materials::new(
        std::mem::take(&mut desc.materials),
        scene_coatings(&desc),
        figure_errors.clone(),
    );
    let dir = path.parent().unwrap_or(Path::new("."));
    let inputs = InputFiles::default();
    let expanded = assemblies::expand(at, dir, &mut desc, &inputs)?;
    for m in expanded.materials {
        materials.add_generated(&m.name, m.desc, m.span);
    }

    let sources = build_sources(at, &desc, dir, &inputs)?;
    let bore = super::magnet_in_scene::find_bore(at, &desc)?;
    (materials.processes, materials.masses) = (
        sources
            .first()
            .map(|s| s.process_names())
            .unwrap_or_default(),
        super::magnet_in_scene::scan_masses(&desc, bore.is_some()),
    );
    let mut objects = Vec::new();
    let mut builder = ObjectBuilder::new(at, dir, representation, &inputs);
    let mut embree = device.scene::<embree_binding::AnalyticPieces>();
    let mut triangle_count = 0;
    for (index, od) in std::mem::take(&mut desc.objects).into_iter().enumerate() {
        let id = u32::try_from(index).map_err(|_| at.whole("too many objects"))?;
        let object = builder.build(index, od, &mut materials)?;
        triangle_count +=
            embree_binding::attach(&mut embree, id, &object.geometry).map_err(|e| {
                at.whole(format!("object `{}`: {e}", object.name))
                    .of_machine()
            })?;
        objects.push(object);
    }
    let magnet = super::magnet_in_scene::attach(at, &desc, bore, &objects, &sources, dir, &inputs)?;
    if let Some((name, span)) = materials.unused() {
        return Err(at.error(span, format!("material `{name}` is not used by any object")));
    }
    let reflectivity = reflectivity_tables(at, &materials.coatings, &sources)?;
    check_foils(at, &materials.foils, &sources)?;
    check_gas(at, &materials.sensors, &sources)?;
    let (embree, shell_search, bvh_seconds) = commit(at, device, embree, &objects)?;
    let (cameras, sky) = cameras_and_sky(at, &desc, &sources)?;
    let magnet_warnings = super::magnet_in_scene::warnings(&desc, magnet.as_deref());
    let warnings = [expanded.warnings, builder.warnings, magnet_warnings].concat();
    let inputs = inputs.hashed(dir).map_err(|m| at.whole(m))?;
    Ok(Scene {
        representation,
        path: path.to_path_buf(),
        title: desc.title.clone(),
        text_sha256: sha256,
        inputs,
        overrides: overrides.clone(),
        vars,
        objects,
        figure_errors,
        sensors: materials.sensors,
        foils: materials.foils,
        roughness: materials.roughness,
        sources,
        magnet,
        max_interactions,
        reflectivity,
        embree,
        shell_search,
        cameras,
        sky,
        warnings,
        bvh_seconds,
        triangle_count,
    })
}

/// Builds Embree's BVH over every object (timed, for `traxer bench`) and the
/// shell search that the photon loop asks instead where the scene has nested
/// shells.
fn commit(
    at: SceneText,
    device: &Device,
    embree: crate::embree::SceneBuilder<embree_binding::AnalyticPieces>,
    objects: &[super::Object],
) -> Result<Built, SceneError> {
    let bvh_start = std::time::Instant::now();
    let embree = embree.commit().map_err(|e| {
        at.whole(format!("Embree could not build the scene: {e}"))
            .of_machine()
    })?;
    let bvh_seconds = bvh_start.elapsed().as_secs_f64();
    let shell_search = embree_binding::ShellSearch::of(device, objects).map_err(|e| {
        at.whole(format!(
            "Embree could not build the scene without its shells: {e}"
        ))
        .of_machine()
    })?;
    Ok((embree, shell_search, bvh_seconds))
}

/// Embree's scene of every object, the shell search, and the BVH's build time.
type Built = (
    crate::embree::CommittedScene<embree_binding::AnalyticPieces>,
    Option<embree_binding::ShellSearch>,
    f64,
);

/// The sources, with the files they read noted; a Sun must be alone.
/// `max_interactions`, at least 1.
fn max_interactions(at: SceneText, desc: &super::desc::SceneDesc) -> Result<u32, SceneError> {
    let n = *desc.max_interactions.get_ref();
    if n == 0 {
        return Err(at.error(
            desc.max_interactions.span(),
            "max_interactions must be at least 1",
        ));
    }
    Ok(n)
}

fn build_sources(
    at: SceneText,
    desc: &super::desc::SceneDesc,
    dir: &Path,
    inputs: &InputFiles,
) -> Result<Vec<Source>, SceneError> {
    let sources = desc
        .sources
        .iter()
        .map(|s| s.get_ref().build(dir).map_err(|m| at.error(s.span(), m)))
        .collect::<Result<Vec<_>, _>>()?;
    for s in &desc.sources {
        for file in s.get_ref().files(dir) {
            inputs.note(&file);
        }
    }
    if sources.len() > 1 {
        if let Some(k) = sources.iter().position(|s| matches!(s, Source::Sun(_))) {
            return Err(at.error(
                desc.sources[k].span(),
                "a `sun` source must be the scene's only source: its images are in axions per second, which other sources' weights are not",
            ));
        }
    }
    Ok(sources)
}

/// The named cameras and the sky of visible-light renders (a Sun source shows
/// in the sky where it stands, as large as it looks).
fn cameras_and_sky(
    at: SceneText,
    desc: &super::desc::SceneDesc,
    sources: &[Source],
) -> Result<(BTreeMap<String, Camera>, Sky), SceneError> {
    let mut cameras = BTreeMap::new();
    for (name, c) in &desc.cameras {
        let camera = c
            .get_ref()
            .build()
            .map_err(|m| at.error(c.span(), format!("camera `{name}`: {m}")))?;
        cameras.insert(name.clone(), camera);
    }
    let sky_desc = desc
        .sky
        .as_ref()
        .map(|k| k.get_ref().clone())
        .unwrap_or_default();
    let mut sky = match &desc.sky {
        None => Default::default(),
        Some(k) => k.get_ref().build().map_err(|m| at.error(k.span(), m))?,
    };
    for source in sources {
        if let Source::Sun(sun) = source {
            sky = sky.with_sun(sun.toward_sun, sun.angular_radius(), &sky_desc);
        }
    }
    Ok((cameras, sky))
}

/// Lowest and highest energy the sources emit (keV); (∞, −∞) without sources.
fn source_energy_range(sources: &[Source]) -> (f64, f64) {
    sources
        .iter()
        .map(|s| s.energy_range())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (lo, hi)| {
            (a.min(lo), b.max(hi))
        })
}

/// Every foil must know its attenuation at every energy the sources emit.
fn check_foils(at: SceneText, foils: &[Foil], sources: &[Source]) -> Result<(), SceneError> {
    let (e_min, e_max) = source_energy_range(sources);
    if sources.is_empty() {
        return Ok(());
    }
    for f in foils {
        for e in [e_min, e_max] {
            f.attenuation_per_nm(e).map_err(|err| {
                at.whole(format!(
                    "foil of `{}`: the sources emit energies it cannot describe: {err}",
                    f.material.name
                ))
            })?;
        }
    }
    Ok(())
}

/// Every detector gas must know its photoabsorption at every energy the
/// sources emit: outside the Henke tables it would convert nothing, and an
/// all-zero image is not a result.
fn check_gas(
    at: SceneText,
    sensors: &[crate::sensor::SensorSpec],
    sources: &[Source],
) -> Result<(), SceneError> {
    let (e_min, e_max) = source_energy_range(sources);
    if sources.is_empty() {
        return Ok(());
    }
    for s in sensors {
        let Some(gas) = &s.gas else { continue };
        for e in [e_min, e_max] {
            gas.attenuation_per_mm(e).map_err(|err| {
                at.whole(format!(
                    "sensor `{}`: the sources emit {}–{} keV, but its gas ({}) knows its photoabsorption only within the Henke tables: {err}; limit the sources' energies (e.g. energy_range of a sun source, or the band or table of a lab source)",
                    s.name,
                    crate::text::number(e_min),
                    crate::text::number(e_max),
                    gas.material.name
                ))
            })?;
        }
    }
    Ok(())
}

/// The shipped coatings with the scene's own, on the scene's table of optical
/// constants.
fn scene_coatings(desc: &super::desc::SceneDesc) -> CoatingLibrary {
    CoatingLibrary::shipped().merged(&CoatingLibrary {
        materials: desc.optical_materials.clone(),
        coatings: desc.coatings.clone(),
        mirror_constants: desc.mirror_optical_constants,
    })
}

/// One reflectivity table per coating, over the energies the sources emit.
fn reflectivity_tables(
    at: SceneText,
    coatings: &[Coating],
    sources: &[Source],
) -> Result<Vec<ReflectivityTable>, SceneError> {
    let (e_min, e_max) = source_energy_range(sources);
    coatings
        .iter()
        .map(|c| {
            ReflectivityTable::cached(c, e_min, e_max, TABLE_THETA_MAX).map_err(|e| {
                at.whole(format!(
                    "coating `{}`: the sources emit energies it cannot describe: {e}",
                    c.name
                ))
            })
        })
        .collect()
}

/// An analytic object of a scene file, for `traxer tessellate`.
pub struct NamedShape {
    pub name: String,
    pub shape: Shape,
    pub transform: Transform,
    /// The object's own `tessellate` setting, if it has one.
    pub resolution: Option<Resolution>,
}

/// The analytic objects of a scene file, assemblies expanded (meshes are skipped),
/// without building it.
pub fn analytic_shapes(path: &Path, overrides: &[String]) -> Result<Vec<NamedShape>, SceneError> {
    let mut loaded = load::read(path, overrides)?;
    let at = SceneText {
        path,
        text: &loaded.text,
        original: &loaded.original,
        overrides: &loaded.overrides,
    };
    // Assemblies (the LLNL telescope) become their objects, as in a trace.
    let dir = path.parent().unwrap_or(Path::new("."));
    assemblies::expand(at, dir, &mut loaded.desc, &InputFiles::default())?;
    let mut out = Vec::new();
    for (index, od) in loaded.desc.objects.iter().enumerate() {
        let od = od.get_ref();
        let Some(shape) = od.shape.get_ref().analytic() else {
            continue;
        };
        out.push(NamedShape {
            name: od.name.clone().unwrap_or_else(|| format!("object{index}")),
            shape: shape.map_err(|m| at.error(od.shape.span(), m))?,
            transform: transform(&od.transform).map_err(|(s, m)| at.error(s, m))?,
            resolution: od
                .tessellate
                .as_ref()
                .map(|t| Resolution::from(*t.get_ref())),
        });
    }
    Ok(out)
}

/// Parses a shape written inline, e.g. `type = "cone", radius_start = 63.2, ...`
/// (the inside of a scene file's `shape = { ... }`).
pub fn inline_shape(text: &str) -> Result<Shape, SceneError> {
    #[derive(serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Wrapper {
        shape: toml::Spanned<ShapeDesc>,
    }
    let path = Path::new("--shape");
    let full = format!("shape = {{ {text} }}");
    let w: Wrapper =
        toml::from_str(&full).map_err(|e| SceneError::new(path, None, e.message().to_string()))?;
    let at = SceneText {
        path,
        text: &full,
        original: &full,
        overrides: &[],
    };
    match w.shape.get_ref().analytic() {
        None => Err(at.whole("a mesh is already a mesh; give an analytic shape")),
        Some(shape) => shape.map_err(|m| at.error(w.shape.span(), m)),
    }
}
