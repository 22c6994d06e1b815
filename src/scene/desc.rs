//! The scene file format's top level: plain serde data, exactly as written in the
//! TOML file. The tables of each closed set live next to the code that checks
//! them (`materials`, `shapes`, `placement`, `appearance`, `camera`,
//! `assemblies`, `crate::source`). Every type's documentation is its user
//! documentation (see docs/scene-format.md for the assembled reference). Units:
//! millimetres, keV, degrees.
//!
//! Data flow: `load` parses text into a [`SceneDesc`]; `build` validates it and
//! turns it into a `Scene`.

use super::appearance::{AppearanceDesc, SkyDesc};
use super::assembly_desc::AssemblyDesc;
use super::camera::CameraDesc;
use super::materials::MaterialDesc;
use super::placement::TransformStep;
use super::shapes::{ShapeDesc, TessellateDesc};
use crate::history::MirrorStage;
use crate::source::SourceDesc;
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

/// A whole scene file.
///
/// ```toml
/// max_interactions = 16        # optional, default 16
/// [vars]                       # optional: defaults for -D name=value
/// energy = 1.49
/// [materials.detector]
/// type = "sensor"
/// size = [14.0, 14.0]
/// pixels = [1000, 1000]
/// [[objects]]  ...
/// [[sources]]  ...
/// ```
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// What the scene is, for people: the title of its figures and plots
    /// (default: the file's name).
    #[serde(default)]
    pub title: Option<String>,
    /// Scene variables (see `vars`); already substituted when this is parsed.
    #[serde(default)]
    pub vars: toml::Table,
    /// Interactions after which a photon is given up (counted in the statistics).
    #[serde(default = "default_max_interactions")]
    pub max_interactions: Spanned<u32>,
    /// Named materials. `mirror` (perfect, both sides) and `absorber` exist
    /// without being declared.
    #[serde(default)]
    pub materials: BTreeMap<String, Spanned<MaterialDesc>>,
    #[serde(default)]
    pub objects: Vec<Spanned<ObjectDesc>>,
    #[serde(default)]
    pub sources: Vec<Spanned<SourceDesc>>,
    /// Built-in assemblies (the LLNL telescope), expanded into objects.
    #[serde(default)]
    pub assemblies: Vec<Spanned<AssemblyDesc>>,
    /// X-ray optical materials (formula or mass fractions, density) for coatings,
    /// added to those of data/coatings.toml.
    #[serde(default)]
    pub optical_materials: BTreeMap<String, crate::xray::coating::MaterialEntry>,
    /// Coatings, added to those of data/coatings.toml (same form).
    #[serde(default)]
    pub coatings: BTreeMap<String, crate::xray::coating::CoatingEntry>,
    /// The helioscope's magnet: the field in a bore that converts the Sun's
    /// axions (see `scene::magnet`).
    #[serde(default)]
    pub magnet: Option<Spanned<super::magnet::MagnetDesc>>,
    /// The table of atomic scattering factors the mirrors' coatings take:
    /// `henke` (default) or `chantler` (the reflectivity-model systematic).
    #[serde(default)]
    pub mirror_optical_constants: crate::xray::elements::OpticalConstants,
    /// Figure-error presets, added to those of data/figure_errors.toml.
    #[serde(default)]
    pub figure_errors: BTreeMap<String, crate::xray::figure_presets::FigureErrorEntry>,
    /// Named cameras for visible-light renders (`traxer render --camera NAME`).
    #[serde(default)]
    pub cameras: BTreeMap<String, Spanned<CameraDesc>>,
    /// The sky that lights visible-light renders.
    #[serde(default)]
    pub sky: Option<Spanned<SkyDesc>>,
}

fn default_max_interactions() -> Spanned<u32> {
    Spanned::new(0..0, 16)
}

/// One object: a shape, where it is, what it is made of.
///
/// ```toml
/// [[objects]]
/// name = "front shell 1"                  # optional; used in statistics and file names
/// material = "shell"
/// shape = { type = "cone", radius_start = 63.24, z_start = 229.0,
///                          radius_end = 60.91, z_end = 2.0, azimuth = [-15.0, 15.0] }
/// transform = [ { rotate = { axis = [0, 0, 1], angle = 14.0 } },
///               { translate = [0, 0, 10.0] } ]   # applied in this order
/// tessellate = { segments = 500, rings = 20 }     # optional: trace a mesh of it instead
/// smooth_normals = true                           # meshes: reflect on interpolated normals
/// ```
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDesc {
    #[serde(default)]
    pub name: Option<String>,
    pub shape: Spanned<ShapeDesc>,
    pub material: Spanned<String>,
    #[serde(default)]
    pub transform: Vec<Spanned<TransformStep>>,
    #[serde(default)]
    pub tessellate: Option<Spanned<TessellateDesc>>,
    #[serde(default)]
    pub smooth_normals: bool,
    /// Visible-light look (renders only); default from the material.
    #[serde(default)]
    pub appearance: Option<Spanned<AppearanceDesc>>,
    /// Photon histories: `stage = "front"` or `"rear"` (primary or secondary
    /// mirror), `shell = 7` or `"outer"` (fluxes are summed per shell).
    #[serde(default)]
    pub stage: Option<MirrorStage>,
    #[serde(default)]
    pub shell: Option<ShellLabel>,
    /// The scene entry the object comes from, when that is not the object
    /// itself: a telescope's parts name their telescope (render labels).
    #[serde(skip)]
    pub part_of: Option<String>,
}

/// A shell's number or name.
#[derive(Debug, Deserialize, Clone)]
#[serde(untagged)]
pub enum ShellLabel {
    Number(i64),
    Name(String),
}

impl ShellLabel {
    pub fn text(&self) -> String {
        match self {
            ShellLabel::Number(n) => n.to_string(),
            ShellLabel::Name(s) => s.clone(),
        }
    }
}
