//! The objects of a scene, one `[[objects]]` entry at a time (assemblies already
//! expanded): unique name, placement, material, geometry — a mesh read from its
//! file (each file read once, whichever parts objects take from it) or an
//! analytic shape, exact or tessellated as the representation asks — checked to
//! lie within the world, and its visible-light appearance.

use super::appearance::Appearance;
use super::desc::ObjectDesc;
use super::error::{SceneError, SceneText};
use super::inputs::InputFiles;
use super::materials::Materials;
use super::placement::transform;
use super::{MeshObject, Object, ObjectGeometry, Representation};
use crate::geometry::{
    within_world, AnalyticObject, Resolution, Shape, Surface, Transform, TriangleMesh,
    MAX_TESSELLATION_QUADS, WORLD_LIMIT_MM,
};
use crate::material::Material;
use crate::mesh::{self, MeshPart};
use crate::sensor::{check_file_names, SensorSpec, MAX_TOTAL_PIXELS, SUMMARY_FILE};
use glam::DVec3;
use std::collections::{HashMap, HashSet};
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// Builds a scene's objects in order, remembering what they share.
pub(super) struct ObjectBuilder<'a> {
    pub at: SceneText<'a>,
    /// Mesh files are relative to this folder (the scene file's).
    pub dir: &'a Path,
    pub representation: Representation,
    names: HashSet<String>,
    /// Output file name → the sensor that writes it.
    sensor_files: HashMap<String, String>,
    /// Image values of the sensors so far (`SensorSpec::image_values`).
    sensor_pixels: u64,
    /// Several objects may take parts of one file: it is read once.
    mesh_files: HashMap<PathBuf, Vec<MeshPart>>,
    /// Things the user should hear about (skipped mesh pieces, tiny meshes).
    pub warnings: Vec<String>,
    /// The files read.
    inputs: &'a InputFiles,
}

impl<'a> ObjectBuilder<'a> {
    pub fn new(
        at: SceneText<'a>,
        dir: &'a Path,
        representation: Representation,
        inputs: &'a InputFiles,
    ) -> Self {
        ObjectBuilder {
            inputs,
            at,
            dir,
            representation,
            names: HashSet::new(),
            sensor_files: HashMap::new(),
            sensor_pixels: 0,
            mesh_files: HashMap::new(),
            warnings: Vec::new(),
        }
    }

    /// Object number `index`, its material resolved in `materials`.
    pub fn build(
        &mut self,
        index: usize,
        od: Spanned<ObjectDesc>,
        materials: &mut Materials,
    ) -> Result<Object, SceneError> {
        let ospan = od.span();
        let od = od.into_inner();
        let name = od.name.clone().unwrap_or_else(|| format!("object{index}"));
        if !self.names.insert(name.clone()) {
            return Err(self.at.error(
                ospan,
                format!("two objects are named `{name}`; names must be unique"),
            ));
        }
        let transform = transform(&od.transform).map_err(|(s, m)| self.at.error(s, m))?;
        let material = self.material(&od, &name, index, materials)?;
        if let Material::Sensor { sensor } = material {
            self.check_sensor(&materials.sensors[sensor], ospan.clone())?;
        }
        let geometry = self.geometry(&od, ospan.clone(), &name, &material, transform)?;
        let (lo, hi) = geometry.world_bounds();
        if !within_world(&[lo, hi]) {
            let point = |p: glam::DVec3| {
                let c: Vec<String> = p.to_array().map(crate::text::number).into();
                format!("[{}]", c.join(", "))
            };
            return Err(self.at.error(
                ospan,
                format!(
                    "object `{name}` reaches from {} to {} mm: everything must lie within ±{WORLD_LIMIT_MM:e} mm of the origin (float32 geometry; check the sizes, the transform and the mesh units)",
                    point(lo),
                    point(hi)
                ),
            ));
        }
        let appearance = match &od.appearance {
            None => Appearance::default_for(&material),
            Some(a) => a
                .get_ref()
                .build()
                .map_err(|m| self.at.error(a.span(), format!("object `{name}`: {m}")))?,
        };
        let part = od.part_of.clone().unwrap_or_else(|| name.clone());
        Ok(Object {
            name,
            material,
            transform,
            geometry,
            appearance,
            stage: od.stage,
            shell: od.shell.as_ref().map(|s| s.text()),
            part,
        })
    }

    /// A sensor's files must not collide with another sensor's or the summary,
    /// their names must suit file systems, and all sensors' pixels together must
    /// stay within [`MAX_TOTAL_PIXELS`].
    fn check_sensor(&mut self, spec: &SensorSpec, span: Range<usize>) -> Result<(), SceneError> {
        let name = &spec.name;
        check_file_names(name).map_err(|m| self.at.error(span.clone(), m))?;
        if let Some(grid) = spec
            .pixel_grid
            .as_ref()
            .filter(|g| !g.overlaps_sensor(spec.size))
        {
            self.warnings.push(format!(
                "sensor `{name}`: its pixel_grid (centre [{}, {}] mm, {} × {} pixels of {} mm, turned {}°) lies entirely outside the {} × {} mm sensor: its grid image will be empty; check pixel_grid.center",
                grid.center_mm[0], grid.center_mm[1], grid.pixels[0], grid.pixels[1], grid.pitch_mm, grid.rotation_deg, spec.size[0], spec.size[1]
            ));
        }
        for file in spec.file_names() {
            let other = if file == SUMMARY_FILE {
                Some("the run's summary".to_string())
            } else {
                self.sensor_files
                    .get(&file)
                    .map(|s| format!("sensor `{s}`"))
            };
            if let Some(other) = other {
                return Err(self.at.error(
                    span,
                    format!(
                        "sensor `{name}` would write {file}, as {other} does: rename one of them"
                    ),
                ));
            }
            self.sensor_files.insert(file, name.clone());
        }
        self.sensor_pixels += spec.image_values();
        if self.sensor_pixels > MAX_TOTAL_PIXELS {
            return Err(self.at.error(
                span,
                format!(
                    "sensor `{name}`: the scene's sensors have {} image values in all (pixels × energy bands, plus 5 images per sensor with history_images and the pixel grids' pixels × bands), more than {MAX_TOTAL_PIXELS} (2 GB of images); use fewer or coarser sensors, or leave out history_images",
                    self.sensor_pixels
                ),
            ));
        }
        Ok(())
    }

    fn material(
        &self,
        od: &ObjectDesc,
        name: &str,
        index: usize,
        materials: &mut Materials,
    ) -> Result<Material, SceneError> {
        let mname = od.material.get_ref();
        match materials.resolve(mname, index, name) {
            Some(Ok(m)) => Ok(m),
            Some(Err(e)) => {
                let e = e.narrowed(self.at.text);
                Err(self.at.error(e.span, e.message))
            }
            None => Err(self.at.error(
                od.material.span(),
                format!(
                    "object `{name}`: unknown material `{mname}` (known: {:?})",
                    materials.names()
                ),
            )),
        }
    }

    fn geometry(
        &mut self,
        od: &ObjectDesc,
        ospan: Range<usize>,
        name: &str,
        material: &Material,
        transform: Transform,
    ) -> Result<ObjectGeometry, SceneError> {
        let sspan = od.shape.span();
        let shape = match od.shape.get_ref().analytic() {
            Some(shape) => shape.map_err(|m| self.at.error(sspan.clone(), m))?,
            None => {
                if od.tessellate.is_some() {
                    return Err(self.at.error(sspan, format!("object `{name}`: `tessellate` applies to analytic shapes, not to meshes")));
                }
                let mesh = self.mesh_file(od, name, &transform)?;
                return Ok(mesh_object(mesh, &transform, od.smooth_normals));
            }
        };
        // What the representation asks: the file's own choice, exact, or meshes.
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
                    return Err(self.at.error(tspan, format!("tessellate: segments and rings must be positive (and their product at most {MAX_TESSELLATION_QUADS})")));
                }
                Ok(mesh_object(shape.tessellate(r), &transform, smooth_normals))
            }
            None if smooth_normals => Err(self.at.error(ospan, format!("object `{name}`: smooth_normals applies to meshes (analytic shapes use their exact normal)"))),
            None => Ok(analytic_object(shape, transform)),
        }
    }

    /// The (parts of the) mesh file of a `mesh` shape, in its local frame.
    fn mesh_file(
        &mut self,
        od: &ObjectDesc,
        name: &str,
        transform: &Transform,
    ) -> Result<TriangleMesh, SceneError> {
        let sspan = od.shape.span();
        let super::shapes::ShapeDesc::Mesh(m) = od.shape.get_ref() else {
            unreachable!("only mesh shapes have no analytic form")
        };
        let file = self.dir.join(&m.file);
        if file.is_dir() {
            return Err(self.at.error(
                sspan,
                format!(
                    "object `{name}`: mesh file {} is a folder; give the .gltf, .glb, .obj or .stl file in it",
                    file.display()
                ),
            ));
        }
        if !file.is_file() {
            return Err(self.at.error(
                sspan,
                format!(
                    "object `{name}`: mesh file {} does not exist",
                    file.display()
                ),
            ));
        }
        let at = |e: mesh::MeshError| {
            self.at
                .error(sspan.clone(), format!("object `{name}`: {e}"))
        };
        if !self.mesh_files.contains_key(&file) {
            let (parts, report) = mesh::load_parts(&file).map_err(at)?;
            self.inputs.note(&file);
            for buffer in &report.files {
                self.inputs.note(buffer);
            }
            self.warnings.extend(
                report
                    .warnings()
                    .into_iter()
                    .map(|w| format!("{}: {w}", file.display())),
            );
            self.mesh_files.insert(file.clone(), parts);
        }
        let mesh =
            mesh::select_parts(&file, &self.mesh_files[&file], m.part.as_deref()).map_err(at)?;
        // The most common silent CAD mistake: a file in metres.
        let (lo, hi) = mesh.bounds();
        let (wlo, whi) = transform.box_to_world(lo, hi);
        let extent = (whi - wlo).max_element();
        if extent < mesh::units::SMALLEST_PLAUSIBLE_MM {
            self.warnings.push(format!(
                "object `{name}`: {} is only {extent:.4} mm across after its transform; \
                 if the file is in metres add `{{ scale = 1000.0 }}` as the first transform step \
                 (`traxer inspect {}` checks the file)",
                file.display(),
                file.display()
            ));
        }
        Ok(mesh)
    }
}

fn mesh_object(mesh: TriangleMesh, transform: &Transform, smooth: bool) -> ObjectGeometry {
    ObjectGeometry::Mesh(MeshObject::new(mesh.transformed(transform), smooth))
}

fn analytic_object(shape: Shape, transform: Transform) -> ObjectGeometry {
    ObjectGeometry::Analytic(AnalyticObject { shape, transform })
}

impl ObjectGeometry {
    /// World-space axis-aligned bounds.
    pub fn world_bounds(&self) -> (DVec3, DVec3) {
        match self {
            ObjectGeometry::Analytic(a) => a.world_bounds(),
            ObjectGeometry::Mesh(m) => m.positions.iter().fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(a, b), &p| (a.min(p), b.max(p)),
            ),
        }
    }
}
