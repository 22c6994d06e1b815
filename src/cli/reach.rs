//! `traxer reach`: the median expected upper limit on the coupling versus the
//! axion mass from finished magnet runs.

use super::signal::RegionArgs;
use super::InputError;
use std::path::PathBuf;
use traxer::analysis::reach::Exposure;
use traxer::output::campaign_read::is_campaign_run;
use traxer::output::run_read::{read_run_signal, RunReadError};
use traxer::output::{write_reach, Provenance, REACH_FILES};
use traxer::studies::reach::{reach, Reach, ReachError};

/// The expected sensitivity: limit on g_aγ (or g_ae·g_aγ) versus m_a.
///
/// For each run (a finished `traxer trace` of a Sun scene with its magnet on,
/// e.g. one per buffer-gas setting, each with a --masses scan) takes the
/// signal in a signal region (as `traxer signal`) and an energy window, and
/// gives the median expected 95 % CL upper limit under the background-only
/// hypothesis: CLs, exact Poisson, one bin; with no background 3.0 counts
/// (above 10⁶ background counts the normal limit, which meets it to 2e-4).
/// The signal scales as g_aγ⁴ for a Primakoff run and as (g_ae·g_aγ)² for an
/// ABC run, so the limit on the counts gives the coupling's. Writes reach.csv,
/// reach.png (log m_a against log coupling, a curve per run, the vacuum
/// plateau dashed) and reach.json into --out (default FIRST_RUN/reach).
///
/// A campaign run (traced with [magnet.campaign], e.g. BabyIAXO's -D
/// campaign=true) gives one curve: at each mass every setting that recorded
/// it combined (CLs of the likelihood ratio of all their channels, exact by
/// Fourier transform; one channel is the one-bin limit), each setting's hours
/// from the run; its region is the campaign's rings out to --radius-mm (a
/// ring edge) or --fraction, and it also writes reach_settings.csv (every
/// setting's part at every mass).
#[derive(clap::Args)]
pub struct ReachArgs {
    /// The results folders of the traces (one curve each).
    #[arg(required = true)]
    pub runs: Vec<PathBuf>,
    #[command(flatten)]
    pub region: RegionArgs,
    /// The energy window (keV, LO,HI): edges of the sensor's energy bands
    /// (default: all of them).
    #[arg(value_name = "LO,HI", long, value_delimiter = ',')]
    pub window: Vec<f64>,
    /// Background in the window: counts per keV per cm² per second.
    #[arg(value_name = "B", long)]
    pub background: f64,
    /// Hours of tracking the Sun: one value for every run, or one per run
    /// (H1,H2,...: a gas setting's share of the gas phase); for a campaign,
    /// one per setting (default: the campaign's own).
    #[arg(value_name = "H", long, value_delimiter = ',')]
    pub tracking_hours: Vec<f64>,
    /// A campaign's channels: each setting's energy bins × rings inside the
    /// region (default: one channel per setting).
    #[arg(long)]
    pub binned: bool,
    /// A published curve to draw beside a campaign's combined curve in
    /// reach.png, as often as there are curves: two numbers per line, m_a
    /// (eV) and the limit (GeV⁻¹) (data/reference_curves/: REST's BabyIAXO
    /// curves, the official IAXO projection).
    #[arg(value_name = "FILE", long)]
    pub reference: Vec<PathBuf>,
    /// Identical bores, each with its optic and detector (signal and
    /// background both scale with it).
    #[arg(value_name = "N", long, default_value_t = 1.0)]
    pub bores: f64,
    /// Efficiency beyond the run's: the run's detector gas is in its counts
    /// already, so this is software cuts, dead time and the like.
    #[arg(value_name = "E", long, default_value_t = 1.0)]
    pub efficiency: f64,
    #[command(flatten)]
    pub output: super::args::OutputArgs,
}

pub fn run(a: ReachArgs) -> anyhow::Result<()> {
    let fail = |e: ReachError| InputError(e.0);
    if a.runs.iter().any(|d| is_campaign_run(d)) {
        return super::campaign_reach::run(super::campaign_reach::CampaignReachArgs {
            runs: &a.runs,
            region: &a.region,
            window: &a.window,
            background: a.background,
            tracking_hours: &a.tracking_hours,
            bores: a.bores,
            efficiency: a.efficiency,
            binned: a.binned,
            reference: &a.reference,
            output: &a.output,
        });
    }
    if a.tracking_hours.is_empty() {
        return Err(InputError("--tracking-hours H: the hours of tracking the Sun (one for every run, or one per run); only a campaign run carries its own".into()).into());
    }
    if !a.reference.is_empty() {
        return Err(InputError("--reference: a published curve drawn beside a campaign's combined curve; these runs are not a campaign".into()).into());
    }
    if a.binned {
        return Err(InputError("--binned: the channels of a campaign run's tallies; these runs are not campaigns (their limit is one bin: the region and window)".into()).into());
    }
    let exposures = a
        .tracking_hours
        .iter()
        .map(|&h| Exposure::checked(h, a.bores, a.efficiency, a.background))
        .collect::<Result<Vec<_>, _>>()
        .map_err(fail)?;
    let window = match a.window.as_slice() {
        [] => None,
        [lo, hi] => Some([*lo, *hi]),
        _ => return Err(InputError("--window LO,HI: two energies (keV)".into()).into()),
    };
    let runs = a
        .runs
        .iter()
        .map(|d| Ok((d.as_path(), read_run_signal(d, a.region.sensor.as_deref())?)))
        .collect::<Result<Vec<_>, RunReadError>>()
        .map_err(|e| InputError(e.0))?;
    let region = a.region.region()?;
    let Reach {
        curves,
        coupling: kind,
        window,
        warnings,
    } = reach(&runs, &region, window, &exposures).map_err(fail)?;
    for w in &warnings {
        tell!("warning: {w}");
    }
    let out = a
        .output
        .out
        .clone()
        .unwrap_or_else(|| a.runs[0].join("reach"));
    let read: Vec<&std::path::Path> = a.runs.iter().map(|r| r.as_path()).collect();
    let folder = traxer::run::results_folder_reading(&out, &REACH_FILES, &read)?;
    let provenance = Provenance::of_table(&super::invocation());
    traxer::run::write_results_folder(folder, |dir| {
        write_reach(dir, &curves, kind, (&exposures[0], window), &provenance)
    })?;
    print_limits(&curves, kind, window, a.output.quiet.quiet);
    if !a.output.quiet.quiet {
        tell!("wrote {} to {}", REACH_FILES.join(", "), out.display());
    }
    Ok(())
}

/// The limits as a table on stdout, the window and region as a note.
fn print_limits(
    curves: &[traxer::studies::reach::ReachCurve],
    kind: &str,
    window: [f64; 2],
    quiet: bool,
) {
    if !quiet {
        tell!(
            "energy window {}–{} keV; counts for the whole exposure; signal regions:",
            traxer::text::number(window[0]),
            traxer::text::number(window[1]),
        );
        for curve in curves {
            let c = &curve.region;
            let centre = c["center_mm"].as_array().map_or(vec![], |v| {
                v.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect()
            });
            tell!(
                "  {}: a circle of {} mm about ({:.4}, {:.4}) mm, {} cm² ({:.1} % of its flux at m_a = {} eV) [{}]",
                curve.label,
                traxer::text::four_decimals(c["radius_mm"].as_f64().unwrap_or(f64::NAN)),
                centre.first().copied().unwrap_or(f64::NAN),
                centre.get(1).copied().unwrap_or(f64::NAN),
                traxer::text::four_decimals(c["area_cm2"].as_f64().unwrap_or(f64::NAN)),
                100.0 * c["fraction"].as_f64().unwrap_or(f64::NAN),
                traxer::text::number(c["placed_on_mass_ev"].as_f64().unwrap_or(f64::NAN)),
                curve.run
            );
        }
    }
    say!(
        "{:<28} {:>10} {:>12} {:>12} {:>10} {:>12}",
        "setting",
        "m_a (eV)",
        "signal",
        "background",
        "limit",
        kind
    );
    for c in curves {
        for l in &c.limits {
            say!(
                "{:<28} {:>10} {:>12.4e} {:>12.4e} {:>10.4} {:>12}",
                c.label,
                traxer::text::number(l.mass_ev),
                l.signal,
                l.background,
                l.counts_limit,
                l.coupling_limit
                    .map_or("none".into(), |g| format!("{g:.4e}"))
            );
        }
    }
}
