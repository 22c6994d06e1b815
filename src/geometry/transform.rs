//! Rigid and scaling placements of objects: local frame → world frame.

use glam::{DAffine3, DMat3, DVec3};

/// An affine map from an object's local frame to the world, with its inverse and
/// the matrix that carries normals (inverse transpose) precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub to_world: DAffine3,
    pub to_local: DAffine3,
    normal_to_world: DMat3,
    /// The identity map (the shells of a telescope sit in the world frame).
    identity: bool,
}

impl Default for Transform {
    fn default() -> Self {
        Transform::from_affine(DAffine3::IDENTITY)
    }
}

impl Transform {
    /// Wraps an invertible affine map (the caller checks the determinant).
    pub fn from_affine(to_world: DAffine3) -> Transform {
        let to_local = to_world.inverse();
        Transform {
            to_world,
            to_local,
            normal_to_world: to_local.matrix3.transpose(),
            identity: to_world == DAffine3::IDENTITY,
        }
    }

    /// `then` applied after `self`.
    pub fn then(&self, then: &Transform) -> Transform {
        Transform::from_affine(then.to_world * self.to_world)
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.to_world.transform_point3(p)
    }

    /// World-space axis-aligned box around a local box: its eight mapped corners
    /// (exact without rotations, an enclosing box with them).
    pub fn box_to_world(&self, lo: DVec3, hi: DVec3) -> (DVec3, DVec3) {
        (0..8)
            .map(|i| {
                self.point(DVec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                ))
            })
            .fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(a, b), p| (a.min(p), b.max(p)),
            )
    }

    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.to_world.transform_vector3(v)
    }

    /// World-space unit normal of a local normal.
    pub fn normal(&self, n: DVec3) -> DVec3 {
        (self.normal_to_world * n).normalize()
    }

    #[inline]
    pub fn is_identity(&self) -> bool {
        self.identity
    }

    /// Whether the map turns right-handed frames into left-handed ones (a mirror
    /// image), which flips triangle winding.
    pub fn flips_orientation(&self) -> bool {
        self.to_world.matrix3.determinant() < 0.0
    }
}
