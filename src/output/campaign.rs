//! A campaign's files ([`crate::magnet::campaign`]): per sensor
//! `NAME_campaign.npy`, the X-rays per second converting over each
//! (setting, mass) pair's energy bins and rings ([pair][energy][ring]), and
//! `campaign.json`: the settings (gas, pressure, photon mass, tracking hours),
//! the mass nodes, the pairs, the bins and what a unit is.
//!
//! Data flow: `output::run_files::write_run` calls [`write_campaign`] with the
//! run's tallies (`trace::RunResult::campaign`); `reach` reads the files.

use crate::magnet::campaign::Campaign;
use crate::scene::Scene;
use crate::sensor::campaign::CampaignTally;
use crate::trace::RunResult;
use serde_json::json;
use std::path::{Path, PathBuf};

/// The campaign's description file.
pub const CAMPAIGN_FILE: &str = "campaign.json";

/// A sensor's tallies file.
pub fn tally_file_name(sensor: &str) -> String {
    format!("{sensor}_campaign.npy")
}

/// The scene's campaign, if its magnet has one.
pub fn campaign_of(scene: &Scene) -> Option<&Campaign> {
    scene.magnet.as_deref().and_then(|m| m.campaign.as_deref())
}

/// The files a campaign writes (none without one).
pub fn campaign_file_names(scene: &Scene) -> Vec<String> {
    match campaign_of(scene) {
        None => Vec::new(),
        Some(_) => std::iter::once(CAMPAIGN_FILE.to_string())
            .chain(scene.sensors.iter().map(|s| tally_file_name(&s.name)))
            .collect(),
    }
}

/// A campaign's results in X-rays per second: each sensor's tallies
/// ([pair][energy][ring], `shape`) and campaign.json's document.
pub struct CampaignTables {
    pub shape: [usize; 3],
    pub sensors: Vec<(String, Vec<f64>)>,
    pub doc: serde_json::Value,
}

/// Writes the campaign's files into `dir`; `rate` turns a unit of summed
/// weight into X-rays per second. Returns the paths.
pub fn write_campaign(
    dir: &Path,
    scene: &Scene,
    result: &RunResult,
    rate: f64,
) -> std::io::Result<Vec<PathBuf>> {
    let Some(t) = campaign_tables(scene, &result.campaign, rate) else {
        return Ok(Vec::new());
    };
    let mut written = Vec::new();
    for (name, values) in &t.sensors {
        let p = dir.join(tally_file_name(name));
        super::write_npy_f64(&p, &t.shape.map(|n| n as u64), values)?;
        written.push(p);
    }
    let p = dir.join(CAMPAIGN_FILE);
    let mut text = serde_json::to_string_pretty(&t.doc).expect("JSON of plain values");
    text.push('\n');
    crate::files::atomic_write(&p, text.as_bytes())?;
    written.push(p);
    Ok(written)
}

/// The campaign's results (None without one) from the run's `tallies`,
/// `rate` X-rays per second per unit of summed weight: what its files hold
/// and Python's `TraceResult.campaign` gives.
pub fn campaign_tables(
    scene: &Scene,
    tallies: &[CampaignTally],
    rate: f64,
) -> Option<CampaignTables> {
    let c = campaign_of(scene)?;
    let (ne, nr) = (c.energy_edges.len() - 1, c.ring_edges.len() - 1);
    let sensors: Vec<(String, Vec<f64>)> = scene
        .sensors
        .iter()
        .zip(tallies)
        .map(|(spec, tally)| {
            let values = tally.values().iter().map(|v| v * rate).collect();
            (spec.name.clone(), values)
        })
        .collect();
    // Each setting's rate at its own photon mass (the mass node nearest it),
    // on the first sensor: what the KSVZ allocation spends time against.
    let first = sensors.first().map_or(&[][..], |s| &s.1[..]);
    let signal: Vec<f64> = (0..c.settings.len())
        .map(|s| own_mass_rate(c, s, first))
        .collect();
    let hours = c.hours(&signal);
    let settings: Vec<_> = c
        .settings
        .iter()
        .enumerate()
        .map(|(s, set)| {
            json!({
                "label": set.label(),
                "gas": set.gas.as_ref().map(|g| g.desc.mixture.keys().next().cloned()),
                "pressure_mbar": set.pressure_mbar(),
                "temperature_k": set.gas.as_ref().map(|g| g.desc.temperature_k),
                "number_density_m3": set.gas.as_ref().map(|g| g.number_density_m3),
                "photon_mass_ev": set.photon_mass_ev,
                "tracking_hours": hours[s],
                "rate_at_own_mass_per_s": signal[s],
            })
        })
        .collect();
    let d = &c.desc;
    let doc = json!({
        "what": "per (setting, mass) pair: X-rays per second converting in each sensor's energy bins and rings about centre_mm, at the run's g_agamma (signal ∝ g⁴ for Primakoff): NAME_campaign.npy [pair][energy][ring]",
        "planner": match &d.plan {
            Some(p) => json!({
                "rule": "REST-for-Physics TRestAxionField::GetMassDensityScanning (axionlib PR #78): the first photon mass where the vacuum P falls to half; then m += FWHM(m) / (exp(-m ramp_down) + 1); P on the bore's axis through the scene's field, or through a uniform field_t over the bore's length",
                "up_to_ev": p.up_to_ev, "ramp_down": p.ramp_down, "energy_kev": p.energy_kev,
                "planned_on": if p.field_t > 0.0 { format!("a uniform {} T over the bore's length", p.field_t) } else { "the scene's field on the bore's axis".to_string() },
            }),
            None => json!({"rule": "pressures_mbar given"}),
        },
        "sees": d.sees,
        "sees_is": "a setting records a mass where its P on the bore's axis is at least this fraction of the best setting's there, at the lowest, planning or highest tallied energy",
        "allocation": if d.fractions.is_empty() { json!(d.allocation) } else { json!({"fractions": d.fractions}) },
        "allocation_rule": "ksvz (REST-for-Physics axionlib examples/03.IAXO/GenerateSignalComponents.C): the first ksvz_first_settings gas settings share ksvz_first_share of gas_hours equally, each later one a share of the rest ∝ 1 / (m_γ⁴ × its rate at its own mass), the time for equal KSVZ counts; equal: gas_hours / settings",
        "ksvz_first_settings": d.ksvz_first_settings,
        "ksvz_first_share": d.ksvz_first_share,
        "vacuum_hours": d.vacuum_hours,
        "gas_hours": d.gas_hours,
        "settings": settings,
        "masses_ev": c.masses,
        "pairs": c.pairs.iter().map(|&(s, m)| [s, m]).collect::<Vec<_>>(),
        "energy_edges_kev": c.energy_edges,
        "ring_edges_mm": c.ring_edges,
        "centre_mm": d.centre_mm,
        "sensors": scene.sensors.iter().map(|s| tally_file_name(&s.name)).collect::<Vec<_>>(),
    });
    Some(CampaignTables {
        shape: [c.pairs.len(), ne, nr],
        sensors,
        doc,
    })
}

/// Setting `s`'s total rate at the mass node nearest its photon mass.
fn own_mass_rate(c: &Campaign, s: usize, values: &[f64]) -> f64 {
    let bins = c.bins();
    c.pairs
        .iter()
        .enumerate()
        .filter(|(_, &(ps, _))| ps as usize == s)
        .min_by(|(_, a), (_, b)| {
            let d = |m: u32| (c.masses[m as usize] - c.settings[s].photon_mass_ev).abs();
            d(a.1).total_cmp(&d(b.1))
        })
        .map_or(0.0, |(k, _)| {
            values
                .get(k * bins..(k + 1) * bins)
                .map_or(0.0, |v| v.iter().sum())
        })
}
