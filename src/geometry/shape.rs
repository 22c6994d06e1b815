//! The interface every analytic shape implements ([`Surface`]), the closed set of
//! shapes that dispatches to it ([`Shape`], matched, never boxed: it sits in the
//! photon path), and an analytic shape placed in the world ([`AnalyticObject`]).

use super::{Cuboid, Disk, Rectangle, RevolutionQuadric, Sphere, Transform, TriangleMesh};
use glam::DVec3;

/// Tessellation resolution: `segments` around the azimuth (or along x for a
/// rectangle, along a box face's first axis), `rings` along the axis (or radius,
/// or y, or the face's second axis; pole to pole for a sphere).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Resolution {
    pub segments: usize,
    pub rings: usize,
}

/// An analytic surface in its own local frame (documented per shape), with a
/// front side: the side [`Surface::normal`] points to.
pub trait Surface {
    /// Nearest hit (t in units of `d`) with 0 < t < t_max of the local ray
    /// o + t·d. `starts_on_surface` says the ray leaves a point of this very
    /// surface (after a reflection): the root at t ≈ 0 is then the start point
    /// and is skipped, but a genuine second hit (a concave mirror) is not.
    fn intersect(&self, o: DVec3, d: DVec3, t_max: f64, starts_on_surface: bool) -> Option<f64>;

    /// Unit front normal at the local surface point `p`.
    fn normal(&self, p: DVec3) -> DVec3;

    /// Local axis-aligned bounds (lower, upper).
    fn bounds(&self) -> (DVec3, DVec3);

    /// Triangle mesh of the surface in its local frame at resolution `res`, with
    /// exact vertex normals, wound counter-clockwise seen from the front.
    fn tessellate(&self, res: Resolution) -> TriangleMesh;
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

/// `$call` on the shape inside `$shape`, whichever it is.
macro_rules! dispatch {
    ($shape:expr, $s:ident => $call:expr) => {
        match $shape {
            Shape::Revolution($s) => $call,
            Shape::Disk($s) => $call,
            Shape::Rectangle($s) => $call,
            Shape::Cuboid($s) => $call,
            Shape::Sphere($s) => $call,
        }
    };
}

impl Surface for Shape {
    #[inline]
    fn intersect(&self, o: DVec3, d: DVec3, t_max: f64, starts_on_surface: bool) -> Option<f64> {
        dispatch!(self, s => s.intersect(o, d, t_max, starts_on_surface))
    }

    #[inline]
    fn normal(&self, p: DVec3) -> DVec3 {
        dispatch!(self, s => s.normal(p))
    }

    fn bounds(&self) -> (DVec3, DVec3) {
        dispatch!(self, s => s.bounds())
    }

    fn tessellate(&self, res: Resolution) -> TriangleMesh {
        dispatch!(self, s => s.tessellate(res))
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
    /// local ray is simply the mapped origin and (unnormalised) direction; shapes
    /// placed by the identity (a telescope's shells) skip the mapping, which
    /// would give the same numbers.
    #[inline]
    pub fn intersect_world(
        &self,
        o: DVec3,
        d: DVec3,
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64> {
        let (lo, ld) = if self.transform.is_identity() {
            (o, d)
        } else {
            let m = &self.transform.to_local;
            (m.transform_point3(o), m.transform_vector3(d))
        };
        self.shape.intersect(lo, ld, t_max, starts_on_surface)
    }

    /// World-space front normal at a world-space surface point.
    #[inline]
    pub fn normal_world(&self, p: DVec3) -> DVec3 {
        if self.transform.is_identity() {
            // What the general branch gives for the identity, bit for bit (the
            // identity matrix maps exactly; the second normalisation stays).
            return self.shape.normal(p).normalize();
        }
        let lp = self.transform.to_local.transform_point3(p);
        self.transform.normal(self.shape.normal(lp))
    }

    /// World-space bounds: the eight mapped corners of the local box.
    pub fn world_bounds(&self) -> (DVec3, DVec3) {
        let (lo, hi) = self.shape.bounds();
        self.transform.box_to_world(lo, hi)
    }
}
