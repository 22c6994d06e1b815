//! The `shape = { type = ... }` entries of a scene file, each variant next to the
//! check of its own parameters and its conversion into a `geometry::Shape` (as
//! pbrt-v4's `Shape::Create`). Meshes are read by `objects`, not here.

use crate::geometry::{AzimuthRange, Cuboid, Disk, Rectangle, RevolutionQuadric, Shape, Sphere};
use glam::DVec3;
use serde::Deserialize;

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
/// shape = { type = "mesh", file = "../meshes/bore.gltf" }         # .gltf, .glb, .obj or .stl
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

impl ShapeDesc {
    /// The shape's `type`, for messages.
    pub fn kind(&self) -> &'static str {
        match self {
            ShapeDesc::Cone(_) => "cone",
            ShapeDesc::Cylinder(_) => "cylinder",
            ShapeDesc::Paraboloid(_) => "paraboloid",
            ShapeDesc::Hyperboloid(_) => "hyperboloid",
            ShapeDesc::Disk(_) => "disk",
            ShapeDesc::Rectangle(_) => "rectangle",
            ShapeDesc::Box(_) => "box",
            ShapeDesc::Sphere(_) => "sphere",
            ShapeDesc::Mesh(_) => "mesh",
        }
    }

    /// The analytic shape, or what is wrong with its parameters ("shape: ...");
    /// `None` for a mesh, which `objects` loads from its file.
    pub fn analytic(&self) -> Option<Result<Shape, InvalidShape>> {
        let shape = match self {
            ShapeDesc::Cone(c) => c.build(),
            ShapeDesc::Cylinder(c) => c.build(),
            ShapeDesc::Paraboloid(p) => p.build(),
            ShapeDesc::Hyperboloid(h) => h.build(),
            ShapeDesc::Disk(d) => d.build(),
            ShapeDesc::Rectangle(r) => r.build(),
            ShapeDesc::Box(b) => b.build(),
            ShapeDesc::Sphere(s) => s.build(),
            ShapeDesc::Mesh(_) => return None,
        };
        Some(shape.map_err(|m| InvalidShape(format!("shape: {m}"))))
    }
}

message_error!(
    /// Shape parameters that describe no shape, with what is wrong.
    InvalidShape
);

fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// `azimuth = [from, to]` (degrees) as a range; absent = the full circle.
fn azimuth(a: &Option<[f64; 2]>) -> Result<AzimuthRange, InvalidShape> {
    match a {
        None => Ok(AzimuthRange::FULL),
        Some([from, to])
            if from.is_finite() && to.is_finite() && to > from && to - from <= 360.0 =>
        {
            Ok(AzimuthRange::new(*from, to - from))
        }
        Some(_) => Err("azimuth = [from, to] needs from < to ≤ from + 360 (degrees)".into()),
    }
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

impl ConeDesc {
    fn build(&self) -> Result<Shape, InvalidShape> {
        let c = self;
        if !all_finite(&[c.radius_start, c.radius_end, c.z_start, c.z_end])
            || c.radius_start < 0.0
            || c.radius_end < 0.0
            || c.z_start == c.z_end
            || (c.radius_start == 0.0 && c.radius_end == 0.0)
        {
            return Err("cone needs radii ≥ 0 (not both 0) and z_start ≠ z_end".into());
        }
        Ok(Shape::Revolution(RevolutionQuadric::cone(
            c.radius_start,
            c.z_start,
            c.radius_end,
            c.z_end,
            azimuth(&c.azimuth)?,
        )))
    }
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

impl CylinderDesc {
    fn build(&self) -> Result<Shape, InvalidShape> {
        let c = self;
        if !all_finite(&[c.radius, c.z_start, c.z_end]) || c.radius <= 0.0 || c.z_start == c.z_end {
            return Err("cylinder needs radius > 0 and z_start ≠ z_end".into());
        }
        Ok(Shape::Revolution(RevolutionQuadric::cylinder(
            c.radius,
            c.z_start,
            c.z_end,
            azimuth(&c.azimuth)?,
        )))
    }
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct ParaboloidDesc {
    /// Vertex-to-focus distance q (mm).
    pub focal_length: f64,
    /// Where the focus lies on the axis (default 0).
    #[serde(default)]
    pub focus_z: f64,
    pub z_start: f64,
    pub z_end: f64,
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

impl ParaboloidDesc {
    fn build(&self) -> Result<Shape, InvalidShape> {
        let p = self;
        if !all_finite(&[p.focal_length, p.focus_z, p.z_start, p.z_end])
            || p.focal_length <= 0.0
            || p.z_start == p.z_end
            || p.z_start.min(p.z_end) - p.focus_z < -p.focal_length
        {
            return Err("paraboloid needs focal_length > 0 and z_start ≠ z_end, both ≥ focus_z − focal_length (the vertex)".into());
        }
        Ok(Shape::Revolution(RevolutionQuadric::paraboloid(
            p.focal_length,
            p.focus_z,
            p.z_start,
            p.z_end,
            azimuth(&p.azimuth)?,
        )))
    }
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct HyperboloidDesc {
    pub semi_axis_a: f64,
    pub semi_axis_b: f64,
    /// Where the centre lies on the axis (default 0).
    #[serde(default)]
    pub center_z: f64,
    pub z_start: f64,
    pub z_end: f64,
    #[serde(default)]
    pub azimuth: Option<[f64; 2]>,
}

impl HyperboloidDesc {
    fn build(&self) -> Result<Shape, InvalidShape> {
        let h = self;
        let (lo, hi) = (h.z_start.min(h.z_end), h.z_start.max(h.z_end));
        let (lo_c, hi_c) = (lo - h.center_z, hi - h.center_z);
        if !all_finite(&[h.semi_axis_a, h.semi_axis_b, h.center_z, lo, hi])
            || h.semi_axis_a <= 0.0
            || h.semi_axis_b <= 0.0
            || lo == hi
            || !(lo_c >= h.semi_axis_a || hi_c <= -h.semi_axis_a)
        {
            return Err(InvalidShape::from(
                "hyperboloid needs semi axes > 0 and a z range on one sheet (|z − center_z| ≥ semi_axis_a)",
            ));
        }
        Ok(Shape::Revolution(RevolutionQuadric::hyperboloid(
            h.semi_axis_a,
            h.semi_axis_b,
            h.center_z,
            h.z_start,
            h.z_end,
            azimuth(&h.azimuth)?,
        )))
    }
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

impl DiskDesc {
    fn build(&self) -> Result<Shape, InvalidShape> {
        let c = self;
        if !all_finite(&[c.radius, c.inner_radius])
            || c.radius <= 0.0
            || c.inner_radius < 0.0
            || c.inner_radius >= c.radius
        {
            return Err("disk needs 0 ≤ inner_radius < radius".into());
        }
        Ok(Shape::Disk(Disk {
            inner_radius: c.inner_radius,
            outer_radius: c.radius,
            azimuth: azimuth(&c.azimuth)?,
        }))
    }
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct RectangleDesc {
    pub size: [f64; 2],
}

impl RectangleDesc {
    fn build(&self) -> Result<Shape, InvalidShape> {
        if !all_finite(&self.size) || self.size.iter().any(|v| *v <= 0.0) {
            return Err("rectangle needs size = [width, height] > 0".into());
        }
        Ok(Shape::Rectangle(Rectangle {
            width: self.size[0],
            height: self.size[1],
        }))
    }
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct BoxDesc {
    pub size: [f64; 3],
}

impl BoxDesc {
    fn build(&self) -> Result<Shape, InvalidShape> {
        if !all_finite(&self.size) || self.size.iter().any(|v| *v <= 0.0) {
            return Err("box needs size = [x, y, z] > 0".into());
        }
        Ok(Shape::Cuboid(Cuboid {
            size: DVec3::from(self.size),
        }))
    }
}

#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct SphereDesc {
    pub radius: f64,
}

impl SphereDesc {
    fn build(&self) -> Result<Shape, InvalidShape> {
        if !self.radius.is_finite() || self.radius <= 0.0 {
            return Err("sphere needs radius > 0".into());
        }
        Ok(Shape::Sphere(Sphere {
            radius: self.radius,
        }))
    }
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

/// Tessellation resolution of an analytic shape.
#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub struct TessellateDesc {
    /// Divisions around the azimuth range (x divisions for a rectangle, along
    /// the first in-plane axis of each face of a box).
    pub segments: usize,
    /// Divisions along the axis (radial for a disk, y for a rectangle, the
    /// second in-plane axis of a box face, pole to pole for a sphere).
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
