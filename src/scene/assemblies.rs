//! Built-in assemblies (`[[assemblies]]`): one entry that expands into many
//! ordinary objects and the mirror materials they need, before objects are built.
//! Today nested grazing-incidence telescopes (`nested_telescope`, with the
//! CAST LLNL optic's `llnl_telescope` as a shorthand), their data read by
//! `telescope` and expanded by `telescope_parts`.

use super::assembly_desc::{AssemblyDesc, NestedTelescopeDesc, ShellAxes};
use super::desc::{ObjectDesc, SceneDesc, ShellLabel};
use super::error::{SceneError, SceneText};
use super::inputs::InputFiles;
use super::materials::{MaterialDesc, MirrorDesc, SideDesc};
use super::placement::{RotateDesc, TransformStep};
use super::shapes::{MeshDesc, ShapeDesc};
use super::telescope::{self, Profile, Telescope};
use super::telescope_parts::{Part, PartChoices, PartMaterial};
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

/// A mirror material an assembly needs, written where the assembly is.
pub struct GeneratedMaterial {
    pub name: String,
    pub desc: MaterialDesc,
    pub span: Range<usize>,
}

/// What expanding the assemblies gives besides their objects.
pub struct Expanded {
    /// The mirror materials the objects use.
    pub materials: Vec<GeneratedMaterial>,
    /// What is legal in a prescription but probably not meant, by assembly.
    pub warnings: Vec<String>,
}

/// Expands the `[[assemblies]]` of a description into ordinary objects (appended
/// to `desc.objects`). Files an assembly names are relative to `dir`.
pub fn expand(
    at: SceneText,
    dir: &Path,
    desc: &mut SceneDesc,
    inputs: &InputFiles,
) -> Result<Expanded, SceneError> {
    let mut materials = Vec::new();
    let mut warnings = Vec::new();
    for a in std::mem::take(&mut desc.assemblies) {
        let span = a.span();
        let (kind, t) = match a.into_inner() {
            AssemblyDesc::NestedTelescope(t) => ("nested_telescope", t),
            AssemblyDesc::LlnlTelescope(t) => ("llnl_telescope", t),
        };
        let site = Site { at, span, kind };
        let data = expand_telescope(&site, dir, &t, &mut desc.objects, &mut materials, inputs)?;
        warnings.extend(
            data.nesting_warnings()
                .into_iter()
                .map(|w| format!("{} `{}`: {w}", site.kind, data.name)),
        );
    }
    Ok(Expanded {
        materials,
        warnings,
    })
}

/// Where an assembly is written: for its messages.
struct Site<'a> {
    at: SceneText<'a>,
    span: Range<usize>,
    /// The assembly's type as written (`nested_telescope`, `llnl_telescope`).
    kind: &'static str,
}

impl Site<'_> {
    fn error(&self, message: String) -> SceneError {
        self.at
            .error(self.span.clone(), format!("{}: {message}", self.kind))
    }

    /// The shipped telescope's key an entry of this kind names by default.
    fn default_telescope(&self) -> Option<&'static str> {
        (self.kind == "llnl_telescope").then_some("llnl")
    }
}

/// The telescope's shell data (shipped, or the scene's `data` file), checked,
/// and the objects' name prefix.
fn telescope_data(
    site: &Site,
    dir: &Path,
    t: &NestedTelescopeDesc,
    inputs: &InputFiles,
) -> Result<(Telescope, String), SceneError> {
    let shipped = t.telescope.as_deref().or(site.default_telescope());
    // `telescope = "FILE.toml"` names a prescription file as `data` does, so
    // that one scene variable swaps a shipped optic for a user's own
    // (`-D telescope=my_optic.toml`).
    let (file, shipped) = match shipped {
        Some(name) if name.ends_with(".toml") && t.data.is_none() => (Some(name.to_string()), None),
        _ => (t.data.clone(), shipped),
    };
    let (data, key) = match (&file, shipped) {
        (Some(_), Some(_)) if t.telescope.is_some() => {
            return Err(
                site.error("give `telescope` (a shipped one) or `data` (a file), not both".into())
            )
        }
        (Some(f), _) => {
            let file = dir.join(f);
            let body = std::fs::read_to_string(&file)
                .map_err(|e| site.error(format!("data {}: {e}", file.display())))?;
            inputs.note(&file);
            let data =
                Telescope::from_toml(&body).map_err(|e| SceneError::from_toml(&file, &body, &e))?;
            data.validate()
                .map_err(|m| site.error(format!("data {}: {m}", file.display())))?;
            (data, "telescope".to_string())
        }
        (None, Some(name)) => (
            Telescope::shipped(name).map_err(|m| site.error(m.to_string()))?,
            name.to_string(),
        ),
        (None, None) => {
            let names: Vec<&str> = telescope::SHIPPED.iter().map(|(n, _)| *n).collect();
            return Err(site.error(format!(
                "name the telescope: `telescope = \"{}\"` (shipped: {}) or `data = \"FILE.toml\"`",
                names[0],
                names.join(", ")
            )));
        }
    };
    Ok((data, t.name.clone().unwrap_or(key)))
}

/// The material name of a part: the absorber, or the mirror material of its
/// coating and figure errors (generated once per pair, with the telescope's
/// figure errors where the scene gives them, else the shell's own).
fn part_material(
    t: &NestedTelescopeDesc,
    prefix: &str,
    part: &Part,
    span: &Range<usize>,
    materials: &mut Vec<GeneratedMaterial>,
) -> String {
    match &part.material {
        PartMaterial::Absorber => "absorber".to_string(),
        PartMaterial::Mirror(own) => {
            let coating = own.coating.as_deref().unwrap_or("perfect");
            let name = match part.shell {
                Some(shell) if own.keeps_own_under(&t.surface) => {
                    format!("{prefix}_mirror_{coating}_shell_{}", shell + 1)
                }
                _ => format!("{prefix}_mirror_{coating}"),
            };
            if !materials.iter().any(|m| m.name == name) {
                materials.push(GeneratedMaterial {
                    name: name.clone(),
                    desc: MaterialDesc::Mirror(MirrorDesc {
                        side: SideDesc::Front,
                        surface: own.under(&t.surface),
                    }),
                    span: span.clone(),
                });
            }
            name
        }
    }
}

/// The scene's choices about the parts, checked against the data.
fn part_choices<'a>(
    site: &Site,
    t: &'a NestedTelescopeDesc,
    data: &Telescope,
) -> Result<PartChoices<'a>, SceneError> {
    if !t.azimuth_center.is_finite() {
        return Err(site.error("azimuth_center must be a number (degrees)".into()));
    }
    if t.mesh.is_some() && t.tessellate.is_some() {
        return Err(site.error("give `mesh` (parts from a file) or `tessellate`, not both".into()));
    }
    if t.shell_axes == ShellAxes::Traxer
        && ((0..data.shells.len()).any(|i| data.span(i) >= 360.0) || data.profile != Profile::Cone)
    {
        return Err(site.error(
            "shell_axes = \"traxer\" moves each cone segment's axis along the segment's centre; this telescope's shells are not cone segments".into(),
        ));
    }
    let spider_distance = match (&data.spider, t.spider) {
        (None, Some(true)) => {
            return Err(site.error(
                "spider = true, but the telescope's data have no spider: set spider = false".into(),
            ))
        }
        // spider = false says the distance is not used (a scene whose optic is
        // a variable keeps its spider_distance).
        (None, None) if t.spider_distance.is_some() => {
            return Err(site.error(
                "spider_distance is given, but the telescope's data have no spider: leave it out, or set spider = false".into(),
            ))
        }
        (None, _) | (Some(_), Some(false)) => None,
        (Some(s), _) => match t.spider_distance.or(s.distance_mm) {
            Some(d) if d.is_finite() && d >= 0.0 => Some(d),
            Some(d) => {
                return Err(site.error(format!(
                    "spider_distance = {d}: give a distance ≥ 0 (mm in front of the entrance)"
                )))
            }
            None => {
                return Err(site.error(
                    "the telescope has an entrance spider whose distance in front of the entrance its data do not give: set spider_distance = MM, or spider = false".into(),
                ))
            }
        },
    };
    Ok(PartChoices {
        // A mesh file was tessellated at azimuth 0 and is rotated instead.
        azimuth_center_deg: if t.mesh.is_some() {
            0.0
        } else {
            t.azimuth_center
        },
        // "as_built" (or no `coating`) keeps each shell's own coating.
        coating: t.surface.coating.as_deref().filter(|c| *c != "as_built"),
        spider_distance_mm: spider_distance,
        central_stop: t.central_stop,
    })
}

/// The telescope's parts as objects: analytic, tessellated, or read from a
/// mesh file that holds them (tessellated at azimuth 0 and rotated into place).
fn expand_telescope(
    site: &Site,
    dir: &Path,
    t: &NestedTelescopeDesc,
    objects: &mut Vec<Spanned<ObjectDesc>>,
    materials: &mut Vec<GeneratedMaterial>,
    inputs: &InputFiles,
) -> Result<Telescope, SceneError> {
    let (data, prefix) = telescope_data(site, dir, t, inputs)?;
    let choices = part_choices(site, t, &data)?;
    let span = &site.span;
    let spanned = |v| Spanned::new(span.clone(), v);
    let parts = data.parts(&choices);
    let omitted = |part: &str| {
        t.omit.iter().any(|o| {
            part.strip_prefix(o.as_str())
                .is_some_and(|rest| rest.is_empty() || rest.starts_with('_'))
        })
    };
    if let Some(unknown) = t.omit.iter().find(|o| !parts.iter().any(|p| &p.name == *o)) {
        return Err(site.error(format!(
            "omit names `{unknown}`, which is no part of the telescope (parts are front_1, front_1_back, front_1_edge_far, front_1_edge_near, rear_1, …, rear_{}_edge_near)",
            data.shells.len()
        )));
    }
    for part in parts.into_iter().filter(|p| !omitted(&p.name)) {
        let material = part_material(t, &prefix, &part, span, materials);
        let is_mirror = matches!(part.material, PartMaterial::Mirror { .. });
        let name = format!("{prefix}_{}", part.name);
        let axis_offset = match (t.shell_axes, part.shell) {
            (ShellAxes::Traxer, Some(shell)) => data.traxer_axis_offset(shell),
            _ => 0.0,
        };
        let shift = |azimuth: f64| {
            let a = azimuth.to_radians();
            TransformStep::Translate([axis_offset * a.cos(), axis_offset * a.sin(), 0.0])
        };
        let (shape, own_transform) = match &t.mesh {
            None => (
                part.shape,
                part.transform
                    .into_iter()
                    .chain([shift(choices.azimuth_center_deg)])
                    .collect(),
            ),
            // The file holds the part already placed in the telescope frame,
            // with the segments centred on azimuth 0.
            Some(file) => (
                ShapeDesc::Mesh(MeshDesc {
                    file: file.clone(),
                    part: Some(name.clone()),
                }),
                vec![
                    shift(0.0),
                    TransformStep::Rotate(RotateDesc {
                        axis: [0.0, 0.0, 1.0],
                        angle: t.azimuth_center,
                    }),
                ],
            ),
        };
        let transform = own_transform
            .iter()
            .chain(&t.transform)
            .map(|s| spanned(s.clone()))
            .collect::<Vec<_>>();
        let meshed = t.tessellate.is_some() || t.mesh.is_some();
        objects.push(Spanned::new(
            span.clone(),
            ObjectDesc {
                name: Some(name),
                shape: Spanned::new(span.clone(), shape),
                material: Spanned::new(span.clone(), material),
                transform,
                tessellate: t.tessellate.map(|r| Spanned::new(span.clone(), r)),
                smooth_normals: meshed && is_mirror,
                appearance: None,
                stage: part.stage,
                shell: part.shell.map(|s| ShellLabel::Number(s as i64 + 1)),
                part_of: Some(prefix.to_string()),
            },
        ));
    }
    Ok(data)
}
