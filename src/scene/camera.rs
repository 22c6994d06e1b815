//! Named cameras for visible-light renders (`[cameras.NAME]`): the pinhole
//! camera's position, look-at point, up vector and field of view, checked.

use crate::geometry::{within_world, WORLD_LIMIT_MM};
use glam::DVec3;
use serde::Deserialize;

message_error!(
    /// A camera that cannot take a picture, with what is wrong.
    InvalidCamera
);

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub look_from: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view, degrees.
    pub vfov: f64,
}

impl Camera {
    /// Checks the camera; the message names what is wrong.
    pub fn validate(&self) -> Result<(), InvalidCamera> {
        let forward = self.look_at - self.look_from;
        if !(self.look_from.is_finite() && self.look_at.is_finite() && self.up.is_finite()) {
            return Err("look_from, look_at and up must be finite".into());
        }
        if !within_world(&[self.look_from, self.look_at]) {
            return Err(InvalidCamera::from(format!(
                "look_from and look_at must lie within ±{WORLD_LIMIT_MM:e} mm of the origin"
            )));
        }
        if forward.length() == 0.0 {
            return Err("look_from and look_at must differ".into());
        }
        if forward.cross(self.up).length() <= 1e-9 * forward.length() * self.up.length() {
            return Err("up must not be parallel to the viewing direction".into());
        }
        if !(self.vfov > 0.0 && self.vfov < 180.0) {
            return Err(InvalidCamera::from(format!(
                "vfov = {}: expected 0 < vfov < 180 degrees",
                self.vfov
            )));
        }
        Ok(())
    }
}

/// A camera for visible-light renders.
///
/// ```toml
/// [cameras.overview]
/// look_from = [600.0, 300.0, 800.0]
/// look_at = [0.0, 0.0, -700.0]
/// up = [0.0, 1.0, 0.0]      # default +y
/// vfov = 30.0               # vertical field of view, degrees
/// ```
#[derive(Debug, Deserialize, Clone)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    pub look_from: [f64; 3],
    pub look_at: [f64; 3],
    #[serde(default = "y_up")]
    pub up: [f64; 3],
    pub vfov: f64,
}

pub(super) fn y_up() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}

impl CameraDesc {
    pub fn build(&self) -> Result<Camera, InvalidCamera> {
        let camera = Camera {
            look_from: DVec3::from(self.look_from),
            look_at: DVec3::from(self.look_at),
            up: DVec3::from(self.up),
            vfov: self.vfov,
        };
        camera.validate()?;
        Ok(camera)
    }
}
