//! Built-in assemblies (`[[assemblies]]`): one entry that expands into many
//! ordinary objects and the mirror materials they need, before objects are built.
//! Today the CAST LLNL telescope (`llnl`).

use super::desc::{ObjectDesc, SceneDesc, ShellLabel, TessellateDesc};
use super::error::{SceneError, SceneText};
use super::inputs::InputFiles;
use super::llnl::{LlnlTelescope, PartMaterial};
use super::materials::{MaterialDesc, MirrorDesc, SideDesc};
use super::placement::{RotateDesc, TransformStep};
use super::shapes::{MeshDesc, ShapeDesc};
use crate::xray::figure_error::FigureErrorSpec;
use serde::Deserialize;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

/// Built-in assemblies: many objects from one entry.
///
/// ```toml
/// [[assemblies]]
/// type = "llnl_telescope"        # the CAST LLNL telescope (data/llnl_telescope.toml)
/// name = "llnl"                  # prefix of its objects' names (default "llnl")
/// data = "my_telescope.toml"     # optional: other radii/coatings in the same form
/// azimuth_center = 0.0           # degrees: direction of the 30° segments' centre
/// coating = "perfect"            # optional: one coating for every shell
///                                # ("as_built", the default: each shell's own)
/// figure_error = "llnl_panter"   # optional: figure errors of every mirror
/// shell_axes = "coaxial"         # or "traxer": each shell's axis where TrAXer puts it
/// omit = ["rear_7"]              # optional: parts left out (stray-light studies):
///                                # a mirror with its glass, or one part ("rear_7_back")
/// tessellate = { segments = 500, rings = 20 }   # optional: meshes with smooth normals
/// mesh = "../meshes/llnl_telescope.glb"          # optional: the parts from a mesh file
/// transform = [ { translate = [0, 0, 0] } ]     # placement of the telescope frame
/// ```
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum AssemblyDesc {
    LlnlTelescope(LlnlTelescopeDesc),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LlnlTelescopeDesc {
    #[serde(default = "llnl_name")]
    pub name: String,
    #[serde(default)]
    pub data: Option<String>,
    #[serde(default)]
    pub azimuth_center: f64,
    #[serde(default)]
    pub coating: Option<String>,
    /// Figure errors of every mirror (preset name or inline parameters).
    #[serde(default)]
    pub figure_error: Option<FigureErrorSpec>,
    /// Microroughness scatter of every mirror (a PSD over a band, or "none");
    /// default none.
    #[serde(default)]
    pub roughness: Option<crate::xray::roughness::RoughnessSpec>,
    /// Where each shell's cone axis lies (see [`ShellAxes`]).
    #[serde(default)]
    pub shell_axes: ShellAxes,
    /// Parts left out, by their name without the assembly's prefix: "rear_7" is
    /// that mirror with its glass (back and edges), "rear_7_back" that part alone.
    #[serde(default)]
    pub omit: Vec<String>,
    #[serde(default)]
    pub tessellate: Option<TessellateDesc>,
    /// A mesh file holding the parts, named `<name>_<part>` as `traxer tessellate`
    /// writes them (meshes/llnl_telescope.glb), tessellated at azimuth_center 0.
    #[serde(default)]
    pub mesh: Option<String>,
    #[serde(default)]
    pub transform: Vec<TransformStep>,
}

/// Where the shells' cone axes lie.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum ShellAxes {
    /// On one common optical axis, as designed.
    #[default]
    Coaxial,
    /// As the predecessor TrAXer built the telescope: shell i's axis moved by
    /// [`LlnlTelescope::traxer_axis_offset`] along the segment centre, so the
    /// shells' foci no longer coincide. For comparing with TrAXer's images.
    Traxer,
}

fn llnl_name() -> String {
    "llnl".into()
}

/// A mirror material an assembly needs, written where the assembly is.
pub struct GeneratedMaterial {
    pub name: String,
    pub desc: MaterialDesc,
    pub span: Range<usize>,
}

/// Expands the `[[assemblies]]` of a description into ordinary objects (appended
/// to `desc.objects`); returns the mirror materials they use. Files an assembly
/// names are relative to `dir`.
pub fn expand(
    at: SceneText,
    dir: &Path,
    desc: &mut SceneDesc,
    inputs: &InputFiles,
) -> Result<Vec<GeneratedMaterial>, SceneError> {
    let mut materials = Vec::new();
    for a in std::mem::take(&mut desc.assemblies) {
        let span = a.span();
        match a.into_inner() {
            AssemblyDesc::LlnlTelescope(t) => {
                expand_llnl(at, dir, &t, span, &mut desc.objects, &mut materials, inputs)?
            }
        }
    }
    Ok(materials)
}

/// The telescope's shell data (shipped, or the scene's `data` file), checked.
fn llnl_data(
    at: SceneText,
    dir: &Path,
    t: &LlnlTelescopeDesc,
    span: Range<usize>,
    inputs: &InputFiles,
) -> Result<LlnlTelescope, SceneError> {
    let err = |m: String| at.error(span.clone(), m);
    let data = match &t.data {
        None => LlnlTelescope::shipped(),
        Some(f) => {
            let file = dir.join(f);
            let body = std::fs::read_to_string(&file)
                .map_err(|e| err(format!("llnl_telescope data {}: {e}", file.display())))?;
            inputs.note(&file);
            LlnlTelescope::from_toml(&body).map_err(|e| SceneError::from_toml(&file, &body, &e))?
        }
    };
    data.validate().map_err(|m| match &t.data {
        // The numbers are wrong in the user's data file: name it.
        Some(f) => err(format!(
            "llnl_telescope data {}: {m}",
            dir.join(f).display()
        )),
        None => err(format!("llnl_telescope data: {m}")),
    })?;
    Ok(data)
}

/// The material name of a part: the absorber, or the mirror material of its
/// coating (generated once per coating, with the telescope's figure error).
fn part_material(
    t: &LlnlTelescopeDesc,
    material: &PartMaterial,
    span: &Range<usize>,
    materials: &mut Vec<GeneratedMaterial>,
) -> String {
    match material {
        PartMaterial::Absorber => "absorber".to_string(),
        PartMaterial::Mirror(coating) => {
            let name = format!("{}_mirror_{coating}", t.name);
            if !materials.iter().any(|m| m.name == name) {
                materials.push(GeneratedMaterial {
                    name: name.clone(),
                    desc: MaterialDesc::Mirror(MirrorDesc {
                        side: SideDesc::Front,
                        coating: Some(coating.clone()),
                        figure_error: t.figure_error.clone(),
                        roughness: t.roughness.clone(),
                    }),
                    span: span.clone(),
                });
            }
            name
        }
    }
}

/// The LLNL telescope's parts as objects: analytic, tessellated, or read from a
/// mesh file that holds them (tessellated at azimuth 0 and rotated into place).
fn expand_llnl(
    at: SceneText,
    dir: &Path,
    t: &LlnlTelescopeDesc,
    span: Range<usize>,
    objects: &mut Vec<Spanned<ObjectDesc>>,
    materials: &mut Vec<GeneratedMaterial>,
    inputs: &InputFiles,
) -> Result<(), SceneError> {
    let err = |m: String| at.error(span.clone(), m);
    let data = llnl_data(at, dir, t, span.clone(), inputs)?;
    if !t.azimuth_center.is_finite() {
        return Err(err("azimuth_center must be a number (degrees)".into()));
    }
    if t.mesh.is_some() && t.tessellate.is_some() {
        return Err(err(
            "llnl_telescope: give `mesh` (parts from a file) or `tessellate`, not both".into(),
        ));
    }
    // "as_built" (or no `coating`) keeps each shell's own coating.
    let coating = t.coating.as_deref().filter(|c| *c != "as_built");
    // A mesh file was tessellated at azimuth 0 and is rotated instead.
    let azimuth = if t.mesh.is_some() {
        0.0
    } else {
        t.azimuth_center
    };
    let spanned = |v| Spanned::new(span.clone(), v);
    let parts = data.parts(azimuth, coating);
    let omitted = |part: &str| {
        t.omit.iter().any(|o| {
            part.strip_prefix(o.as_str())
                .is_some_and(|rest| rest.is_empty() || rest.starts_with('_'))
        })
    };
    if let Some(unknown) = t.omit.iter().find(|o| !parts.iter().any(|p| &p.name == *o)) {
        return Err(err(format!(
            "llnl_telescope: omit names `{unknown}`, which is no part of the telescope (parts are front_1, front_1_back, front_1_edge_far, front_1_edge_near, rear_1, …, rear_{}_edge_near)",
            data.shells.len()
        )));
    }
    for part in parts.into_iter().filter(|p| !omitted(&p.name)) {
        let material = part_material(t, &part.material, &span, materials);
        let is_mirror = matches!(part.material, PartMaterial::Mirror(_));
        let name = format!("{}_{}", t.name, part.name);
        let axis_offset = match t.shell_axes {
            ShellAxes::Coaxial => 0.0,
            ShellAxes::Traxer => data.traxer_axis_offset(part.shell),
        };
        let shift = |azimuth: f64| {
            let a = azimuth.to_radians();
            TransformStep::Translate([axis_offset * a.cos(), axis_offset * a.sin(), 0.0])
        };
        let (shape, own_transform) = match &t.mesh {
            None => (
                part.shape,
                part.transform.into_iter().chain([shift(azimuth)]).collect(),
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
            .collect();
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
                shell: Some(ShellLabel::Number(part.shell as i64 + 1)),
            },
        ));
    }
    Ok(())
}
