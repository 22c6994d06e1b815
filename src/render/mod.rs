//! Visible-light renders of a scene (SPEC §7): a pinhole camera, simple surface
//! appearances and a path tracer over the very same Embree scene the X-rays use,
//! so a user sees exactly the geometry being traced.
//!
//! Data flow: the scene build gives every object an `Appearance` (from its
//! `appearance` table, or a default for its X-ray material) and reads the
//! `[cameras]` and `[sky]`; `traxer render` calls [`render`] with a [`Camera`] and
//! writes the gamma-corrected PNG; an X-ray sensor image can be shown on the
//! sensor's face ([`SensorTexture`]). Rays are cast by `raycast`, as for X-rays.

mod camera;
mod integrator;
mod labels;

pub use crate::scene::{Appearance, Camera, Sky};
pub use integrator::{
    overview_camera, render, render_pass, render_with_progress, to_srgb8, RenderSettings,
    SensorTexture,
};
pub use labels::{part_labels, PartLabel};
