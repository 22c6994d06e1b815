//! Scenes: the TOML file format ([`desc`]), variables ([`vars`]), and the build step
//! that validates a description and instantiates it with Embree ([`Scene::load`]).
//!
//! Data flow: scene.toml ─substitute vars─▶ text ─serde─▶ `SceneDesc`
//! ─build─▶ `Scene` (immutable, shared by all tracing threads).

mod build;
pub mod desc;
mod error;
pub mod llnl;
mod vars;

pub use build::{
    analytic_shapes, inline_shape, MeshObject, NamedShape, Object, ObjectGeometry, Representation,
    Scene,
};
pub use error::SceneError;
