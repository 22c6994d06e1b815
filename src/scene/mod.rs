//! Scenes: the TOML file format, variables, and the build step that validates a
//! description and instantiates it with Embree ([`Scene::load`]).
//!
//! Data flow: scene.toml ─[`load`]: substitute vars, serde─▶ `SceneDesc`
//! ─`build`─▶ [`Scene`] (complete, immutable, shared by all tracing threads).
//! One file per build concern: `materials`, `assemblies` (nested telescopes:
//! `telescope` data, `telescope_parts`), `objects` (meshes, tessellation, world bounds), `shapes` and
//! `placement` (each shape and transform step checks its own parameters),
//! `appearance` and `camera` (render setup), `embree_binding` (how objects reach
//! Embree); sources check themselves in `crate::source`.

mod appearance;
mod assemblies;
mod assembly_desc;
mod build;
mod camera;
pub mod desc;
mod embree_binding;
mod error;
pub mod inputs;
pub mod load;
pub mod magnet;
mod magnet_in_scene;
mod materials;
mod mirror_surface;
mod objects;
mod placement;
mod shapes;
pub mod telescope;
mod telescope_nesting;
pub mod telescope_parts;
mod vars;
pub use vars::merged_overrides;

pub use appearance::{Appearance, AppearanceDesc, Sky, SkyDesc};
pub use assembly_desc::{AssemblyDesc, NestedTelescopeDesc};
pub use build::{analytic_shapes, inline_shape, NamedShape, TABLE_THETA_MAX};
pub use camera::{Camera, CameraDesc};
pub use embree_binding::{AnalyticPieces, ShellSearch};
pub use error::SceneError;
pub use inputs::{input_difference, InputHashes};
pub use materials::{AbsorberDesc, FoilDesc, MaterialDesc, MirrorDesc, SideDesc};
pub use placement::{RotateDesc, ScaleDesc, TransformStep};
pub use shapes::ShapeDesc;

use crate::embree::{CommittedScene, Device};
use crate::geometry::{AnalyticObject, Resolution, Transform, TriangleMesh};
use crate::history::MirrorStage;
use crate::material::Material;
use crate::sensor::SensorSpec;
use crate::source::Source;
use crate::xray::ReflectivityTable;
use glam::DVec3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A built scene, ready to trace.
pub struct Scene {
    pub path: PathBuf,
    /// What the scene is, for people (its `title`), if it says.
    pub title: Option<String>,
    /// SHA-256 of the scene file's bytes.
    pub text_sha256: String,
    /// The `-D name=value` overrides it was loaded with.
    pub overrides: Vec<String>,
    /// Final values of its variables.
    pub vars: BTreeMap<String, toml::Value>,
    /// The other files it read (meshes, data and emission tables) and their
    /// SHA-256: part of a run's identity.
    pub inputs: InputHashes,
    pub objects: Vec<Object>,
    /// The figure-error presets the scene could name (the shipped ones and its
    /// own `[figure_errors]`), with their covariances, for studies that vary
    /// the figure.
    pub figure_errors: crate::xray::FigureErrorLibrary,
    pub sensors: Vec<SensorSpec>,
    /// Thin foils (windows, filters), indexed by `Material::Foil::foil`.
    pub foils: Vec<crate::xray::Foil>,
    /// Mirror microroughness models, indexed by `Material::Mirror::roughness`.
    pub roughness: Vec<crate::xray::roughness::Roughness>,
    pub sources: Vec<Source>,
    /// The helioscope's magnet (`[magnet]`): a step on each Sun photon's path,
    /// applied where the photon is recorded (`trace`).
    pub magnet: Option<std::sync::Arc<crate::magnet::Magnet>>,
    pub max_interactions: u32,
    /// Reflectivity tables of the coated mirrors' coatings (indexed by
    /// `Material::Mirror::reflectivity`), over the sources' energy range.
    pub reflectivity: Vec<ReflectivityTable>,
    /// Every object, in one Embree scene.
    pub embree: CommittedScene<embree_binding::AnalyticPieces>,
    /// With nested shells, how the photon loop finds hits instead
    /// ([`Scene::nearest_hit`]); `None` sends every query to `embree`.
    pub shell_search: Option<ShellSearch>,
    /// Named cameras for visible-light renders.
    pub cameras: BTreeMap<String, Camera>,
    /// The sky of visible-light renders.
    pub sky: Sky,
    /// Things worth telling the user (skipped mesh primitives, ...).
    pub warnings: Vec<String>,
    /// Seconds Embree took to build the scene's BVH (`traxer bench` reports it).
    pub bvh_seconds: f64,
    pub triangle_count: usize,
    /// How its analytic objects were given to Embree (`traxer compare` traces
    /// one scene in several).
    pub representation: Representation,
}

/// What a unit of a scene's images counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Counted {
    /// Summed photon weights (beams and point sources: see their weights).
    Weights,
    /// A Sun without a magnet: axions per second, before conversion.
    Axions,
    /// A Sun with a magnet: X-ray photons per second, each axion weighted by
    /// its conversion probability.
    XRays,
}

impl Counted {
    /// Whether images are rates per second (a Sun).
    pub fn absolute(self) -> bool {
        self != Counted::Weights
    }

    /// What one per-second unit is: "axions" or "X-rays" ("" for weights).
    pub fn particles(self) -> &'static str {
        match self {
            Counted::Weights => "",
            Counted::Axions => "axions",
            Counted::XRays => "X-rays",
        }
    }
}

/// One object of a built scene; its index is its Embree geometry id.
pub struct Object {
    pub name: String,
    pub material: Material,
    /// Local frame → world (for sensors' pixel grids and for reporting).
    pub transform: Transform,
    pub geometry: ObjectGeometry,
    /// How it looks in visible-light renders.
    pub appearance: Appearance,
    /// For photon histories: which mirror of a two-reflection telescope it is,
    /// and the shell (or part) it belongs to.
    pub stage: Option<MirrorStage>,
    pub shell: Option<String>,
    /// The scene entry it comes from: its own name, or its telescope's for a
    /// telescope's parts (what a render's labels name).
    pub part: String,
}

// Few objects per scene: keeping the analytic shape inline costs nothing.
#[allow(clippy::large_enum_variant)]
pub enum ObjectGeometry {
    Analytic(AnalyticObject),
    Mesh(MeshObject),
}

/// A mesh in world space, as the photon loop reads it after an Embree hit.
/// The f64 vertices give each facet's exact plane, on which Embree's f32 hit is
/// refined; the triangles are the very index buffer Embree reads (shared, not
/// copied). Facet planes and corner normals are looked up per hit rather than
/// stored per triangle: that keeps a 2-million-triangle mesh at about 40 bytes a
/// triangle instead of 100 (docs/speed.md "Memory").
pub struct MeshObject {
    pub positions: Vec<DVec3>,
    pub triangles: Arc<Vec<[u32; 3]>>,
    /// Unit vertex normals, one per position, present only when the object
    /// reflects on interpolated normals (f32: 1e-7 rad is far below any figure
    /// error).
    vertex_normals: Option<Vec<[f32; 3]>>,
}

impl MeshObject {
    pub fn new(world: TriangleMesh, smooth: bool) -> MeshObject {
        let vertex_normals = match (world.normals, smooth) {
            (Some(ns), true) => Some(ns.iter().map(|n| n.as_vec3().to_array()).collect()),
            _ => None,
        };
        MeshObject {
            positions: world.positions,
            triangles: Arc::new(world.triangles),
            vertex_normals,
        }
    }

    /// Triangle `prim`'s unit front normal (counter-clockwise side) and its
    /// offset n·p0, in f64; zero for a degenerate (zero-area) triangle.
    #[inline]
    pub fn plane(&self, prim: usize) -> (DVec3, f64) {
        let [a, b, c] = self.triangles[prim].map(|k| self.positions[k as usize]);
        match (b - a).cross(c - a).try_normalize() {
            Some(n) => (n, n.dot(a)),
            None => (DVec3::ZERO, 0.0),
        }
    }

    /// Triangle `prim`'s vertex normals at its three corners, when the object
    /// reflects on interpolated normals.
    #[inline]
    pub fn corner_normals(&self, prim: usize) -> Option<[DVec3; 3]> {
        let normals = self.vertex_normals.as_ref()?;
        Some(self.triangles[prim].map(|k| {
            let [x, y, z] = normals[k as usize];
            DVec3::new(x as f64, y as f64, z as f64)
        }))
    }
}

/// How the analytic objects of a scene are given to Embree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Representation {
    /// As the scene file says (each object's own `tessellate`).
    AsWritten,
    /// Every analytic object exact, any `tessellate` ignored.
    Analytic,
    /// Every analytic object (assemblies included) tessellated at this resolution,
    /// mirrors with smooth normals. Meshes from files stay as they are.
    Tessellated(Resolution),
}

impl Scene {
    /// The nearest hit of `q`: by the shell search where the scene has one,
    /// else by Embree over every object (the same answers; docs/speed.md).
    #[inline]
    pub fn nearest_hit(&self, q: &crate::embree::Query) -> Option<crate::embree::Hit> {
        match &self.shell_search {
            Some(s) => s.intersect(q),
            None => self.embree.intersect(q),
        }
    }

    /// The energies an image on `spec` holds (keV): the sensor's bins, else the
    /// sources' range.
    pub fn image_energy_range(&self, spec: &SensorSpec) -> (f64, f64) {
        if let Some((lo, hi, _)) = spec.energy_bins {
            return (lo, hi);
        }
        self.sources
            .iter()
            .map(|s| s.energy_range())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (lo, hi)| {
                (a.min(lo), b.max(hi))
            })
    }

    /// Whether any object reflects (a mirror material).
    pub fn has_mirrors(&self) -> bool {
        self.objects
            .iter()
            .any(|o| matches!(o.material, crate::material::Material::Mirror { .. }))
    }

    /// The scene's name for figure titles: its `title`, else its file's name.
    pub fn name_for_people(&self) -> String {
        self.title.clone().unwrap_or_else(|| {
            self.path
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned())
        })
    }

    /// Reads, substitutes, parses, validates and builds a scene file.
    pub fn load(device: &Device, path: &Path, overrides: &[String]) -> Result<Scene, SceneError> {
        Scene::load_as(device, path, overrides, Representation::AsWritten)
    }

    /// [`Scene::load`] with the analytic objects represented as `representation`
    /// says (`traxer compare` traces one scene in several representations).
    pub fn load_as(
        device: &Device,
        path: &Path,
        overrides: &[String],
        representation: Representation,
    ) -> Result<Scene, SceneError> {
        build::build(device, path, load::read(path, overrides)?, representation)
    }

    /// The magnet that converts the scene's axions: the scene's magnet when
    /// its one source is the Sun (a lab source's X-rays pass a magnet
    /// unconverted).
    pub fn converting_magnet(&self) -> Option<&crate::magnet::Magnet> {
        match self.sources.as_slice() {
            [crate::source::Source::Sun(_)] => self.magnet.as_deref(),
            _ => None,
        }
    }

    /// What a unit of the scene's images counts.
    pub fn counted(&self) -> Counted {
        match (self.rate_per_unit_weight(1), &self.magnet) {
            (None, _) => Counted::Weights,
            (Some(_), None) => Counted::Axions,
            (Some(_), Some(_)) => Counted::XRays,
        }
    }

    /// With a `sun` source (then the only source), the axions per second that one
    /// unit of summed weight stands for in a run of `photons` photons: images are
    /// in absolute units. `None` for other sources.
    pub fn rate_per_unit_weight(&self, photons: u64) -> Option<f64> {
        self.sources.iter().find_map(|s| match s {
            Source::Sun(sun) => Some(
                sun.rate_per_unit_weight(photons)
                    * self.magnet.as_ref().map_or(1.0, |m| m.weight_scale),
            ),
            _ => None,
        })
    }

    /// The emission of the scene's Sun (which splits photons among the process
    /// images), or `None` without a Sun.
    pub fn sun_emission(&self) -> Option<&crate::source::SunEmission> {
        self.sources.iter().find_map(|s| match s {
            Source::Sun(sun) => Some(sun.emission_draw.as_ref()),
            _ => None,
        })
    }

    /// Index of the object with this name.
    pub fn object_index(&self, name: &str) -> Option<usize> {
        self.objects.iter().position(|o| o.name == name)
    }
}
