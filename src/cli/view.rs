//! `traxer view`: the live window (SPEC §7). Its arguments live here; the window
//! itself is in `view_window` (cargo feature `window`, on by default), so that a
//! build without it still knows the command and says why it cannot open one
//! (`cli::view` chooses).

use super::args::{SamplingArgs, SceneArgs};
use std::path::PathBuf;

/// Fly through the scene while the X-ray image builds up on its sensors.
///
/// Opens a window (X11 or Wayland, no GPU needed) showing the scene from one of
/// its cameras (default: the only one, else a view of the whole scene). The
/// picture refines while the camera is still and is coarse while it moves; the
/// scene's sources emit photons in a background thread and the sensors glow with
/// their flux (viridis), with the photon count and live HPD in the title.
///
/// Keys: mouse drag (left button) to look around; W/A/S/D or the arrows to move,
/// E/Q up/down; PageUp/PageDown speed ×2/÷2; R back to the camera; C next camera
/// of the scene; F2 save the sensor images (the files of `traxer trace`) and the
/// frame (frame.png) into --save; P print the camera as a [cameras.NAME] table;
/// H or F1 help on screen; Esc quit.
#[derive(clap::Args)]
pub struct ViewArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The scene camera to start from (default: the only one, or a view of the
    /// whole scene).
    #[arg(value_name = "NAME", long)]
    pub camera: Option<String>,
    /// Window width in pixels.
    #[arg(value_name = "PX", long, default_value_t = 640)]
    pub width: usize,
    /// Window height in pixels.
    #[arg(value_name = "PX", long, default_value_t = 400)]
    pub height: usize,
    /// Bounces after which a light path stops.
    #[arg(value_name = "N", long, default_value_t = 6)]
    pub max_depth: u32,
    /// Stop the X-rays after this many photons (default: run until the window
    /// closes).
    #[arg(value_name = "N", long, value_parser = super::args::parse_count)]
    pub photons: Option<u64>,
    /// Show the sensors' flux on a log scale over N decades (default linear).
    #[arg(value_name = "N", long)]
    pub log_decades: Option<u32>,
    /// Radiance of the brightest sensor pixel (1 = as bright as a white sky).
    #[arg(value_name = "B", long, default_value_t = 1.5)]
    pub brightness: f64,
    /// Where F2 (and --frames) saves the sensor images and the frame.
    #[arg(value_name = "DIR", long, default_value = "out/view")]
    pub save: PathBuf,
    /// For scripts and tests: show N frames (and, with --photons, wait for the
    /// X-rays to reach them), save into --save, and close.
    #[arg(value_name = "N", long)]
    pub frames: Option<u64>,
    /// Start with the help on screen (as H does).
    #[arg(long)]
    pub show_help: bool,
    #[command(flatten)]
    pub sampling: SamplingArgs,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}
