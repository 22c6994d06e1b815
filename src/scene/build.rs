//! Validating a scene description and instantiating it: materials resolved, meshes
//! loaded, analytic shapes placed, and everything handed to Embree.

use super::desc::*;
use super::error::SceneError;
use super::vars;
use crate::embree::{CommittedScene, Device};
use crate::figure_error::FigureErrorLibrary;
use crate::files::sha256_hex;
use crate::geometry::{
    within_world, AnalyticObject, AzimuthRange, Cuboid, Disk, Rectangle, Resolution,
    RevolutionQuadric, Shape, Sphere, Transform, MAX_TESSELLATION_QUADS, WORLD_LIMIT_MM,
};
use crate::material::{Material, Side};
use crate::mesh::{self, TriangleMesh};
use crate::render::{Appearance, Camera, Sky};
use crate::sensor::SensorSpec;
use crate::source::{AnnulusSector, ParallelBeam, PointSource, Source, Spectrum};
use crate::xray::{Coating, CoatingLibrary, ReflectivityTable};
use glam::{DAffine3, DVec3};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// Largest grazing angle (rad) kept in reflectivity tables (X-ray telescopes work
/// below ~3°); steeper reflections are evaluated directly.
const TABLE_THETA_MAX: f64 = 4.0 * std::f64::consts::PI / 180.0;

/// A built scene, ready to trace.
pub struct Scene {
    pub path: PathBuf,
    pub text_sha256: String,
    pub overrides: Vec<String>,
    pub vars: BTreeMap<String, toml::Value>,
    pub objects: Vec<Object>,
    pub sensors: Vec<SensorSpec>,
    pub sources: Vec<Source>,
    pub max_interactions: u32,
    /// Reflectivity tables of the coated mirrors' coatings (indexed by
    /// `Material::Mirror::reflectivity`), over the sources' energy range.
    pub reflectivity: Vec<ReflectivityTable>,
    pub embree: CommittedScene<AnalyticObject>,
    /// Named cameras for visible-light renders.
    pub cameras: BTreeMap<String, Camera>,
    /// The sky of visible-light renders.
    pub sky: Sky,
    /// Things worth telling the user (skipped mesh primitives, ...).
    pub warnings: Vec<String>,
    pub triangle_count: usize,
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
}

// Few objects per scene: keeping the analytic shape inline costs nothing.
#[allow(clippy::large_enum_variant)]
pub enum ObjectGeometry {
    Analytic(AnalyticObject),
    Mesh(MeshObject),
}

/// A mesh in world space. Besides the vertices it keeps, per triangle, what the
/// photon loop reads after an Embree hit, packed so that one hit touches one or
/// two cache lines instead of an index and three scattered vertices.
pub struct MeshObject {
    pub positions: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: unit front normal (counter-clockwise side) and its offset
    /// n·p0, in f64: the plane on which Embree's f32 hit is refined. Zero for a
    /// degenerate (zero-area) triangle.
    pub planes: Vec<[f64; 4]>,
    /// Per triangle, the vertex normals at its three corners, present only when
    /// the object reflects on interpolated normals (f32: 1e-7 rad is far below
    /// any figure error).
    pub corner_normals: Option<Vec<[[f32; 3]; 3]>>,
}

impl MeshObject {
    pub fn new(world: TriangleMesh, smooth: bool) -> MeshObject {
        let planes = world
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| world.positions[k as usize]);
                match (b - a).cross(c - a).try_normalize() {
                    Some(n) => [n.x, n.y, n.z, n.dot(a)],
                    None => [0.0; 4],
                }
            })
            .collect();
        let corner_normals = match (&world.normals, smooth) {
            (Some(ns), true) => Some(
                world
                    .triangles
                    .iter()
                    .map(|t| t.map(|k| ns[k as usize].as_vec3().to_array()))
                    .collect(),
            ),
            _ => None,
        };
        MeshObject {
            positions: world.positions,
            triangles: world.triangles,
            planes,
            corner_normals,
        }
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
        let original = std::fs::read_to_string(path)
            .map_err(|e| SceneError::new(path, None, format!("cannot read the scene file: {e}")))?;
        let (text, vars) = vars::substitute(path, &original, overrides)?;
        let desc: SceneDesc =
            toml::from_str(&text).map_err(|e| SceneError::from_toml(path, &text, &e))?;
        let mut b = Builder {
            path,
            text: &text,
            dir: path.parent().unwrap_or(Path::new(".")).to_path_buf(),
            representation,
        };
        let mut scene = b.build(device, desc)?;
        scene.text_sha256 = sha256_hex(original.as_bytes());
        scene.overrides = overrides.to_vec();
        scene.vars = vars;
        Ok(scene)
    }

    /// Index of the object with this name.
    pub fn object_index(&self, name: &str) -> Option<usize> {
        self.objects.iter().position(|o| o.name == name)
    }
}

struct Builder<'a> {
    path: &'a Path,
    text: &'a str,
    dir: PathBuf,
    representation: Representation,
}

impl Builder<'_> {
    fn err<T>(
        &self,
        span: std::ops::Range<usize>,
        msg: impl Into<String>,
    ) -> Result<T, SceneError> {
        if span.is_empty() && span.start == 0 {
            Err(SceneError::new(self.path, None, msg))
        } else {
            Err(SceneError::at(self.path, self.text, span.start, msg))
        }
    }

    fn build(&mut self, device: &Device, mut desc: SceneDesc) -> Result<Scene, SceneError> {
        let max_interactions = *desc.max_interactions.get_ref();
        if max_interactions == 0 {
            return self.err(
                desc.max_interactions.span(),
                "max_interactions must be at least 1",
            );
        }
        // Materials: the file's, plus the two built-in names.
        let mut materials: BTreeMap<String, (MaterialDesc, std::ops::Range<usize>)> =
            BTreeMap::new();
        materials.insert(
            "mirror".into(),
            (
                MaterialDesc::Mirror(MirrorDesc {
                    side: SideDesc::Both,
                    coating: None,
                    figure_error: None,
                }),
                0..0,
            ),
        );
        materials.insert(
            "absorber".into(),
            (MaterialDesc::Absorber(AbsorberDesc {}), 0..0),
        );
        for (name, m) in std::mem::take(&mut desc.materials) {
            let span = m.span();
            materials.insert(name, (m.into_inner(), span));
        }
        let mut used_materials = std::collections::BTreeSet::new();
        let library = CoatingLibrary::shipped().merged(&CoatingLibrary {
            materials: desc.optical_materials.clone(),
            coatings: desc.coatings.clone(),
        });
        let mut coatings: Vec<Coating> = Vec::new();
        let figure_errors = FigureErrorLibrary::shipped().merged(&desc.figure_errors);
        expand_assemblies(self.path, self.text, &self.dir, &mut desc, &mut materials)?;

        let mut objects = Vec::new();
        let mut sensors = Vec::new();
        let mut warnings = Vec::new();
        let mut embree = device.scene::<AnalyticObject>();
        let mut triangle_count = 0;
        let mut names = std::collections::HashSet::new();
        let mut mesh_files: std::collections::HashMap<PathBuf, Vec<mesh::MeshPart>> =
            Default::default();
        for (index, od) in desc.objects.into_iter().enumerate() {
            let ospan = od.span();
            let od = od.into_inner();
            let name = od.name.clone().unwrap_or_else(|| format!("object{index}"));
            if !names.insert(name.clone()) {
                return self.err(
                    ospan,
                    format!("two objects are named `{name}`; names must be unique"),
                );
            }
            let transform = self.transform(&od.transform)?;
            let mname = od.material.get_ref();
            let Some((mdesc, mspan)) = materials.get(mname) else {
                let known: Vec<&String> = materials.keys().collect();
                return self.err(
                    od.material.span(),
                    format!("object `{name}`: unknown material `{mname}` (known: {known:?})"),
                );
            };
            used_materials.insert(mname.clone());
            let material = match mdesc {
                MaterialDesc::Mirror(m) => Material::Mirror {
                    figure_error: match &m.figure_error {
                        None => None,
                        Some(spec) => figure_errors.resolve(spec).map_err(|e| {
                            SceneError::at(
                                self.path,
                                self.text,
                                mspan.start,
                                format!("material `{mname}`: figure_error: {e}"),
                            )
                        })?,
                    },
                    side: match m.side {
                        SideDesc::Front => Side::Front,
                        SideDesc::Back => Side::Back,
                        SideDesc::Both => Side::Both,
                    },
                    reflectivity: match &m.coating {
                        None => None,
                        Some(c) if library.is_perfect(c) => None,
                        Some(c) => Some(match coatings.iter().position(|k| &k.name == c) {
                            Some(i) => i,
                            None => {
                                let built = library.coating(c).map_err(|e| {
                                    SceneError::at(
                                        self.path,
                                        self.text,
                                        mspan.start,
                                        format!("material `{mname}`: {e}"),
                                    )
                                })?;
                                coatings.push(built);
                                coatings.len() - 1
                            }
                        }),
                    },
                },
                MaterialDesc::Absorber(_) => Material::Absorber,
                MaterialDesc::Sensor(s) => {
                    if !(s.size.iter().all(|v| v.is_finite() && *v > 0.0)) {
                        return self.err(
                            mspan.clone(),
                            format!("material `{mname}`: size must be two positive lengths (mm)"),
                        );
                    }
                    if s.pixels.contains(&0)
                        || (s.pixels[0] as u64 * s.pixels[1] as u64) > (1 << 26)
                    {
                        return self.err(mspan.clone(), format!("material `{mname}`: pixels must be positive, at most 2^26 (67 million) in all"));
                    }
                    if s.focal_length.is_some_and(|f| !(f.is_finite() && f > 0.0)) {
                        return self.err(
                            mspan.clone(),
                            format!(
                                "material `{mname}`: focal_length must be a positive length (mm)"
                            ),
                        );
                    }
                    if let Some((lo, hi, n)) = s.energy_bins {
                        let pixels = s.pixels[0] as u64 * s.pixels[1] as u64 * n as u64;
                        if !(lo.is_finite() && hi.is_finite() && lo < hi && n >= 1)
                            || pixels > (1 << 26)
                        {
                            return self.err(mspan.clone(), format!("material `{mname}`: energy_bins = [min, max, count] needs min < max (keV), count ≥ 1, and at most 2^26 pixels × bands"));
                        }
                    }
                    sensors.push(SensorSpec {
                        name: name.clone(),
                        object: index,
                        size: s.size,
                        pixels: s.pixels,
                        energy_bins: s.energy_bins,
                        focal_length: s.focal_length,
                    });
                    Material::Sensor {
                        sensor: sensors.len() - 1,
                    }
                }
            };
            let id = u32::try_from(index)
                .map_err(|_| SceneError::new(self.path, None, "too many objects"))?;
            let sspan = od.shape.span();
            let geometry = match od.shape.get_ref() {
                ShapeDesc::Mesh(m) => {
                    if od.tessellate.is_some() {
                        return self.err(sspan, format!("object `{name}`: `tessellate` applies to analytic shapes, not to meshes"));
                    }
                    let file = self.dir.join(&m.file);
                    if !file.is_file() {
                        return self.err(
                            sspan,
                            format!(
                                "object `{name}`: mesh file {} does not exist",
                                file.display()
                            ),
                        );
                    }
                    let at = |e: mesh::MeshError| {
                        SceneError::at(
                            self.path,
                            self.text,
                            sspan.start,
                            format!("object `{name}`: {e}"),
                        )
                    };
                    // Several objects may take parts of one file: read it once.
                    if !mesh_files.contains_key(&file) {
                        let (parts, report) = mesh::load_parts(&file).map_err(at)?;
                        warnings.extend(
                            report
                                .warnings()
                                .into_iter()
                                .map(|w| format!("{}: {w}", file.display())),
                        );
                        mesh_files.insert(file.clone(), parts);
                    }
                    let mesh = mesh::select_parts(&file, &mesh_files[&file], m.part.as_deref())
                        .map_err(at)?;
                    // The most common silent CAD mistake: a file in metres.
                    let extent = world_extent(&mesh, &transform);
                    if extent < mesh::units::SMALLEST_PLAUSIBLE_MM {
                        warnings.push(format!(
                            "object `{name}`: {} is only {extent:.4} mm across after its transform; \
                             if the file is in metres add `{{ scale = 1000.0 }}` as the first transform step \
                             (`traxer inspect {}` checks the file)",
                            file.display(),
                            file.display()
                        ));
                    }
                    self.mesh_object(mesh, &transform, od.smooth_normals)
                }
                shape => {
                    let shape = self.shape(shape, sspan.clone())?;
                    let (tessellate, smooth_normals) = match self.representation {
                        Representation::AsWritten => (
                            od.tessellate
                                .as_ref()
                                .map(|t| (Resolution::from(*t.get_ref()), t.span())),
                            od.smooth_normals,
                        ),
                        Representation::Analytic => (None, false),
                        Representation::Tessellated(r) => (
                            Some((r, ospan.clone())),
                            matches!(material, Material::Mirror { .. }),
                        ),
                    };
                    match tessellate {
                        Some((r, tspan)) => {
                            if r.segments == 0
                                || r.rings == 0
                                || r.segments.saturating_mul(r.rings) > MAX_TESSELLATION_QUADS
                            {
                                return self.err(tspan, format!("tessellate: segments and rings must be positive (and their product at most {MAX_TESSELLATION_QUADS})"));
                            }
                            let mesh = shape.tessellate(r);
                            self.mesh_object(mesh, &transform, smooth_normals)
                        }
                        None => {
                            if smooth_normals {
                                return self.err(ospan, format!("object `{name}`: smooth_normals applies to meshes (analytic shapes use their exact normal)"));
                            }
                            ObjectGeometry::Analytic(AnalyticObject { shape, transform })
                        }
                    }
                }
            };
            let (lo, hi) = match &geometry {
                ObjectGeometry::Analytic(a) => a.world_bounds(),
                ObjectGeometry::Mesh(m) => m.positions.iter().fold(
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                    |(a, b), &p| (a.min(p), b.max(p)),
                ),
            };
            if !within_world(&[lo, hi]) {
                return self.err(
                    ospan,
                    format!(
                        "object `{name}` reaches from {lo} to {hi} mm: everything must lie within ±{WORLD_LIMIT_MM:e} mm of the origin (float32 geometry; check the sizes, the transform and the mesh units)"
                    ),
                );
            }
            match &geometry {
                ObjectGeometry::Analytic(a) => embree.add_user(id, *a),
                ObjectGeometry::Mesh(m) => {
                    triangle_count += m.triangles.len();
                    let v32: Vec<[f32; 3]> =
                        m.positions.iter().map(|p| p.as_vec3().to_array()).collect();
                    embree.add_triangles(id, &v32, &m.triangles)
                }
            }
            .map_err(|e| SceneError::new(self.path, None, format!("object `{name}`: {e}")))?;
            let appearance = match &od.appearance {
                None => Appearance::default_for(&material),
                Some(a) => self.appearance(a.get_ref(), a.span(), &name)?,
            };
            objects.push(Object {
                name,
                material,
                transform,
                geometry,
                appearance,
            });
        }
        for (name, (_, span)) in &materials {
            if !used_materials.contains(name) && !span.is_empty() {
                return self.err(
                    span.clone(),
                    format!("material `{name}` is not used by any object"),
                );
            }
        }
        let sources = desc
            .sources
            .iter()
            .map(|s| self.source(s.get_ref(), s.span()))
            .collect::<Result<Vec<_>, _>>()?;
        // Reflectivity tables over the energies the sources emit.
        let (e_min, e_max) = sources
            .iter()
            .map(|s| s.spectrum().range())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (lo, hi)| {
                (a.min(lo), b.max(hi))
            });
        let reflectivity = coatings
            .iter()
            .map(|c| {
                ReflectivityTable::new(c, e_min, e_max, TABLE_THETA_MAX).map_err(|e| {
                    SceneError::new(
                        self.path,
                        None,
                        format!(
                            "coating `{}`: the sources emit energies it cannot describe: {e}",
                            c.name
                        ),
                    )
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let embree = embree.commit().map_err(|e| {
            SceneError::new(
                self.path,
                None,
                format!("Embree could not build the scene: {e}"),
            )
        })?;
        let mut cameras = BTreeMap::new();
        for (name, c) in &desc.cameras {
            let camera = Camera {
                look_from: DVec3::from(c.get_ref().look_from),
                look_at: DVec3::from(c.get_ref().look_at),
                up: DVec3::from(c.get_ref().up),
                vfov: c.get_ref().vfov,
            };
            camera
                .validate()
                .or_else(|m| self.err(c.span(), format!("camera `{name}`: {m}")))?;
            cameras.insert(name.clone(), camera);
        }
        let sky = match &desc.sky {
            None => Sky::default(),
            Some(k) => {
                let d = k.get_ref();
                let colours_ok = [d.zenith, d.horizon]
                    .iter()
                    .flatten()
                    .all(|v| v.is_finite() && *v >= 0.0);
                let up = DVec3::from(d.up);
                if !colours_ok || !up.is_finite() || up.length() == 0.0 {
                    return self.err(
                        k.span(),
                        "sky: zenith and horizon are colours (≥ 0), up a non-zero direction",
                    );
                }
                Sky {
                    zenith: DVec3::from(d.zenith),
                    horizon: DVec3::from(d.horizon),
                    up: up.normalize(),
                }
            }
        };
        Ok(Scene {
            cameras,
            sky,
            path: self.path.to_path_buf(),
            text_sha256: String::new(),
            overrides: Vec::new(),
            vars: BTreeMap::new(),
            objects,
            sensors,
            sources,
            max_interactions,
            reflectivity,
            embree,
            warnings,
            triangle_count,
        })
    }

    fn appearance(
        &self,
        d: &AppearanceDesc,
        span: std::ops::Range<usize>,
        object: &str,
    ) -> Result<Appearance, SceneError> {
        let colour = |c: [f64; 3], what: &str| {
            if c.iter().all(|v| v.is_finite() && *v >= 0.0) {
                Ok(DVec3::from(c))
            } else {
                self.err(
                    span.clone(),
                    format!("object `{object}`: appearance {what} must be three numbers ≥ 0 (linear RGB)"),
                )
            }
        };
        Ok(match d {
            AppearanceDesc::Diffuse { color } => Appearance::Diffuse {
                color: colour(*color, "color")?,
            },
            AppearanceDesc::Metal { color, roughness } => {
                if !(0.0..=1.0).contains(roughness) {
                    return self.err(
                        span,
                        format!("object `{object}`: roughness = {roughness}: expected 0 to 1"),
                    );
                }
                Appearance::Metal {
                    color: colour(*color, "color")?,
                    roughness: *roughness,
                }
            }
            AppearanceDesc::Glass { ior } => {
                if !(ior.is_finite() && *ior >= 1.0) {
                    return self.err(
                        span,
                        format!(
                            "object `{object}`: ior = {ior}: expected an index of refraction ≥ 1"
                        ),
                    );
                }
                Appearance::Glass { ior: *ior }
            }
            AppearanceDesc::Emitting { color } => Appearance::Emitting {
                color: colour(*color, "color")?,
            },
        })
    }

    fn mesh_object(
        &self,
        mesh: TriangleMesh,
        transform: &Transform,
        smooth: bool,
    ) -> ObjectGeometry {
        ObjectGeometry::Mesh(MeshObject::new(mesh.transformed(transform), smooth))
    }

    fn transform(&self, steps: &[Spanned<TransformStep>]) -> Result<Transform, SceneError> {
        let mut m = DAffine3::IDENTITY;
        for step in steps {
            let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
            let next = match step.get_ref() {
                TransformStep::Translate(t) if finite(t) => {
                    DAffine3::from_translation(DVec3::from(*t))
                }
                TransformStep::Rotate(r) if finite(&r.axis) && r.angle.is_finite() => {
                    let Some(axis) = DVec3::from(r.axis).try_normalize() else {
                        return self.err(step.span(), "rotate: axis must not be zero");
                    };
                    DAffine3::from_axis_angle(axis, r.angle.to_radians())
                }
                TransformStep::Scale(s) => {
                    let v = match s {
                        ScaleDesc::Uniform(k) => DVec3::splat(*k),
                        ScaleDesc::PerAxis(a) => DVec3::from(*a),
                    };
                    if !v.is_finite() || v.x * v.y * v.z == 0.0 {
                        return self.err(step.span(), "scale: factors must be finite and non-zero");
                    }
                    DAffine3::from_scale(v)
                }
                _ => return self.err(step.span(), "transform values must be finite numbers"),
            };
            m = next * m;
        }
        Ok(Transform::from_affine(m))
    }

    fn shape(&self, d: &ShapeDesc, span: std::ops::Range<usize>) -> Result<Shape, SceneError> {
        let bad = |msg: &str| -> Result<Shape, SceneError> {
            self.err(span.clone(), format!("shape: {msg}"))
        };
        let all_finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let azimuth = |a: &Option<[f64; 2]>| -> Result<AzimuthRange, SceneError> {
            match a {
                None => Ok(AzimuthRange::FULL),
                Some([from, to])
                    if from.is_finite() && to.is_finite() && to > from && to - from <= 360.0 =>
                {
                    Ok(AzimuthRange {
                        start_deg: *from,
                        span_deg: to - from,
                    })
                }
                Some(_) => self.err(
                    span.clone(),
                    "shape: azimuth = [from, to] needs from < to ≤ from + 360 (degrees)",
                ),
            }
        };
        Ok(match d {
            ShapeDesc::Cone(c) => {
                if !all_finite(&[c.radius_start, c.radius_end, c.z_start, c.z_end])
                    || c.radius_start < 0.0
                    || c.radius_end < 0.0
                    || c.z_start == c.z_end
                    || (c.radius_start == 0.0 && c.radius_end == 0.0)
                {
                    return bad("cone needs radii ≥ 0 (not both 0) and z_start ≠ z_end");
                }
                Shape::Revolution(RevolutionQuadric::cone(
                    c.radius_start,
                    c.z_start,
                    c.radius_end,
                    c.z_end,
                    azimuth(&c.azimuth)?,
                ))
            }
            ShapeDesc::Cylinder(c) => {
                if !all_finite(&[c.radius, c.z_start, c.z_end])
                    || c.radius <= 0.0
                    || c.z_start == c.z_end
                {
                    return bad("cylinder needs radius > 0 and z_start ≠ z_end");
                }
                Shape::Revolution(RevolutionQuadric::cylinder(
                    c.radius,
                    c.z_start,
                    c.z_end,
                    azimuth(&c.azimuth)?,
                ))
            }
            ShapeDesc::Paraboloid(p) => {
                if !all_finite(&[p.focal_length, p.z_start, p.z_end])
                    || p.focal_length <= 0.0
                    || p.z_start == p.z_end
                    || p.z_start.min(p.z_end) < -p.focal_length
                {
                    return bad("paraboloid needs focal_length > 0 and z_start ≠ z_end, both ≥ −focal_length (the vertex)");
                }
                Shape::Revolution(RevolutionQuadric::paraboloid(
                    p.focal_length,
                    p.z_start,
                    p.z_end,
                    azimuth(&p.azimuth)?,
                ))
            }
            ShapeDesc::Hyperboloid(h) => {
                let (lo, hi) = (h.z_start.min(h.z_end), h.z_start.max(h.z_end));
                if !all_finite(&[h.semi_axis_a, h.semi_axis_b, lo, hi])
                    || h.semi_axis_a <= 0.0
                    || h.semi_axis_b <= 0.0
                    || lo == hi
                    || !(lo >= h.semi_axis_a || hi <= -h.semi_axis_a)
                {
                    return bad("hyperboloid needs semi axes > 0 and a z range on one sheet (|z| ≥ semi_axis_a)");
                }
                Shape::Revolution(RevolutionQuadric::hyperboloid(
                    h.semi_axis_a,
                    h.semi_axis_b,
                    h.z_start,
                    h.z_end,
                    azimuth(&h.azimuth)?,
                ))
            }
            ShapeDesc::Disk(c) => {
                if !all_finite(&[c.radius, c.inner_radius])
                    || c.radius <= 0.0
                    || c.inner_radius < 0.0
                    || c.inner_radius >= c.radius
                {
                    return bad("disk needs 0 ≤ inner_radius < radius");
                }
                Shape::Disk(Disk {
                    inner_radius: c.inner_radius,
                    outer_radius: c.radius,
                    azimuth: azimuth(&c.azimuth)?,
                })
            }
            ShapeDesc::Rectangle(r) => {
                if !all_finite(&r.size) || r.size.iter().any(|v| *v <= 0.0) {
                    return bad("rectangle needs size = [width, height] > 0");
                }
                Shape::Rectangle(Rectangle {
                    width: r.size[0],
                    height: r.size[1],
                })
            }
            ShapeDesc::Box(b) => {
                if !all_finite(&b.size) || b.size.iter().any(|v| *v <= 0.0) {
                    return bad("box needs size = [x, y, z] > 0");
                }
                Shape::Cuboid(Cuboid {
                    size: DVec3::from(b.size),
                })
            }
            ShapeDesc::Sphere(s) => {
                if !s.radius.is_finite() || s.radius <= 0.0 {
                    return bad("sphere needs radius > 0");
                }
                Shape::Sphere(Sphere { radius: s.radius })
            }
            ShapeDesc::Mesh(_) => unreachable!("meshes are handled by the caller"),
        })
    }

    fn source(&self, d: &SourceDesc, span: std::ops::Range<usize>) -> Result<Source, SceneError> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let spectrum = |e: &EnergyDesc| -> Result<Spectrum, SceneError> {
            match *e {
                EnergyDesc::Line(x) if x.is_finite() && x > 0.0 => Ok(Spectrum::Line(x)),
                EnergyDesc::Band([a, b]) if a.is_finite() && b.is_finite() && a > 0.0 && b > a => Ok(Spectrum::Band(a, b)),
                _ => self.err(span.clone(), "source energy: { line = E } with E > 0 or { band = [min, max] } with 0 < min < max (keV)"),
            }
        };
        let far = |points: &[[f64; 3]]| {
            !within_world(&points.iter().map(|&p| DVec3::from(p)).collect::<Vec<_>>())
        };
        if match d {
            SourceDesc::Parallel(p) => {
                far(&[p.aperture.center]) || p.aperture.radius > WORLD_LIMIT_MM
            }
            SourceDesc::Point(p) => {
                far(&[p.position, p.target.center]) || p.target.radius > WORLD_LIMIT_MM
            }
        } {
            return self.err(
                span,
                format!("source positions, centres and radii must lie within ±{WORLD_LIMIT_MM:e} mm of the origin (float32 geometry: start photons near the target)"),
            );
        }
        let aperture_ok = |a: &ApertureDesc| {
            a.azimuth
                .is_none_or(|[f, t]| f.is_finite() && t.is_finite() && f < t && t - f <= 360.0)
                && finite(&a.center)
                && finite(&[a.radius, a.inner_radius])
                && a.radius > 0.0
                && a.inner_radius >= 0.0
                && a.inner_radius < a.radius
        };
        match d {
            SourceDesc::Parallel(p) => {
                if !aperture_ok(&p.aperture) {
                    return self.err(span, "parallel source: aperture needs finite center, 0 ≤ inner_radius < radius and azimuth = [from, to] with from < to ≤ from + 360");
                }
                let Some(axis) = DVec3::from(p.direction).try_normalize() else {
                    return self.err(span, "parallel source: direction must be a non-zero vector");
                };
                if !finite(&[p.off_axis, p.off_axis_azimuth]) || p.off_axis.abs() >= 90.0 {
                    return self.err(span, "parallel source: off_axis must be below 90 degrees");
                }
                let aperture = AnnulusSector::new(
                    DVec3::from(p.aperture.center),
                    axis,
                    p.aperture.inner_radius,
                    p.aperture.radius,
                    p.aperture.azimuth,
                );
                Ok(Source::Parallel(ParallelBeam::new(
                    aperture,
                    axis,
                    p.off_axis,
                    p.off_axis_azimuth,
                    spectrum(&p.energy)?,
                )))
            }
            SourceDesc::Point(p) => {
                if !aperture_ok(&p.target) {
                    return self.err(
                        span,
                        "point source: target needs finite center, 0 ≤ inner_radius < radius and azimuth = [from, to] with from < to ≤ from + 360",
                    );
                }
                if !finite(&p.position) || !p.radius.is_finite() || p.radius < 0.0 {
                    return self.err(span, "point source: position must be finite and radius ≥ 0");
                }
                let dist = (DVec3::from(p.position) - DVec3::from(p.target.center)).length();
                if dist <= p.radius.max(p.target.radius) {
                    return self.err(span, "point source: the source must be farther from the target centre than both radii");
                }
                Ok(Source::Point(PointSource::new(
                    DVec3::from(p.position),
                    p.radius,
                    DVec3::from(p.target.center),
                    p.target.inner_radius,
                    p.target.radius,
                    p.target.azimuth,
                    spectrum(&p.energy)?,
                )))
            }
        }
    }
}

/// Expands the `[[assemblies]]` of a description into ordinary objects (appended to
/// `desc.objects`) and the mirror materials they need (added to `materials`).
fn expand_assemblies(
    path: &Path,
    text: &str,
    dir: &Path,
    desc: &mut SceneDesc,
    materials: &mut BTreeMap<String, (MaterialDesc, std::ops::Range<usize>)>,
) -> Result<(), SceneError> {
    use super::llnl::{LlnlTelescope, PartMaterial};
    for a in std::mem::take(&mut desc.assemblies) {
        let span = a.span();
        let err = |m: String| SceneError::at(path, text, span.start, m);
        match a.into_inner() {
            AssemblyDesc::LlnlTelescope(t) => {
                let data = match &t.data {
                    None => LlnlTelescope::shipped(),
                    Some(f) => {
                        let file = dir.join(f);
                        let body = std::fs::read_to_string(&file).map_err(|e| {
                            err(format!("llnl_telescope data {}: {e}", file.display()))
                        })?;
                        LlnlTelescope::from_toml(&body)
                            .map_err(|e| SceneError::from_toml(&file, &body, &e))?
                    }
                };
                data.validate()
                    .map_err(|m| err(format!("llnl_telescope data: {m}")))?;
                if !t.azimuth_center.is_finite() {
                    return Err(err("azimuth_center must be a number (degrees)".into()));
                }
                if t.mesh.is_some() && t.tessellate.is_some() {
                    return Err(err(
                        "llnl_telescope: give `mesh` (parts from a file) or `tessellate`, not both"
                            .into(),
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
                for part in data.parts(azimuth, coating) {
                    let material = match &part.material {
                        PartMaterial::Absorber => "absorber".to_string(),
                        PartMaterial::Mirror(coating) => {
                            let m = format!("{}_mirror_{coating}", t.name);
                            materials.entry(m.clone()).or_insert((
                                MaterialDesc::Mirror(MirrorDesc {
                                    side: SideDesc::Front,
                                    coating: Some(coating.clone()),
                                    figure_error: t.figure_error.clone(),
                                }),
                                0..0,
                            ));
                            m
                        }
                    };
                    let is_mirror = matches!(part.material, PartMaterial::Mirror(_));
                    let name = format!("{}_{}", t.name, part.name);
                    let (shape, own_transform) = match &t.mesh {
                        None => (part.shape, part.transform),
                        // The file holds the part already placed in the telescope
                        // frame, with the segments centred on azimuth 0.
                        Some(file) => (
                            ShapeDesc::Mesh(MeshDesc {
                                file: file.clone(),
                                part: Some(name.clone()),
                            }),
                            vec![TransformStep::Rotate(RotateDesc {
                                axis: [0.0, 0.0, 1.0],
                                angle: t.azimuth_center,
                            })],
                        ),
                    };
                    let transform = own_transform
                        .iter()
                        .chain(&t.transform)
                        .map(|s| Spanned::new(span.clone(), s.clone()))
                        .collect();
                    let meshed = t.tessellate.is_some() || t.mesh.is_some();
                    desc.objects.push(Spanned::new(
                        span.clone(),
                        ObjectDesc {
                            name: Some(name),
                            shape: Spanned::new(span.clone(), shape),
                            material: Spanned::new(span.clone(), material),
                            transform,
                            tessellate: t.tessellate.map(|r| Spanned::new(span.clone(), r)),
                            smooth_normals: meshed && is_mirror,
                            appearance: None,
                        },
                    ));
                }
            }
        }
    }
    Ok(())
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
    let original = std::fs::read_to_string(path)
        .map_err(|e| SceneError::new(path, None, format!("cannot read the scene file: {e}")))?;
    let (text, _) = vars::substitute(path, &original, overrides)?;
    let mut desc: SceneDesc =
        toml::from_str(&text).map_err(|e| SceneError::from_toml(path, &text, &e))?;
    // Assemblies (the LLNL telescope) become their objects, as in a trace.
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    expand_assemblies(path, &text, &dir, &mut desc, &mut BTreeMap::new())?;
    let b = Builder {
        path,
        text: &text,
        dir: PathBuf::new(),
        representation: Representation::AsWritten,
    };
    let mut out = Vec::new();
    for (index, od) in desc.objects.iter().enumerate() {
        let od = od.get_ref();
        if matches!(od.shape.get_ref(), ShapeDesc::Mesh(_)) {
            continue;
        }
        out.push(NamedShape {
            name: od.name.clone().unwrap_or_else(|| format!("object{index}")),
            shape: b.shape(od.shape.get_ref(), od.shape.span())?,
            transform: b.transform(&od.transform)?,
            resolution: od.tessellate.as_ref().map(|t| Resolution {
                segments: t.get_ref().segments,
                rings: t.get_ref().rings,
            }),
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
        shape: Spanned<ShapeDesc>,
    }
    let path = Path::new("--shape");
    let full = format!("shape = {{ {text} }}");
    let w: Wrapper =
        toml::from_str(&full).map_err(|e| SceneError::new(path, None, e.message().to_string()))?;
    if matches!(w.shape.get_ref(), ShapeDesc::Mesh(_)) {
        return Err(SceneError::new(
            path,
            None,
            "a mesh is already a mesh; give an analytic shape",
        ));
    }
    let b = Builder {
        path,
        text: &full,
        dir: PathBuf::new(),
        representation: Representation::AsWritten,
    };
    b.shape(w.shape.get_ref(), w.shape.span())
}

/// Largest edge of the world-space box around a mesh's local box (an upper bound
/// of its world extent; exact without rotations).
fn world_extent(mesh: &TriangleMesh, transform: &Transform) -> f64 {
    let (lo, hi) = mesh.bounds();
    let (wlo, whi) = transform.box_to_world(lo, hi);
    (whi - wlo).max_element()
}
