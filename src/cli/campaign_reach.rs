//! `traxer reach` on a campaign run: one combined curve from the campaign's
//! tallies (`studies::campaign_reach`), written and printed.

use super::args::OutputArgs;
use super::signal::RegionArgs;
use super::InputError;
use std::path::PathBuf;
use traxer::analysis::signal::{Centre, Size};
use traxer::output::campaign_read::read_campaign_run;
use traxer::output::{write_campaign_reach, Provenance, CAMPAIGN_REACH_FILES};
use traxer::studies::campaign_reach::{reach, CampaignReach, CampaignReachRequest};

/// What `traxer reach` was given, for a campaign run.
pub struct CampaignReachArgs<'a> {
    pub runs: &'a [PathBuf],
    pub region: &'a RegionArgs,
    pub window: &'a [f64],
    pub background: f64,
    pub tracking_hours: &'a [f64],
    pub bores: f64,
    pub efficiency: f64,
    pub binned: bool,
    pub reference: &'a [PathBuf],
    pub output: &'a OutputArgs,
}

pub fn run(a: CampaignReachArgs) -> anyhow::Result<()> {
    let [dir] = a.runs else {
        return Err(InputError(format!(
            "{} runs with a campaign among them: a campaign run holds every setting; give it alone",
            a.runs.len()
        ))
        .into());
    };
    let region = a.region.region()?;
    if let Centre::At(_) = region.centre {
        return Err(InputError("--center: a campaign's rings lie about the centre_mm it was traced with (campaign.json); trace with [magnet.campaign] centre_mm = [X, Y] to move them".into()).into());
    }
    let window = match a.window {
        [] => None,
        [lo, hi] => Some([*lo, *hi]),
        _ => return Err(InputError("--window LO,HI: two energies (keV)".into()).into()),
    };
    let reference = a
        .reference
        .iter()
        .map(|p| traxer::output::reference_curve::read_reference_curve(p))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| InputError(e.0))?;
    let run = read_campaign_run(dir, a.region.sensor.as_deref()).map_err(|e| InputError(e.0))?;
    let request = CampaignReachRequest {
        size: region.size,
        on_mass: region.on_mass,
        window,
        hours: (!a.tracking_hours.is_empty()).then(|| a.tracking_hours.to_vec()),
        bores: a.bores,
        efficiency: a.efficiency,
        background: a.background,
        binned: a.binned,
    };
    let r = reach(&run, &request).map_err(|e| InputError(e.0))?;
    for w in &r.warnings {
        tell!("warning: {w}");
    }
    let out = a.output.out.clone().unwrap_or_else(|| dir.join("reach"));
    let folder =
        traxer::run::results_folder_reading(&out, &CAMPAIGN_REACH_FILES, &[dir.as_path()])?;
    let provenance = Provenance::of_table(&super::invocation());
    traxer::run::write_results_folder(folder, |d| {
        write_campaign_reach(d, &r, &provenance, &reference)
    })?;
    print_curve(
        &r,
        a.output.quiet.quiet,
        matches!(region.size, Size::Fraction(_)),
    );
    if !a.output.quiet.quiet {
        tell!(
            "wrote {} to {}",
            CAMPAIGN_REACH_FILES.join(", "),
            out.display()
        );
    }
    Ok(())
}

/// The region as a note, the curve as a table on stdout.
fn print_curve(r: &CampaignReach, quiet: bool, by_fraction: bool) {
    if !quiet {
        let gas = r.settings.iter().filter(|s| s.pressure_mbar > 0.0).count();
        tell!(
            "a campaign of {} settings ({} of gas), {} h of tracking; energy window {}–{} keV; the rings about ({:.4}, {:.4}) mm out to {} mm{}, {} cm²; {}",
            r.settings.len(),
            gas,
            // The settings' shares add up to the total only to rounding: shown
            // to 0.1 h, not as 13149.000000000015.
            format!("{:.1}", r.settings.iter().map(|s| s.tracking_hours).sum::<f64>()),
            traxer::text::number(r.window[0]),
            traxer::text::number(r.window[1]),
            r.centre_mm[0],
            r.centre_mm[1],
            traxer::text::four_decimals(r.radius_mm),
            if by_fraction { " (the fraction asked, at a ring edge)" } else { "" },
            traxer::text::four_decimals(r.area_cm2),
            if r.binned { "channels: energy bins × rings" } else { "one channel per setting" },
        );
    }
    say!(
        "{:>12} {:>9} {:>12} {:>12} {:>12} {:>12}",
        "m_a (eV)",
        "settings",
        "signal",
        "background",
        r.coupling,
        "best alone"
    );
    let g = |v: Option<f64>| v.map_or("none".into(), |g| format!("{g:.4e}"));
    for l in &r.limits {
        say!(
            "{:>12.5e} {:>9} {:>12.4e} {:>12.4e} {:>12} {:>12}",
            l.mass_ev,
            l.parts.len(),
            l.parts.iter().map(|p| p.signal).sum::<f64>(),
            l.parts.iter().map(|p| p.background).sum::<f64>(),
            g(l.coupling_limit),
            g(l.best_alone().map(|b| b.1))
        );
    }
}
