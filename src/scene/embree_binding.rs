//! How the objects of a scene are handed to Embree: meshes as f32 triangle
//! geometry, analytic shapes as user geometry that Embree only bounds and that
//! Rust intersects in f64 (`geometry` itself knows nothing of Embree); and a
//! nested telescope's shells searched by radius beside Embree ([`ShellSearch`]).

use super::ObjectGeometry;
use crate::embree::{CommittedScene, Device, EmbreeError, Hit, Query, SceneBuilder, UserGeometry};
use crate::geometry::{AnalyticObject, NestedShells, Piece};
use glam::DVec3;

/// What Embree holds of one analytic object: the object, whole (one Embree
/// primitive) or cut into pieces with tight boxes ([`AnalyticObject::pieces`],
/// one primitive each, 64 bytes: they share the object's transform).
pub struct AnalyticPieces {
    object: AnalyticObject,
    pieces: Box<[Piece]>,
}

impl AnalyticPieces {
    pub fn new(object: &AnalyticObject) -> AnalyticPieces {
        AnalyticPieces {
            object: *object,
            pieces: object.pieces().into_boxed_slice(),
        }
    }
}

impl UserGeometry for AnalyticPieces {
    fn primitive_count(&self) -> u32 {
        self.pieces.len().max(1) as u32
    }

    fn bounds(&self, primitive: u32) -> ([f32; 3], [f32; 3]) {
        let (lo, hi) = match self.pieces.get(primitive as usize) {
            Some(piece) => self.object.piece_bounds(piece),
            None => self.object.world_bounds(),
        };
        // Pad so that f32 rounding of the box never cuts off the exact surface.
        let pad = 1e-6 * (lo.abs().max(hi.abs()).max_element() + 1.0);
        let down = |x: f64| ((x - pad) as f32).next_down();
        let up = |x: f64| ((x + pad) as f32).next_up();
        (
            [down(lo.x), down(lo.y), down(lo.z)],
            [up(hi.x), up(hi.y), up(hi.z)],
        )
    }

    #[inline]
    fn intersect(
        &self,
        primitive: u32,
        origin: [f64; 3],
        dir: [f64; 3],
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64> {
        let (o, d) = (DVec3::from(origin), DVec3::from(dir));
        match self.pieces.get(primitive as usize) {
            Some(piece) => self
                .object
                .intersect_piece(piece, o, d, t_max, starts_on_surface),
            None => self.object.intersect_world(o, d, t_max, starts_on_surface),
        }
    }
}

/// Attaches one object's geometry under Embree geometry id `id` (its index in
/// the scene); returns its number of triangles.
pub(super) fn attach(
    embree: &mut SceneBuilder<AnalyticPieces>,
    id: u32,
    geometry: &ObjectGeometry,
) -> Result<usize, EmbreeError> {
    match geometry {
        ObjectGeometry::Analytic(a) => embree.add_user(id, AnalyticPieces::new(a)).map(|_| 0),
        ObjectGeometry::Mesh(m) => {
            let v32 = m.positions.iter().map(|p| p.as_vec3().to_array());
            embree.add_triangles(id, v32, m.triangles.clone())?;
            Ok(m.triangles.len())
        }
    }
}

/// A nested telescope's shells searched by radius ([`NestedShells`]), and
/// Embree for the other objects: the photon loop's nearest hit without
/// traversing a BVH over hundreds of shells (docs/speed.md, "A nested-shell
/// intersector": 2.3–2.6 × Embree's rate on XMM's and BabyIAXO's rays, same answers).
pub struct ShellSearch {
    pub shells: NestedShells,
    /// The scene's other objects (ids are still the objects' indices).
    pub rest: CommittedScene<AnalyticPieces>,
}

impl ShellSearch {
    /// For scenes with at least two surfaces of revolution about the z axis.
    pub fn of(
        device: &Device,
        objects: &[super::Object],
    ) -> Result<Option<ShellSearch>, EmbreeError> {
        let analytic = (0u32..)
            .zip(objects)
            .filter_map(|(id, o)| match &o.geometry {
                ObjectGeometry::Analytic(a) => Some((id, a)),
                ObjectGeometry::Mesh(_) => None,
            });
        let Some(shells) = NestedShells::of(analytic) else {
            return Ok(None);
        };
        let ids: std::collections::BTreeSet<u32> = shells.ids().collect();
        let rest = embree_without(device, objects, &|id| ids.contains(&id))?;
        Ok(Some(ShellSearch { shells, rest }))
    }

    /// The nearest hit of `q`: the nearest shell, unless Embree finds another
    /// object before it. A shell hit carries primitive 0 and u = v = 0 (an
    /// analytic hit's point and normal come from t and the shape).
    #[inline]
    pub fn intersect(&self, q: &Query) -> Option<Hit> {
        let (o, d) = (DVec3::from(q.origin), DVec3::from(q.dir));
        let shell = self.shells.nearest(o, d, q.t_max, q.start_geometry);
        let t_max = shell.map_or(q.t_max, |s| s.1);
        self.rest
            .intersect(&Query { t_max, ..*q })
            .or(shell.map(|(geometry, t)| Hit {
                geometry,
                primitive: 0,
                t,
                u: 0.0,
                v: 0.0,
            }))
    }
}

/// An Embree scene of `objects` without those `leave_out` names (ids stay the
/// objects' indices).
pub fn embree_without(
    device: &Device,
    objects: &[super::Object],
    leave_out: &dyn Fn(u32) -> bool,
) -> Result<CommittedScene<AnalyticPieces>, EmbreeError> {
    let mut embree = device.scene::<AnalyticPieces>();
    for (id, object) in (0u32..).zip(objects) {
        if !leave_out(id) {
            attach(&mut embree, id, &object.geometry)?;
        }
    }
    embree.commit()
}
