//! How the objects of a scene are handed to Embree: meshes as f32 triangle
//! geometry, analytic shapes as user geometry that Embree only bounds and that
//! Rust intersects in f64 (`geometry` itself knows nothing of Embree).

use super::ObjectGeometry;
use crate::embree::{EmbreeError, SceneBuilder, UserGeometry};
use crate::geometry::AnalyticObject;
use glam::DVec3;

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

/// Attaches one object's geometry under Embree geometry id `id` (its index in
/// the scene); returns its number of triangles.
pub(super) fn attach(
    embree: &mut SceneBuilder<AnalyticObject>,
    id: u32,
    geometry: &ObjectGeometry,
) -> Result<usize, EmbreeError> {
    match geometry {
        ObjectGeometry::Analytic(a) => embree.add_user(id, *a).map(|_| 0),
        ObjectGeometry::Mesh(m) => {
            let v32: Vec<[f32; 3]> = m.positions.iter().map(|p| p.as_vec3().to_array()).collect();
            embree.add_triangles(id, &v32, &m.triangles)?;
            Ok(m.triangles.len())
        }
    }
}
