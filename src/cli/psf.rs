//! `traxer psf`: the PSF library, the telescope's image over a grid of
//! energies, off-axis angles and azimuths (`traxer::studies::psf`).

use super::args::{parse_values, OutputArgs, SamplingArgs, SceneArgs};
use traxer::studies::psf::PsfGrid;

/// PSF library: images of a source at infinity over energies × off-axis angles ×
/// azimuths, for X-ray simulators.
///
/// The scene's only source must be a parallel beam (as for effective-area); at
/// each point it is tilted by the angle (arcmin) towards the azimuth (degrees,
/// as its off_axis_azimuth) and emits the one energy; --photons photons are
/// traced with the trace's random streams, so a point equals `traxer trace` of
/// the scene set to that angle and energy. A --window of pixels around each
/// image's centroid is kept, normalised to 1. Writes psf.fits (one image per
/// HDU with ENERGY [eV], THETA [arcmin], PHI [deg] and DETX/DETY in m: the
/// layout SIXTE reads, OGIP CAL/GEN/92-027), psf.npy [angle, azimuth, energy,
/// iy, ix] and psf.json. Example (XMM-Newton at three energies, 0–15′):
///   traxer psf scenes/xmm_effective_area.toml -D figure_error=xmm_newton --energies 1.5,4,8 --angles 0:15:5 --window 201
/// (the module's fitted figure error: without it the mirrors are perfect, and
/// the command says so)
#[derive(clap::Args)]
pub struct PsfArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Energies (keV): a,b,c or start:stop:step.
    #[arg(value_name = "E", long, default_value = "1.5")]
    pub energies: String,
    /// Off-axis angles (arcmin): a,b,c or start:stop:step.
    #[arg(
        value_name = "ARCMIN",
        long,
        default_value = "0",
        allow_hyphen_values = true
    )]
    pub angles: String,
    /// Azimuths of the tilt (degrees): a,b,c or start:stop:step.
    #[arg(
        value_name = "DEG",
        long,
        default_value = "0",
        allow_hyphen_values = true
    )]
    pub azimuths: String,
    /// Photons traced per point.
    #[arg(short = 'n', long, value_name = "N", default_value = "200000", value_parser = super::args::parse_count)]
    pub photons: u64,
    /// Sensor to image on (default: the scene's only sensor).
    #[arg(value_name = "NAME", long)]
    pub sensor: Option<String>,
    /// Pixels per side of each image's window around its centroid.
    #[arg(value_name = "PIXELS", long, default_value = "101")]
    pub window: u32,
    /// Continue the stopped library whose results folder is --out: run the same
    /// command with --resume; the points it recorded (psf_checkpoint.jsonl) are
    /// not traced again.
    #[arg(long)]
    pub resume: bool,
    #[command(flatten)]
    pub sampling: SamplingArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

pub fn run(a: PsfArgs) -> anyhow::Result<()> {
    let g = PsfGrid {
        energies: parse_values("energies", &a.energies)?,
        angles_arcmin: parse_values("angles", &a.angles)?,
        azimuths_deg: parse_values("azimuths", &a.azimuths)?,
        sampling: a.sampling.block(a.photons, &a.sensor),
        window: a.window,
    };
    let (lib, out) = super::study::run(&g, &a.scene, &a.output, a.resume, |scene| {
        if perfect_mirrors(scene) {
            tell!(
                "note: the scene's mirrors have a perfect figure and no roughness: these are the ideal optic's PSFs, far sharper than a real module's (give the scene its figure error, e.g. -D figure_error=xmm_newton for XMM-Newton's fitted 15″ HPD)"
            );
        }
    })?;
    if !a.output.quiet.quiet {
        print_library(&g, &lib, &out);
    }
    Ok(())
}

/// Whether the scene has mirrors and every one reflects exactly specularly
/// (no figure error, no roughness).
fn perfect_mirrors(scene: &traxer::scene::Scene) -> bool {
    use traxer::material::Material;
    let mut mirrors = scene.objects.iter().filter_map(|o| match &o.material {
        Material::Mirror {
            figure_error,
            roughness,
            ..
        } => Some(figure_error.is_none_or(|f| f.is_perfect()) && roughness.is_none()),
        _ => None,
    });
    let first = mirrors.next();
    first.is_some_and(|p| p && mirrors.all(|p| p))
}

/// The library's summary on stdout: its points and the least share of the
/// flux a window holds.
fn print_library(g: &PsfGrid, lib: &traxer::studies::psf::PsfLibrary, out: &std::path::Path) {
    say!(
        "{} points ({} energies × {} angles × {} azimuths), {} photons each, in {:.2} s with {} threads",
        lib.images.len(),
        g.energies.len(),
        g.angles_arcmin.len(),
        g.azimuths_deg.len(),
        g.sampling.photons,
        lib.seconds,
        lib.threads
    );
    let least = lib
        .images
        .iter()
        .min_by(|x, y| x.enclosed().total_cmp(&y.enclosed()))
        .expect("a library has points");
    say!(
        "  windows of {w} × {w} pixels hold {:.2} % of the flux on the sensor or more (least at {} keV, {}′, {}°)",
        100.0 * least.enclosed(),
        least.energy_kev,
        least.angle_arcmin,
        least.azimuth_deg,
        w = lib.window
    );
    say!("wrote psf.fits, psf.npy, psf.json to {}", out.display());
}
