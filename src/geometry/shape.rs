//! The interface every analytic shape implements ([`Surface`]), the closed set of
//! shapes that dispatches to it ([`Shape`], matched, never boxed: it sits in the
//! photon path), and an analytic shape placed in the world ([`AnalyticObject`]).

use super::{
    AzimuthRange, Cuboid, Disk, Rectangle, RevolutionQuadric, Sphere, Transform, TriangleMesh,
};
use glam::DVec3;

/// Tessellation resolution: `segments` around the azimuth (or along x for a
/// rectangle, along a box face's first axis), `rings` along the axis (or radius,
/// or y, or the face's second axis; pole to pole for a sphere).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Resolution {
    pub segments: usize,
    pub rings: usize,
}

impl std::str::FromStr for Resolution {
    type Err = String;

    /// `SEGMENTSxRINGS` with positive integers, e.g. `120x4` (`traxer compare
    /// --resolutions`, Python's `Scene.compare`).
    fn from_str(s: &str) -> Result<Resolution, String> {
        let bad =
            || format!("expected SEGMENTSxRINGS with positive integers, e.g. 120x4, got `{s}`");
        let (a, b) = s.trim().split_once(['x', 'X']).ok_or_else(bad)?;
        let segments: usize = a.trim().parse().map_err(|_| bad())?;
        let rings: usize = b.trim().parse().map_err(|_| bad())?;
        if segments == 0 || rings == 0 {
            return Err(bad());
        }
        Ok(Resolution { segments, rings })
    }
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
        let (lo, ld) = self.local_ray(o, d);
        self.shape.intersect(lo, ld, t_max, starts_on_surface)
    }

    /// A world-space ray in the local frame.
    #[inline]
    fn local_ray(&self, o: DVec3, d: DVec3) -> (DVec3, DVec3) {
        if self.transform.is_identity() {
            (o, d)
        } else {
            let m = &self.transform.to_local;
            (m.transform_point3(o), m.transform_vector3(d))
        }
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

/// Azimuth sectors wider than this are cut for their bounding boxes (the LLNL
/// shells' 30° segments stay whole).
const SPLIT_ABOVE_DEG: f64 = 90.0;
/// The longest arc (mm) and radial length of a piece of a cut surface.
const PIECE_MAX_MM: f64 = 20.0;

/// A piece of a cut surface: an azimuth sector and, for a disk, a ring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    pub azimuth: AzimuthRange,
    pub inner_radius: f64,
    pub outer_radius: f64,
}

impl Shape {
    /// This shape restricted to `piece` (a surface of revolution or a disk).
    #[inline]
    pub fn piece(&self, piece: &Piece) -> Shape {
        let mut shape = *self;
        match &mut shape {
            Shape::Revolution(q) => q.azimuth = piece.azimuth,
            Shape::Disk(d) => {
                d.azimuth = piece.azimuth;
                d.inner_radius = piece.inner_radius;
                d.outer_radius = piece.outer_radius;
            }
            _ => {}
        }
        shape
    }
}

impl AnalyticObject {
    /// Cuts the object into pieces with tight bounding boxes, which together are
    /// the same surface; none when it stays whole. A full-circle shell's box
    /// holds every shell nested inside it, so an unsplit nested telescope sends
    /// each ray through every shell's intersection test; cut into sectors of
    /// at most 10 mm of arc, a piece's box holds only its neighbours'. Disks
    /// longer than 10 mm radially (a spider's arms) are also cut into rings.
    /// Surfaces within 90° of azimuth and small disks stay whole (the LLNL
    /// shells' 30° segments).
    pub fn pieces(&self) -> Vec<Piece> {
        let (azimuth, r_min, r_max) = match &self.shape {
            Shape::Revolution(q) => {
                let (lo, hi) = q.radius_range();
                (q.azimuth, lo, hi)
            }
            Shape::Disk(d) => (d.azimuth, d.inner_radius, d.outer_radius),
            _ => return vec![],
        };
        let disk = matches!(self.shape, Shape::Disk(_));
        let span = azimuth.span_deg().min(360.0);
        let radial = if disk { r_max - r_min } else { 0.0 };
        if span <= SPLIT_ABOVE_DEG && radial <= PIECE_MAX_MM {
            return vec![];
        }
        let rings = ((radial / PIECE_MAX_MM).ceil() as usize).clamp(1, 256);
        let edge = |k: usize| {
            if k == rings {
                r_max
            } else {
                r_min + (r_max - r_min) * k as f64 / rings as f64
            }
        };
        let mut pieces = Vec::new();
        for ring in 0..rings {
            let (inner, outer) = (edge(ring), edge(ring + 1));
            let arc = span.to_radians() * outer;
            let n = if span <= SPLIT_ABOVE_DEG {
                1
            } else {
                (arc / PIECE_MAX_MM).ceil().clamp(1.0, 4096.0) as usize
            };
            pieces.extend(azimuth.sectors(n).into_iter().map(|azimuth| Piece {
                azimuth,
                inner_radius: inner,
                outer_radius: outer,
            }));
        }
        pieces
    }

    /// [`AnalyticObject::intersect_world`] on one piece of the shape.
    #[inline]
    pub fn intersect_piece(
        &self,
        piece: &Piece,
        o: DVec3,
        d: DVec3,
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64> {
        let (lo, ld) = self.local_ray(o, d);
        self.shape
            .piece(piece)
            .intersect(lo, ld, t_max, starts_on_surface)
    }

    /// World-space bounds of one piece.
    pub fn piece_bounds(&self, piece: &Piece) -> (DVec3, DVec3) {
        let (lo, hi) = self.shape.piece(piece).bounds();
        self.transform.box_to_world(lo, hi)
    }
}
