//! The scene file format: plain serde data, exactly as written in the TOML file.
//! Every type's documentation is its user documentation (see docs/scene-format.md
//! for the assembled reference). Units: millimetres, keV, degrees.
//!
//! Data flow: `load` parses text into a [`SceneDesc`]; `build` validates it and
//! turns it into a `Scene`.

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
    /// Figure-error presets, added to those of data/figure_errors.toml.
    #[serde(default)]
    pub figure_errors: BTreeMap<String, crate::figure_error::FigureErrorEntry>,
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

/// What happens to a photon that hits an object.
///
/// ```toml
/// [materials.shell]
/// type = "mirror"      # specular reflection
/// side = "front"       # "front", "back" or "both" (default): the other side absorbs
/// coating = "llnl_recipe_3"   # optional: weight × R(E, θ); without it R = 1
///
/// [materials.baffle]
/// type = "absorber"
///
/// [materials.detector]
/// type = "sensor"      # records and absorbs every photon
/// size = [14.0, 14.0]  # mm, along the object's local x and y, centred on its origin
/// pixels = [1000, 1000]
/// energy_bins = [0.5, 10.0, 19]   # optional: keV min, max, number of bands
/// focal_length = 1500.0  # optional, mm: HPD etc. also in arcseconds
/// ```
#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum MaterialDesc {
    Mirror(MirrorDesc),
    Absorber(AbsorberDesc),
    Sensor(SensorDesc),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MirrorDesc {
    #[serde(default)]
    pub side: SideDesc,
    /// Name of a coating (data/coatings.toml or this file's `[coatings]`); without
    /// one the mirror is perfect (R = 1).
    #[serde(default)]
    pub coating: Option<String>,
    /// Figure errors: a preset name (data/figure_errors.toml or this file's
    /// `[figure_errors]`, "none") or the parameters inline; default none.
    #[serde(default)]
    pub figure_error: Option<crate::figure_error::FigureErrorSpec>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AbsorberDesc {}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorDesc {
    pub size: [f64; 2],
    pub pixels: [u32; 2],
    /// Optional energy binning `[min, max, count]` (keV): the image gets an energy
    /// axis, one image per band.
    #[serde(default)]
    pub energy_bins: Option<(f64, f64, u32)>,
    /// Focal length (mm) of the optics in front of the sensor: image-quality
    /// diameters are then also given in arcseconds, 2·atan(r/f).
    #[serde(default)]
    pub focal_length: Option<f64>,
}

/// Which side of a surface reflects. The front is the side the shape's normal
/// points to: towards the axis for cones, cylinders, paraboloids and hyperboloids;
/// local +z for disks and rectangles; outwards for boxes and spheres; for meshes
/// the side from which the triangles are counter-clockwise.
#[derive(Debug, Deserialize, Default, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SideDesc {
    Front,
    Back,
    #[default]
    Both,
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
}

/// A camera for visible-light renders.
///
/// ```toml
/// [cameras.overview]
/// look_from = [600.0, 300.0, 800.0]
/// look_at = [0.0, 0.0, -700.0]
/// up = [0.0, 1.0, 0.0]      # default +y
/// vfov = 30.0               # vertical field of view, degrees
/// ```
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    pub look_from: [f64; 3],
    pub look_at: [f64; 3],
    #[serde(default = "y_up")]
    pub up: [f64; 3],
    pub vfov: f64,
}

fn y_up() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}

/// The sky of visible-light renders: `zenith` colour along `up`, `horizon`
/// colour below, blended linearly (the same colour twice: a uniform sky).
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct SkyDesc {
    #[serde(default = "sky_zenith")]
    pub zenith: [f64; 3],
    #[serde(default = "sky_horizon")]
    pub horizon: [f64; 3],
    #[serde(default = "y_up")]
    pub up: [f64; 3],
}

fn sky_zenith() -> [f64; 3] {
    [0.5, 0.7, 1.0]
}

fn sky_horizon() -> [f64; 3] {
    [1.0, 1.0, 1.0]
}

/// Visible-light appearance of an object.
///
/// ```toml
/// appearance = { type = "diffuse", color = [0.8, 0.3, 0.3] }
/// appearance = { type = "metal", color = [0.9, 0.9, 0.9], roughness = 0.05 }
/// appearance = { type = "glass", ior = 1.5 }
/// appearance = { type = "emitting", color = [4.0, 4.0, 4.0] }
/// ```
#[derive(Debug, Deserialize, Clone)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum AppearanceDesc {
    Diffuse {
        color: [f64; 3],
    },
    Metal {
        color: [f64; 3],
        #[serde(default)]
        roughness: f64,
    },
    Glass {
        ior: f64,
    },
    Emitting {
        color: [f64; 3],
    },
}

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
    pub figure_error: Option<crate::figure_error::FigureErrorSpec>,
    #[serde(default)]
    pub tessellate: Option<TessellateDesc>,
    /// A mesh file holding the parts, named `<name>_<part>` as `traxer tessellate`
    /// writes them (meshes/llnl_telescope.glb), tessellated at azimuth_center 0.
    #[serde(default)]
    pub mesh: Option<String>,
    #[serde(default)]
    pub transform: Vec<TransformStep>,
}

fn llnl_name() -> String {
    "llnl".into()
}

/// Tessellation resolution of an analytic shape.
#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub struct TessellateDesc {
    /// Divisions around the azimuth range (x divisions for a rectangle).
    pub segments: usize,
    /// Divisions along the axis (radial for a disk, y for a rectangle,
    /// pole to pole for a sphere).
    pub rings: usize,
}

impl From<TessellateDesc> for crate::geometry::Resolution {
    fn from(t: TessellateDesc) -> Self {
        crate::geometry::Resolution {
            segments: t.segments,
            rings: t.rings,
        }
    }
}

/// A placement step; a list of them is applied in order (the first one acts on
/// the shape's local frame first).
///
/// ```toml
/// { translate = [x, y, z] }
/// { rotate = { axis = [x, y, z], angle = 30.0 } }   # degrees, right-handed
/// { scale = 2.0 }  or  { scale = [sx, sy, sz] }
/// ```
#[derive(Debug, Deserialize, Clone)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum TransformStep {
    Translate([f64; 3]),
    Rotate(RotateDesc),
    Scale(ScaleDesc),
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct RotateDesc {
    pub axis: [f64; 3],
    /// Degrees.
    pub angle: f64,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(untagged)]
pub enum ScaleDesc {
    Uniform(f64),
    PerAxis([f64; 3]),
}

/// The shapes. Analytic ones are intersected exactly in f64; `mesh` imports a
/// file. Surfaces of revolution share the local z axis; `azimuth = [from, to]`
/// (degrees from +x towards +y) limits them to a segment (default: full circle).
///
/// ```toml
/// shape = { type = "cone", radius_start = 63.24, z_start = 229.0, radius_end = 60.91, z_end = 2.0 }
/// shape = { type = "cylinder", radius = 21.5, z_start = 0.0, z_end = 9260.0 }
/// shape = { type = "paraboloid", focal_length = 4.0, z_start = 1500.0, z_end = 1600.0 }
///     # r² = 4q(z + q): focus at the local origin, opening towards +z
/// shape = { type = "hyperboloid", semi_axis_a = 700.0, semi_axis_b = 30.0, z_start = 760.0, z_end = 850.0 }
///     # z²/a² − r²/b² = 1, centred at the origin, foci at z = ±√(a² + b²)
/// shape = { type = "disk", radius = 10.0, inner_radius = 2.0 }    # in local z = 0, facing +z
/// shape = { type = "rectangle", size = [14.0, 14.0] }             # in local z = 0, facing +z
/// shape = { type = "box", size = [1.0, 2.0, 3.0] }                # centred on the origin
/// shape = { type = "sphere", radius = 5.0 }
/// shape = { type = "mesh", file = "../meshes/bore.gltf" }         # .gltf, .glb or .obj
/// ```
#[derive(Debug, Deserialize, Clone)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ShapeDesc {
    Cone(ConeDesc),
    Cylinder(CylinderDesc),
    Paraboloid(ParaboloidDesc),
    Hyperboloid(HyperboloidDesc),
    Disk(DiskDesc),
    Rectangle(RectangleDesc),
    Box(BoxDesc),
    Sphere(SphereDesc),
    Mesh(MeshDesc),
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct ConeDesc {
    pub radius_start: f64,
    pub z_start: f64,
    pub radius_end: f64,
    pub z_end: f64,
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct CylinderDesc {
    pub radius: f64,
    pub z_start: f64,
    pub z_end: f64,
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct ParaboloidDesc {
    /// Vertex-to-focus distance q (mm).
    pub focal_length: f64,
    pub z_start: f64,
    pub z_end: f64,
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct HyperboloidDesc {
    pub semi_axis_a: f64,
    pub semi_axis_b: f64,
    pub z_start: f64,
    pub z_end: f64,
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct DiskDesc {
    pub radius: f64,
    #[serde(default)]
    pub inner_radius: f64,
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct RectangleDesc {
    pub size: [f64; 2],
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct BoxDesc {
    pub size: [f64; 3],
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct SphereDesc {
    pub radius: f64,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct MeshDesc {
    /// Path relative to the scene file. Coordinates are read as millimetres
    /// (glTF's convention is metres: add `{ scale = 1000.0 }` for such files).
    pub file: String,
    /// Only this part of the file: a glTF node (or its mesh, or an ancestor node)
    /// or an OBJ object, by name. Default: the whole file.
    #[serde(default)]
    pub part: Option<String>,
}

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
/// ```
#[derive(Debug, Deserialize, Clone)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum SourceDesc {
    Parallel(ParallelDesc),
    Point(PointDesc),
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct ParallelDesc {
    #[serde(default = "minus_z")]
    pub direction: [f64; 3],
    #[serde(default)]
    pub off_axis: f64,
    #[serde(default)]
    pub off_axis_azimuth: f64,
    pub aperture: ApertureDesc,
    pub energy: EnergyDesc,
}

fn minus_z() -> [f64; 3] {
    [0.0, 0.0, -1.0]
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct ApertureDesc {
    pub center: [f64; 3],
    pub radius: f64,
    #[serde(default)]
    pub inner_radius: f64,
    /// Optional sector `[from, to]` in degrees (from e1 towards e2; for photons
    /// travelling along −z: from +x towards +y). Default: the full circle.
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct PointDesc {
    pub position: [f64; 3],
    #[serde(default)]
    pub radius: f64,
    pub target: ApertureDesc,
    pub energy: EnergyDesc,
}

/// Photon energies in keV.
#[derive(Debug, Deserialize, Clone)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum EnergyDesc {
    Line(f64),
    Band([f64; 2]),
}
