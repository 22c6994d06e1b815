//! The closed set of analytic shapes, and an analytic shape placed in the world.

use super::{Cuboid, Disk, Rectangle, RevolutionQuadric, Sphere, Transform};
use crate::embree::UserGeometry;
use crate::mesh::TriangleMesh;
use glam::DVec3;

/// Tessellation resolution: `segments` around the azimuth (or along x for a
/// rectangle), `rings` along the axis (or radius, or y).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Resolution {
    pub segments: usize,
    pub rings: usize,
}

/// An analytic shape in its local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// Cone, cylinder, paraboloid and hyperboloid sections.
    Revolution(RevolutionQuadric),
    Disk(Disk),
    Rectangle(Rectangle),
    Cuboid(Cuboid),
    Sphere(Sphere),
}

impl Shape {
    /// Nearest hit (t in units of `d`) with 0 < t < t_max, in the local frame.
    #[inline]
    pub fn intersect(
        &self,
        o: DVec3,
        d: DVec3,
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64> {
        match self {
            Shape::Revolution(s) => s.intersect(o, d, t_max, starts_on_surface),
            Shape::Disk(s) => s.intersect(o, d, t_max, starts_on_surface),
            Shape::Rectangle(s) => s.intersect(o, d, t_max, starts_on_surface),
            Shape::Cuboid(s) => s.intersect(o, d, t_max, starts_on_surface),
            Shape::Sphere(s) => s.intersect(o, d, t_max, starts_on_surface),
        }
    }

    /// Unit front normal at a local surface point.
    #[inline]
    pub fn normal(&self, p: DVec3) -> DVec3 {
        match self {
            Shape::Revolution(s) => s.normal(p),
            Shape::Disk(s) => s.normal(),
            Shape::Rectangle(s) => s.normal(),
            Shape::Cuboid(s) => s.normal(p),
            Shape::Sphere(s) => s.normal(p),
        }
    }

    pub fn bounds(&self) -> (DVec3, DVec3) {
        match self {
            Shape::Revolution(s) => s.bounds(),
            Shape::Disk(s) => s.bounds(),
            Shape::Rectangle(s) => s.bounds(),
            Shape::Cuboid(s) => s.bounds(),
            Shape::Sphere(s) => s.bounds(),
        }
    }

    /// Triangle mesh of the shape in its local frame, with exact vertex normals,
    /// wound counter-clockwise seen from the front.
    pub fn tessellate(&self, res: Resolution) -> TriangleMesh {
        match self {
            Shape::Revolution(s) => s.tessellate(res),
            Shape::Disk(s) => s.tessellate(res),
            Shape::Rectangle(s) => s.tessellate(res),
            Shape::Cuboid(s) => s.tessellate(),
            Shape::Sphere(s) => s.tessellate(res),
        }
    }
}

/// An analytic shape placed in the world: what Embree sees as user geometry.
#[derive(Clone, Copy, Debug)]
pub struct AnalyticObject {
    pub shape: Shape,
    pub transform: Transform,
}

impl AnalyticObject {
    /// Nearest hit of a world-space ray. The affine map keeps t unchanged, so the
    /// local ray is simply the mapped origin and (unnormalised) direction.
    #[inline]
    pub fn intersect_world(
        &self,
        o: DVec3,
        d: DVec3,
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64> {
        let lo = self.transform.to_local.transform_point3(o);
        let ld = self.transform.to_local.transform_vector3(d);
        self.shape.intersect(lo, ld, t_max, starts_on_surface)
    }

    /// World-space front normal at a world-space surface point.
    pub fn normal_world(&self, p: DVec3) -> DVec3 {
        let lp = self.transform.to_local.transform_point3(p);
        self.transform.normal(self.shape.normal(lp))
    }

    /// World-space bounds: the eight mapped corners of the local box.
    pub fn world_bounds(&self) -> (DVec3, DVec3) {
        let (lo, hi) = self.shape.bounds();
        self.transform.box_to_world(lo, hi)
    }
}

impl UserGeometry for AnalyticObject {
    fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let (lo, hi) = self.world_bounds();
        // Pad so that f32 rounding of the box never cuts off the exact surface.
        let pad = 1e-6 * (lo.abs().max(hi.abs()).max_element() + 1.0);
        let down = |x: f64| ((x - pad) as f32).next_down();
        let up = |x: f64| ((x + pad) as f32).next_up();
        (
            [down(lo.x), down(lo.y), down(lo.z)],
            [up(hi.x), up(hi.y), up(hi.z)],
        )
    }

    fn intersect(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64> {
        self.intersect_world(
            DVec3::from(origin),
            DVec3::from(dir),
            t_max,
            starts_on_surface,
        )
    }
}
