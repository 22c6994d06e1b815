//! The pinhole camera's ray generation: a scene's `Camera` (look-from, look-at,
//! up, field of view) as a frame that maps image positions to rays.

use crate::scene::Camera;
use glam::DVec3;

/// The camera's frame for an image of a given aspect ratio.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    origin: DVec3,
    /// Upper-left corner of the image plane at distance 1, and the full extents.
    corner: DVec3,
    horizontal: DVec3,
    vertical: DVec3,
}

impl Frame {
    pub(super) fn new(camera: &Camera, aspect: f64) -> Frame {
        let w = (camera.look_from - camera.look_at).normalize();
        let u = camera.up.cross(w).normalize();
        let v = w.cross(u);
        let half_h = (0.5 * camera.vfov.to_radians()).tan();
        let half_w = aspect * half_h;
        Frame {
            origin: camera.look_from,
            corner: -w - u * half_w + v * half_h,
            horizontal: u * (2.0 * half_w),
            vertical: -v * (2.0 * half_h),
        }
    }

    /// Unit direction through image position (s, t) ∈ [0, 1]², (0, 0) the
    /// upper-left corner, s to the right, t down.
    #[inline]
    pub(super) fn ray(&self, s: f64, t: f64) -> (DVec3, DVec3) {
        (
            self.origin,
            (self.corner + self.horizontal * s + self.vertical * t).normalize(),
        )
    }
}
