//! The pinhole camera: position, look-at point, up vector, vertical field of view.

use glam::DVec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub look_from: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view, degrees.
    pub vfov: f64,
}

/// The camera's frame for an image of a given aspect ratio.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    origin: DVec3,
    /// Upper-left corner of the image plane at distance 1, and the full extents.
    corner: DVec3,
    horizontal: DVec3,
    vertical: DVec3,
}

impl Camera {
    /// Checks the camera; the message names what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let forward = self.look_at - self.look_from;
        if !(self.look_from.is_finite() && self.look_at.is_finite() && self.up.is_finite()) {
            return Err("look_from, look_at and up must be finite".into());
        }
        if !crate::geometry::within_world(&[self.look_from, self.look_at]) {
            return Err(format!(
                "look_from and look_at must lie within ±{:e} mm of the origin",
                crate::geometry::WORLD_LIMIT_MM
            ));
        }
        if forward.length() == 0.0 {
            return Err("look_from and look_at must differ".into());
        }
        if forward.cross(self.up).length() <= 1e-9 * forward.length() * self.up.length() {
            return Err("up must not be parallel to the viewing direction".into());
        }
        if !(self.vfov > 0.0 && self.vfov < 180.0) {
            return Err(format!(
                "vfov = {}: expected 0 < vfov < 180 degrees",
                self.vfov
            ));
        }
        Ok(())
    }

    pub(super) fn frame(&self, aspect: f64) -> Frame {
        let w = (self.look_from - self.look_at).normalize();
        let u = self.up.cross(w).normalize();
        let v = w.cross(u);
        let half_h = (0.5 * self.vfov.to_radians()).tan();
        let half_w = aspect * half_h;
        Frame {
            origin: self.look_from,
            corner: -w - u * half_w + v * half_h,
            horizontal: u * (2.0 * half_w),
            vertical: -v * (2.0 * half_h),
        }
    }
}

impl Frame {
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
