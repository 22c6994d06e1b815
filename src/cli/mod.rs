//! Subcommands of the `traxer` binary. Physics comes from the scene file; these
//! modules only handle I/O-side settings (photons, seed, threads, output folder).

/// `println!` that treats a closed pipe (`traxer ... | head`) as the end of the
/// program rather than an error: the process exits quietly with code 0.
macro_rules! say {
    ($($t:tt)*) => {
        $crate::cli::say_line(format_args!($($t)*))
    };
}

pub mod bench;
pub mod compare;
pub mod eef;
pub mod fit_figure_error;
pub mod focus;
pub mod info;
pub mod inspect;
pub mod measure;
pub mod progress;
pub mod reflectivity;
pub mod render;
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

/// More worker threads than this is a typo, not a machine (and would take minutes
/// to start).
pub const MAX_THREADS: usize = 1024;

/// Parses `--threads N`: 0 (one per core) to [`MAX_THREADS`].
pub fn parse_threads(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if n <= MAX_THREADS => Ok(n),
        _ => Err(format!(
            "expected 0 (one per core) to {MAX_THREADS} worker threads, got `{s}`"
        )),
    }
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

/// Loads a scene for X-ray tracing: as [`load_scene`], and it must have sources.
pub fn load_xray_scene(
    path: &std::path::Path,
    defines: &[String],
) -> anyhow::Result<(traxer::embree::Device, traxer::scene::Scene)> {
    let (device, scene) = load_scene(path, defines)?;
    if scene.sources.is_empty() {
        return Err(InputError(format!(
            "{}: the scene has no [[sources]]: nothing to trace (a scene without sources can only be rendered)",
            path.display()
        ))
        .into());
    }
    Ok((device, scene))
}

/// Writes one line to stdout; see [`say!`].
pub fn say_line(text: std::fmt::Arguments) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let result = out.write_fmt(text).and_then(|_| out.write_all(b"\n"));
    if let Err(e) = result {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}
