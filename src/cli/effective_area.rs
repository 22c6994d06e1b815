//! `traxer effective-area`: the telescope's effective area against energy and
//! off-axis angle, and its off-axis image quality
//! (`traxer::studies::effective_area`).

use super::args::{parse_values, OutputArgs, SamplingArgs, SceneArgs};
use traxer::output::{effective_area_files, sixte_vignetting_refused, SIXTE_VIGNETTING};
use traxer::studies::effective_area::{AreaResult, AreaSweep};

/// Effective area A_eff(E, θ) in cm² and off-axis image quality.
///
/// The scene's only source must be a parallel beam whose aperture covers the
/// telescope's entrance; it is tilted to each of --angles (arcminutes, in the
/// direction of its off_axis_azimuth). At each angle --photons photons are traced
/// once, and each photon's weight is evaluated at every energy of --energies from
/// the reflections and foils on its path (exact: the path does not depend on the
/// energy). The area counts the flux on --sensor, or within --radius mm of the
/// image's centroid (the area within the PSF), with its Monte Carlo error and split
/// by photon path class. Writes effective_area.csv, off_axis.csv,
/// effective_area.json and the plots effective_area.png, vignetting.png and
/// off_axis.png into --out. Example (the LLNL telescope, 1–10 keV, on and off axis):
///   traxer effective-area scenes/llnl_effective_area.toml --energies 1:10:0.1 --angles 0,2,4,6,8
#[derive(clap::Args)]
pub struct EffectiveAreaArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Energies (keV): a,b,c or start:stop:step.
    #[arg(value_name = "E", long, default_value = "1:10:0.1")]
    pub energies: String,
    /// Off-axis angles (arcmin): a,b,c or start:stop:step.
    #[arg(
        value_name = "ARCMIN",
        long,
        default_value = "0",
        allow_hyphen_values = true
    )]
    pub angles: String,
    /// Photons traced per angle.
    #[arg(short = 'n', long, value_name = "N", default_value = "200000", value_parser = super::args::parse_count)]
    pub photons: u64,
    /// Sensor to count on (default: the scene's only sensor).
    #[arg(value_name = "NAME", long)]
    pub sensor: Option<String>,
    /// Count only within this radius (mm) of the image centre.
    #[arg(value_name = "MM", long)]
    pub radius: Option<f64>,
    /// Continue the stopped sweep whose results folder is --out: run the same
    /// command with --resume; the angles it recorded
    /// (effective_area_checkpoint.jsonl) are not traced again.
    #[arg(long)]
    pub resume: bool,
    #[command(flatten)]
    pub sampling: SamplingArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

pub fn run(a: EffectiveAreaArgs) -> anyhow::Result<()> {
    let s = AreaSweep {
        energies: parse_values("energies", &a.energies)?,
        angles_arcmin: parse_values("angles", &a.angles)?,
        sampling: a.sampling.block(a.photons, &a.sensor),
        radius_mm: a.radius,
    };
    let (result, out) = super::study::run(&s, &a.scene, &a.output, a.resume, |_| {})?;
    if !a.output.quiet.quiet {
        print_sweep(&s, &result, &out);
    }
    Ok(())
}

/// The sweep's summary on stdout: per angle the area at the first, peak and last
/// energy, the geometric area and the HPD.
fn print_sweep(s: &AreaSweep, result: &AreaResult, out: &std::path::Path) {
    say!(
        "{} energies × {} angles, {} photons per angle, in {:.2} s with {} threads",
        s.energies.len(),
        s.angles_arcmin.len(),
        s.sampling.photons,
        result.seconds,
        result.threads
    );
    say!("  the area counts {}", result.counts);
    for ang in &result.angles {
        let (lo, hi) = (ang.points.first().unwrap(), ang.points.last().unwrap());
        let peak = ang
            .points
            .iter()
            .max_by(|x, y| x.area_cm2.total_cmp(&y.area_cm2))
            .unwrap();
        let hpd = ang
            .quality
            .as_ref()
            .map_or(String::new(), |q| match q.hpd_arcsec {
                Some(v) => format!(", HPD {v:.1}″"),
                None => format!(", HPD {:.4} mm", q.hpd_mm),
            });
        say!(
            "  {}′: {:.3} ± {:.3} cm² at {} keV, {:.3} at {} keV (peak), {:.3} at {} keV; geometric {:.3} cm²{hpd}",
            ang.off_axis_arcmin,
            lo.area_cm2, lo.error_cm2, lo.energy_kev,
            peak.area_cm2, peak.energy_kev,
            hi.area_cm2, hi.energy_kev,
            ang.geometric_area_cm2,
        );
    }
    let files = effective_area_files(&s.angles_arcmin, &s.energies);
    let arfs = files.iter().filter(|f| f.ends_with(".arf")).count();
    let sixte = files.iter().any(|f| f == SIXTE_VIGNETTING);
    let arf_note = match arfs {
        0 => " (no ARF: an ARF's energy bins need two energies or more)".to_string(),
        n => format!(", {n} of them OGIP ARFs (effective_area_<angle>arcmin.arf)"),
    };
    say!("wrote {} files to {}{arf_note}", files.len(), out.display());
    match sixte_vignetting_refused(&s.angles_arcmin) {
        Some(why) if arfs > 0 => say!("no {SIXTE_VIGNETTING} (SIXTE's vignetting): {why}"),
        _ if sixte => {
            say!("{SIXTE_VIGNETTING}: the vignetting as SIXTE reads it (THETA in degrees)")
        }
        _ => {}
    }
}
