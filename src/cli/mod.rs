//! Subcommands of the `traxer` binary, thin: each parses its arguments (the
//! shared groups in [`args`]), calls the library (scene, trace, studies, render),
//! hands the results to `output`, and prints. Physics comes from the scene file;
//! these modules only handle I/O-side settings (photons, seed, threads, output
//! folder). Progress bars are drawn here ([`progress`]), never in the library.

/// `println!` that never panics: once stdout is closed (`traxer ... | head`) the
/// rest is dropped and the run goes on; its exit code is what the run deserves.
macro_rules! say {
    ($($t:tt)*) => {
        $crate::cli::say_line(format_args!($($t)*))
    };
}

/// `eprintln!` that never panics: with stderr closed (`traxer ... 2>&1 | true`)
/// warnings and messages are dropped, and the run is not killed for it.
macro_rules! tell {
    ($($t:tt)*) => {
        $crate::cli::tell_line(format_args!($($t)*))
    };
}

pub mod args;
pub mod bench;
pub mod cache;
mod campaign_reach;
pub mod compare;
pub mod conversion;
pub mod eef;
pub mod effective_area;
pub mod fit_figure_error;
pub mod focus;
pub mod info;
pub mod inspect;
pub mod merge;
pub mod progress;
pub mod psf;
pub mod reach;
pub mod reflectivity;
pub mod render;
pub mod report;
pub mod resume;
pub mod signal;
pub mod signals;
pub mod solar_flux;
pub mod study;
pub mod synopsis;
pub mod systematics;
pub mod tessellate;
pub mod trace;
pub mod view;
#[cfg(feature = "window")]
pub mod view_controls;
#[cfg(feature = "window")]
pub mod view_window;

use args::SceneArgs;

/// `traxer view`: the live window, or why this build has none.
pub fn view(a: view::ViewArgs) -> anyhow::Result<()> {
    #[cfg(feature = "window")]
    {
        view_window::run(a)
    }
    #[cfg(not(feature = "window"))]
    {
        let _ = a;
        Err(InputError(
            "this traxer was built without the live window (cargo feature `window`); build it with the default features".into(),
        )
        .into())
    }
}
use traxer::embree::Device;
use traxer::scene::Scene;

/// A usage problem the user can fix (exit code 2), and a run stopped on a
/// signal after writing its checkpoint (exit code 130; the message says how to
/// continue): the library's, so that its front ends agree.
pub use traxer::run::{InputError, Stopped};

/// This command line, for the provenance of what it writes.
pub fn invocation() -> traxer::run::Invocation {
    traxer::run::Invocation::new(std::env::args())
}

/// Whether a run stopped on a signal after writing its checkpoint (exit 130).
pub fn is_stopped(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.is::<Stopped>()
            || matches!(
                c.downcast_ref::<traxer::run::RunError>(),
                Some(traxer::run::RunError::Stopped(_))
            )
    })
}

/// Whether an error is the user's input (exit code 2) rather than a failed run.
pub fn is_input_error(e: &anyhow::Error) -> bool {
    e.chain()
        .any(|c| c.is::<InputError>() || traxer::is_bad_input(c))
}

/// Prints a scene's warnings once each, however often it is loaded.
#[derive(Default)]
pub struct Warnings(std::collections::BTreeSet<String>);

impl Warnings {
    /// Marks the scene's warnings as shown (its load showed them already).
    pub fn seen(&mut self, scene: &Scene) {
        self.0.extend(scene.warnings.iter().cloned());
    }

    pub fn show(&mut self, scene: &Scene) {
        for w in &scene.warnings {
            if self.0.insert(w.clone()) {
                tell!("warning: {w}");
            }
        }
    }
}

/// Loads a scene with a fresh Embree device (returned too: it reports the
/// version), printing the scene's warnings.
pub fn load_scene(a: &SceneArgs) -> anyhow::Result<(Device, Scene)> {
    let device = Device::new()?;
    let scene = Scene::load(&device, &a.scene, &a.vars.define)?;
    Warnings::default().show(&scene);
    Ok((device, scene))
}

/// Loads a scene for X-ray tracing: as [`load_scene`], and it must have sources.
pub fn load_xray_scene(a: &SceneArgs) -> anyhow::Result<(Device, Scene)> {
    let (device, scene) = load_scene(a)?;
    traxer::studies::require_sources(&scene)?;
    Ok((device, scene))
}

/// Writes one line to stdout; see [`say!`]. After the first failed write (a
/// closed pipe, a full disk) nothing more is tried.
pub fn say_line(text: std::fmt::Arguments) {
    use std::io::Write;
    use std::sync::atomic::{AtomicBool, Ordering};
    static CLOSED: AtomicBool = AtomicBool::new(false);
    if CLOSED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    let result = out
        .write_fmt(text)
        .and_then(|_| out.write_all(b"\n"))
        .and_then(|_| out.flush());
    if let Err(e) = result {
        CLOSED.store(true, Ordering::Relaxed);
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            tell!("warning: cannot write to standard output: {e}");
        }
    }
}

/// Writes one line to stderr; see [`tell!`]. Errors are ignored: there is no one
/// left to tell.
pub fn tell_line(text: std::fmt::Arguments) {
    use std::io::Write;
    let mut err = std::io::stderr().lock();
    let _ = err.write_fmt(text).and_then(|_| err.write_all(b"\n"));
}
