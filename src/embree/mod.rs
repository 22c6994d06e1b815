//! The only `unsafe` code in traxer: a thin, safe wrapper over Intel Embree's C API.
//!
//! Data flow: the scene build hands triangle meshes (world-space f32 vertices) and
//! analytic shapes (any type implementing [`UserGeometry`], intersected in f64 by
//! Rust) to a [`SceneBuilder`] (`scene.rs`, started from a [`Device`],
//! `device.rs`); [`SceneBuilder::commit`] turns it into a read-only
//! [`CommittedScene`] that every tracing thread shares; `raycast` asks it for the
//! nearest hit of one f64 ray at a time ([`CommittedScene::intersect`]), and
//! Embree calls back into the shapes (`callbacks.rs`).
//!
//! Embree 3 and 4 differ in a handful of calls (see ARCHITECTURE.md); `build.rs`
//! sets `cfg(embree3)` or `cfg(embree4)` from the headers it found, and the two
//! small files `version3.rs` and `version4.rs` hold every difference.
//!
//! Rules kept here:
//! * one [`Device`] with an error callback; the first error is stored and checked
//!   after each commit, never per ray;
//! * geometries are released right after they are attached (the scene owns them);
//! * scenes use `RTC_SCENE_FLAG_ROBUST`: without it grazing rays aimed at triangle
//!   seams leak through;
//! * user-geometry callbacks never unwind into C (an `extern "C"` function that
//!   panics aborts) and read the shape through a pointer to data the scene owns.
#![allow(unsafe_code)]

#[allow(
    non_upper_case_globals,
    non_camel_case_types,
    non_snake_case,
    dead_code,
    clippy::all
)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/embree_bindings.rs"));
}

mod callbacks;
mod device;
mod scene;
#[cfg(embree3)]
#[path = "version3.rs"]
mod version;
#[cfg(embree4)]
#[path = "version4.rs"]
mod version;

pub use device::{Device, DeviceInfo};
pub use scene::{CommittedScene, SceneBuilder};

/// `RTC_INVALID_GEOMETRY_ID` (a cast macro bindgen does not translate).
pub const INVALID_ID: u32 = u32::MAX;

/// Major version of the Embree library this build links (3 or 4).
#[cfg(embree3)]
pub const EMBREE_MAJOR: u32 = 3;
/// Major version of the Embree library this build links (3 or 4).
#[cfg(embree4)]
pub const EMBREE_MAJOR: u32 = 4;

/// Errors reported by Embree.
#[derive(Debug, thiserror::Error)]
pub enum EmbreeError {
    #[error("Embree could not create a device: {0}")]
    NoDevice(String),
    #[error("Embree reported an error ({code}): {message}")]
    Reported { code: u32, message: String },
    #[error("too many objects for Embree geometry ids: {0}")]
    TooManyGeometries(usize),
}

/// An analytic shape that Embree treats as user geometry: Embree only sees its
/// bounding box; the exact intersection is computed by Rust in f64.
///
/// One geometry may hold several primitives, each with its own box: parts of
/// one surface (a full-circle shell cut into azimuth sectors), so that Embree's
/// boxes stay tight. All primitives of a geometry are one surface to the caller.
pub trait UserGeometry: Send + Sync + 'static {
    /// How many primitives (≥ 1).
    fn primitive_count(&self) -> u32;
    /// World-space axis-aligned bounds (lower, upper) of primitive `primitive`,
    /// slightly padded by the caller.
    fn bounds(&self, primitive: u32) -> ([f32; 3], [f32; 3]);
    /// Distance `t` (in units of `dir`) to the nearest hit on primitive
    /// `primitive` with `t < t_max`.
    /// `starts_on_surface` is true when the ray leaves a point of this same
    /// surface (after a reflection): the root at t ≈ 0 must then be ignored, but a
    /// genuine second hit on the same (concave) surface must not.
    fn intersect(
        &self,
        primitive: u32,
        origin: [f64; 3],
        dir: [f64; 3],
        t_max: f64,
        starts_on_surface: bool,
    ) -> Option<f64>;
}

/// Embree's bound on ray origin and direction components (`FLT_LARGE` in its
/// sources); `Ray::valid()` rejects anything larger.
const EMBREE_FLT_LARGE: f32 = 1.844e18;

/// One ray query, in f64. Embree's triangle test sees the f32 rounding of it;
/// user geometry sees it exactly. A query Embree cannot represent misses.
#[derive(Clone, Copy, Debug)]
pub struct Query {
    pub origin: [f64; 3],
    /// Direction; need not be normalised (t is in its units).
    pub dir: [f64; 3],
    /// Only hits with t < t_max count (use `f64::INFINITY` for none).
    pub t_max: f64,
    /// Geometry id of the user-geometry surface the ray starts on, or [`INVALID_ID`].
    pub start_geometry: u32,
}

/// The nearest hit Embree found.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub geometry: u32,
    pub primitive: u32,
    /// Distance along the query direction: exact f64 for user geometry, Embree's
    /// f32 value for triangles (refine it in f64 if it matters).
    pub t: f64,
    /// Barycentric coordinates of a triangle hit (0 for user geometry).
    pub u: f32,
    pub v: f32,
}
