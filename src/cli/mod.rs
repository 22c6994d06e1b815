//! Subcommands of the `traxer` binary. Physics comes from the scene file; these
//! modules only handle I/O-side settings (photons, seed, threads, output folder).

pub mod bench;
pub mod eef;
pub mod info;
pub mod reflectivity;
pub mod tessellate;
pub mod trace;

use traxer::mesh::MeshError;
use traxer::scene::SceneError;

/// A usage problem the user can fix (exit code 2).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

/// Whether an error is the user's input (exit code 2) rather than a failed run.
pub fn is_input_error(e: &anyhow::Error) -> bool {
    e.chain()
        .any(|c| c.is::<SceneError>() || c.is::<MeshError>() || c.is::<InputError>())
}

/// Parses `-D name=value`, checking the shape only (the scene checks the name).
pub fn parse_define(s: &str) -> Result<String, String> {
    match s.split_once('=') {
        Some((k, _)) if !k.trim().is_empty() => Ok(s.to_string()),
        _ => Err(format!("expected name=value, got `{s}`")),
    }
}

/// Loads a scene with a fresh Embree device (returned too: it reports the
/// version), printing the scene's warnings.
pub fn load_scene(
    path: &std::path::Path,
    defines: &[String],
) -> anyhow::Result<(traxer::embree::Device, traxer::scene::Scene)> {
    let device = traxer::embree::Device::new()?;
    let scene = traxer::scene::Scene::load(&device, path, defines)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok((device, scene))
}
