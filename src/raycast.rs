//! Ray casting over a built scene, shared by the X-ray photon loop (`trace`) and
//! the visible-light renderer (`render`): the query for a ray leaving a surface,
//! Embree's nearest hit refined in f64 into a [`SurfaceHit`] (exact point and
//! normals, and which object it is), and mirror reflection.

use crate::embree::{Query, INVALID_ID};
use crate::scene::{ObjectGeometry, Scene};
use glam::DVec3;

/// Where and how a ray met a surface, all in f64 world coordinates.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    pub object: usize,
    pub point: DVec3,
    /// Unit normal of the surface as built (the facet for meshes), on the front side.
    pub geometric_normal: DVec3,
    /// Unit normal used for reflection: interpolated for smooth meshes, else the
    /// geometric one.
    pub shading_normal: DVec3,
    /// Whether the surface is a triangle (its hit point came from f32 and the next
    /// ray must start off the surface) or analytic (exact; the next query just
    /// tells the shape the ray starts on it).
    pub on_mesh: bool,
}

/// Hook called with every Embree query (benchmarks record rays with it; the
/// ordinary run uses `()`, which compiles to nothing).
pub trait QueryHook {
    fn query(&mut self, q: &Query);
}

impl QueryHook for () {
    #[inline(always)]
    fn query(&mut self, _: &Query) {}
}

/// Offset (mm) that moves a point reliably off an f32 triangle it lies on: a few
/// f32 ulps of the largest coordinate, so it scales with the scene (pbrt's
/// OffsetRayOrigin idea; ~2e-4 mm at 100 mm).
#[inline]
fn surface_offset(p: DVec3) -> f64 {
    (p.abs().max_element() + 1.0) * (16.0 * f32::EPSILON as f64)
}

/// The query for a ray from `origin` along `dir` that leaves the surface `start`
/// (if any): off a triangle by a small offset to the side the ray goes to; from an
/// analytic surface exactly, telling the shape to ignore its own root at t ≈ 0.
#[inline]
pub fn query_leaving(origin: DVec3, dir: DVec3, start: Option<&SurfaceHit>) -> Query {
    let (origin, start_geometry) = match start {
        Some(h) if h.on_mesh => {
            let side = if dir.dot(h.geometric_normal) >= 0.0 {
                1.0
            } else {
                -1.0
            };
            (
                h.point + h.geometric_normal * (side * surface_offset(h.point)),
                INVALID_ID,
            )
        }
        Some(h) => (origin, h.object as u32),
        None => (origin, INVALID_ID),
    };
    Query {
        origin: origin.to_array(),
        dir: dir.to_array(),
        t_max: f64::INFINITY,
        start_geometry,
    }
}

/// Nearest surface along a ray; `start` is the surface the ray leaves, if any.
#[inline]
pub fn intersect(
    scene: &Scene,
    origin: DVec3,
    dir: DVec3,
    start: Option<&SurfaceHit>,
) -> Option<SurfaceHit> {
    intersect_query(scene, &query_leaving(origin, dir, start), &mut ())
}

#[inline]
pub fn intersect_query<H: QueryHook>(scene: &Scene, q: &Query, hook: &mut H) -> Option<SurfaceHit> {
    hook.query(q);
    let hit = scene.nearest_hit(q)?;
    let object = hit.geometry as usize;
    let origin = DVec3::from(q.origin);
    let dir = DVec3::from(q.dir);
    match &scene.objects[object].geometry {
        ObjectGeometry::Analytic(a) => {
            let point = origin + dir * hit.t;
            let n = a.normal_world(point);
            Some(SurfaceHit {
                object,
                point,
                geometric_normal: n,
                shading_normal: n,
                on_mesh: false,
            })
        }
        ObjectGeometry::Mesh(m) => {
            let prim = hit.primitive as usize;
            let (n, offset) = m.plane(prim);
            // Refine Embree's f32 distance on the f64 plane of the triangle.
            let denom = dir.dot(n);
            let (t, geometric_normal) = if denom != 0.0 {
                ((offset - n.dot(origin)) / denom, n)
            } else {
                // Degenerate triangle, or a ray in its plane: keep Embree's t and
                // face the ray.
                (hit.t, -dir.normalize())
            };
            let point = origin + dir * t;
            let shading_normal = match m.corner_normals(prim) {
                Some([n0, n1, n2]) => {
                    let (u, v) = (hit.u as f64, hit.v as f64);
                    let s = (n0 * (1.0 - u - v) + n1 * u + n2 * v)
                        .try_normalize()
                        .unwrap_or(geometric_normal);
                    // Keep the interpolated normal on the facet's front side.
                    if s.dot(geometric_normal) < 0.0 {
                        -s
                    } else {
                        s
                    }
                }
                None => geometric_normal,
            };
            Some(SurfaceHit {
                object,
                point,
                geometric_normal,
                shading_normal,
                on_mesh: true,
            })
        }
    }
}

/// Mirror reflection of `d` about unit normal `n`.
#[inline]
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - n * (2.0 * d.dot(n))
}
