//! The reach of a campaign run: from a campaign's tallies (every setting's
//! X-rays per second per mass, energy bin and ring: `magnet::campaign`) to
//! one curve of the median expected limit on the coupling versus the axion
//! mass, each mass limited by every setting that recorded it together
//! (`analysis::combined`): the vacuum plateau and the gas phase as one
//! curve, not an envelope of single settings.
//!
//! The signal region is the campaign's rings about its centre out to a
//! radius (a ring edge), the window a run of its energy bins; each setting's
//! exposure is its tracking hours (the run's `campaign.json`, or a list
//! given). By default each setting counts its region and window as one
//! channel; `binned` splits it into the energy bins × rings inside.
//!
//! Data flow: `traxer reach` reads a campaign folder
//! (`output::campaign_read`) into a [`CampaignRun`] and calls [`reach`];
//! `output::campaign_reach` writes what it returns.

use super::reach::{ReachError, FEW_TRACKING_HOURS};
use crate::analysis::combined::{median_expected_scale, Channel, Method};
use crate::analysis::reach::{median_expected_limit, Coupling, Exposure, MAX_BACKGROUND_COUNTS};
use crate::analysis::signal::Size;
use rayon::prelude::*;

/// One setting of a campaign run as its files describe it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CampaignSetting {
    pub label: String,
    pub pressure_mbar: f64,
    pub photon_mass_ev: f64,
    pub tracking_hours: f64,
}

/// A finished campaign run, one sensor's tallies.
#[derive(Clone, Debug)]
pub struct CampaignRun {
    pub dir: String,
    pub sensor: String,
    pub settings: Vec<CampaignSetting>,
    pub masses: Vec<f64>,
    /// (setting, mass) indices, the tallies' first axis.
    pub pairs: Vec<(usize, usize)>,
    pub energy_edges: Vec<f64>,
    pub ring_edges: Vec<f64>,
    pub centre_mm: [f64; 2],
    /// X-rays per second [pair][energy][ring] at the run's couplings.
    pub tallies: Vec<f64>,
    pub coupling: Coupling,
}

/// What the reach of a campaign is asked for.
#[derive(Clone, Debug)]
pub struct CampaignReachRequest {
    /// The region's outer radius (a ring edge), or the fraction of the
    /// placing mass's tallied flux it holds.
    pub size: Size,
    /// The mass whose flux a fraction is of (default: the brightest).
    pub on_mass: Option<f64>,
    pub window: Option<[f64; 2]>,
    /// Hours per setting in the campaign's order (default: the run's).
    pub hours: Option<Vec<f64>>,
    pub bores: f64,
    pub efficiency: f64,
    /// Counts per keV per cm² per second.
    pub background: f64,
    /// Energy bins × rings as channels (else one per setting).
    pub binned: bool,
}

/// One setting's part at one mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contribution {
    pub setting: usize,
    /// Signal counts (at the run's couplings, × efficiency) and background
    /// counts in the region and window, over the setting's exposure.
    pub signal: f64,
    pub background: f64,
    /// The setting's limit on the coupling alone (one bin).
    pub alone: Option<f64>,
}

/// The combined limit at one mass.
#[derive(Clone, Debug, PartialEq)]
pub struct MassLimit {
    pub mass_ev: f64,
    pub coupling_limit: Option<f64>,
    pub method: Option<Method>,
    pub parts: Vec<Contribution>,
}

impl MassLimit {
    /// The best single setting's limit and which.
    pub fn best_alone(&self) -> Option<(usize, f64)> {
        self.parts
            .iter()
            .filter_map(|p| Some((p.setting, p.alone?)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// The campaign's curve and what it was computed over.
pub struct CampaignReach {
    pub coupling: &'static str,
    pub window: [f64; 2],
    pub centre_mm: [f64; 2],
    pub radius_mm: f64,
    pub area_cm2: f64,
    /// The settings with the hours used.
    pub settings: Vec<CampaignSetting>,
    pub limits: Vec<MassLimit>,
    pub exposure: Exposure,
    pub binned: bool,
    pub warnings: Vec<String>,
}

/// The combined reach of `run`.
pub fn reach(run: &CampaignRun, q: &CampaignReachRequest) -> Result<CampaignReach, ReachError> {
    let fail = |m: String| ReachError(format!("{}: {m}", run.dir));
    let (e0, e1) = super::reach::band_range(&run.energy_edges, q.window).map_err(|e| fail(e.0))?;
    let rings = region_rings(run, q).map_err(fail)?;
    let mut settings = run.settings.clone();
    if let Some(h) = &q.hours {
        if h.len() != settings.len() {
            return Err(ReachError(format!(
                "--tracking-hours: {} values for the campaign's {} settings (give one per setting in campaign.json's order, or none to take the run's)",
                h.len(),
                settings.len()
            )));
        }
        for (s, &h) in settings.iter_mut().zip(h) {
            s.tracking_hours = h;
        }
    }
    // Each setting's exposure (none for a setting without hours: it adds
    // nothing) and the background of its region and window.
    let exposures = settings
        .iter()
        .map(|s| match s.tracking_hours == 0.0 {
            true => Ok(None),
            false => {
                Exposure::checked(s.tracking_hours, q.bores, q.efficiency, q.background).map(Some)
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let Some(exposure) = exposures.iter().flatten().next().copied() else {
        return Err(fail("no setting has tracking hours".into()));
    };
    let radius_mm = run.ring_edges[rings];
    let area_cm2 = std::f64::consts::PI * radius_mm * radius_mm / 100.0;
    let window = [run.energy_edges[e0], run.energy_edges[e1]];
    for (s, e) in settings.iter().zip(&exposures) {
        let b = e.map_or(0.0, |e| {
            e.background_counts((area_cm2, window[1] - window[0]))
        });
        if b > MAX_BACKGROUND_COUNTS {
            return Err(ReachError(format!(
                "{}: the background is {b:.3e} counts in the region and window, more than {MAX_BACKGROUND_COUNTS:e}: is --background in counts per keV per cm² per second?",
                s.label
            )));
        }
    }
    let total_hours: f64 = settings.iter().map(|s| s.tracking_hours).sum();
    let mut warnings = Vec::new();
    if total_hours < FEW_TRACKING_HOURS {
        warnings.push(format!(
            "the campaign's exposure is {} h of tracking in all, where a helioscope's campaign is thousands (tracking hours are hours)",
            crate::text::number(total_hours)
        ));
    }
    // One-bin limits per setting: the background is one per setting.
    let alone_counts: Vec<f64> = exposures
        .iter()
        .map(|e| {
            e.map_or(f64::INFINITY, |e| {
                median_expected_limit(e.background_counts((area_cm2, window[1] - window[0])))
            })
        })
        .collect();
    let by_mass: Vec<Vec<usize>> = (0..run.masses.len())
        .map(|m| {
            (0..run.pairs.len())
                .filter(|&k| run.pairs[k].1 == m)
                .collect()
        })
        .collect();
    let bins = Bins {
        energies: (e0, e1),
        rings,
        binned: q.binned,
    };
    let limits = (0..run.masses.len())
        .into_par_iter()
        .map(|m| mass_limit(run, m, &by_mass[m], (&exposures, &alone_counts), &bins))
        .collect();
    Ok(CampaignReach {
        coupling: run.coupling.name(),
        window,
        centre_mm: run.centre_mm,
        radius_mm,
        area_cm2,
        settings,
        limits,
        exposure,
        binned: q.binned,
        warnings,
    })
}

/// The region's bins and how they make channels.
struct Bins {
    /// The window's first and past-the-last energy bins.
    energies: (usize, usize),
    /// The rings inside the region.
    rings: usize,
    /// Each bin a channel (else one per setting).
    binned: bool,
}

/// The combined limit at mass node `m` from the `pairs` that recorded it,
/// each setting's exposure and one-bin limit on the counts.
fn mass_limit(
    run: &CampaignRun,
    m: usize,
    pairs: &[usize],
    (exposures, alone_counts): (&[Option<Exposure>], &[f64]),
    bins: &Bins,
) -> MassLimit {
    let (ne, nr) = (run.energy_edges.len() - 1, run.ring_edges.len() - 1);
    let ring_area = |r: usize| {
        std::f64::consts::PI * (run.ring_edges[r + 1].powi(2) - run.ring_edges[r].powi(2)) / 100.0
    };
    let width = |e: usize| run.energy_edges[e + 1] - run.energy_edges[e];
    let mut channels = Vec::new();
    let mut parts = Vec::new();
    for &k in pairs {
        let s = run.pairs[k].0;
        let Some(e) = exposures[s] else { continue };
        let t = e.seconds() * e.efficiency;
        let tally = &run.tallies[k * ne * nr..(k + 1) * ne * nr];
        let mut part = Contribution {
            setting: s,
            signal: 0.0,
            background: 0.0,
            alone: None,
        };
        for eb in bins.energies.0..bins.energies.1 {
            for r in 0..bins.rings {
                let c = Channel {
                    signal: tally[eb * nr + r] * t,
                    background: e.background * ring_area(r) * width(eb) * e.seconds(),
                };
                part.signal += c.signal;
                part.background += c.background;
                if bins.binned {
                    channels.push(c);
                }
            }
        }
        if !bins.binned {
            channels.push(Channel {
                signal: part.signal,
                background: part.background,
            });
        }
        part.alone = run.coupling.at_counts(part.signal, alone_counts[s]);
        parts.push(part);
    }
    let total: f64 = channels.iter().map(|c| c.signal).sum();
    let combined = median_expected_scale(&channels);
    MassLimit {
        mass_ev: run.masses[m],
        coupling_limit: combined.and_then(|c| run.coupling.at_counts(total, c.scale * total)),
        method: combined.map(|c| c.method),
        parts,
    }
}

/// How many rings the region holds: out to the radius asked (a ring edge),
/// or to the first edge holding the fraction asked of the placing mass's
/// flux in the rings.
fn region_rings(run: &CampaignRun, q: &CampaignReachRequest) -> Result<usize, String> {
    let edges = &run.ring_edges;
    let outer = edges[edges.len() - 1];
    match q.size {
        Size::RadiusMm(r) => edges
            .iter()
            .position(|&e| e > 0.0 && (e - r).abs() <= 1e-9 * r.abs())
            .ok_or_else(|| {
                format!(
                    "--radius-mm {}: the campaign's rings end at {} … {} mm, every {} mm: give one of their edges (or trace with other rings_mm)",
                    crate::text::number(r),
                    crate::text::number(edges[1]),
                    crate::text::number(outer),
                    crate::text::number(edges[1] - edges[0])
                )
            }),
        Size::Fraction(f) => {
            if !(f > 0.0 && f <= 1.0) {
                return Err(format!("--fraction {f}: in (0, 1]"));
            }
            let flux = placing_flux(run, q.on_mass)?;
            let total: f64 = flux.iter().sum();
            let mut sum = 0.0;
            for (r, v) in flux.iter().enumerate() {
                sum += v;
                if sum >= f * total * (1.0 - 1e-12) {
                    return Ok(r + 1);
                }
            }
            Ok(flux.len())
        }
    }
}

/// The flux per ring (all energies) of the placing mass's brightest setting.
fn placing_flux(run: &CampaignRun, on_mass: Option<f64>) -> Result<Vec<f64>, String> {
    let nr = run.ring_edges.len() - 1;
    let bins = nr * (run.energy_edges.len() - 1);
    let pair_total = |k: usize| -> f64 { run.tallies[k * bins..(k + 1) * bins].iter().sum() };
    let candidates: Vec<usize> = match on_mass {
        None => (0..run.pairs.len()).collect(),
        Some(m) => {
            let node = run
                .masses
                .iter()
                .position(|&x| (x - m).abs() <= 1e-9 * x.abs().max(m.abs()))
                .ok_or_else(|| {
                    format!(
                        "--region-mass {}: not one of the campaign's {} mass nodes (campaign.json masses_ev)",
                        crate::text::number(m),
                        run.masses.len()
                    )
                })?;
            (0..run.pairs.len())
                .filter(|&k| run.pairs[k].1 == node)
                .collect()
        }
    };
    let best = candidates
        .into_iter()
        .max_by(|&a, &b| pair_total(a).total_cmp(&pair_total(b)))
        .ok_or("the campaign records no pair")?;
    let tally = &run.tallies[best * bins..(best + 1) * bins];
    Ok((0..nr)
        .map(|r| tally.iter().skip(r).step_by(nr).sum())
        .collect())
}
