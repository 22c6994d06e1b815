//! Reads a finished campaign run back from its results folder for `traxer
//! reach`: `campaign.json` (settings, masses, pairs, bins), one sensor's
//! `NAME_campaign.npy` tallies and the run's couplings from `summary.json`,
//! each checked against the others before use.
//!
//! Data flow: `cli::reach` calls [`read_campaign_run`] on a folder holding
//! [`super::campaign::CAMPAIGN_FILE`]; `studies::campaign_reach` uses it.

use super::campaign::{tally_file_name, CAMPAIGN_FILE};
use super::run_read::{emission_of, read_json, sensor_name, RunReadError};
use crate::sensor::SUMMARY_FILE;
use crate::studies::campaign_reach::{CampaignRun, CampaignSetting};
use serde_json::Value;
use std::path::Path;

/// Whether the results folder `dir` holds a campaign.
pub fn is_campaign_run(dir: &Path) -> bool {
    dir.join(CAMPAIGN_FILE).is_file()
}

/// The campaign run in `dir`, the tallies of `sensor` (or its only one).
pub fn read_campaign_run(dir: &Path, sensor: Option<&str>) -> Result<CampaignRun, RunReadError> {
    let summary = read_json(&dir.join(SUMMARY_FILE))?;
    let path = dir.join(CAMPAIGN_FILE);
    let doc = read_json(&path)?;
    let bad = |what: String| RunReadError(format!("{}: {what}", path.display()));
    let name = sensor_name(&summary, sensor)
        .map_err(|m| RunReadError(format!("{}: {m}", dir.join(SUMMARY_FILE).display())))?;
    let numbers = |key: &str| -> Result<Vec<f64>, RunReadError> {
        doc[key]
            .as_array()
            .and_then(|a| a.iter().map(Value::as_f64).collect::<Option<Vec<_>>>())
            .filter(|v| v.iter().all(|x| x.is_finite()))
            .ok_or_else(|| bad(format!("{key}: a list of finite numbers expected")))
    };
    let masses = numbers("masses_ev")?;
    let energy_edges = numbers("energy_edges_kev")?;
    let ring_edges = numbers("ring_edges_mm")?;
    let centre = numbers("centre_mm")?;
    let [cx, cy] = centre[..] else {
        return Err(bad("centre_mm: [x, y] expected".into()));
    };
    let ascending = |v: &[f64]| v.len() >= 2 && v.windows(2).all(|w| w[1] > w[0]);
    if !ascending(&energy_edges) || !ascending(&ring_edges) || ring_edges[0] != 0.0 {
        return Err(bad(
            "energy_edges_kev and ring_edges_mm: ascending edges, the rings from 0".into(),
        ));
    }
    let settings = settings_of(&doc, &bad)?;
    let pairs = doc["pairs"]
        .as_array()
        .ok_or_else(|| bad("no pairs".into()))?
        .iter()
        .map(|p| {
            let i = |k: usize| p[k].as_u64().map(|v| v as usize);
            match (i(0), i(1)) {
                (Some(s), Some(m)) if s < settings.len() && m < masses.len() => Ok((s, m)),
                _ => Err(bad(format!(
                    "pairs: {p} is not [setting, mass] of the {} settings and {} masses",
                    settings.len(),
                    masses.len()
                ))),
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let file = tally_file_name(&name);
    let (shape, tallies) =
        super::read_npy(&dir.join(&file)).map_err(|e| RunReadError(e.to_string()))?;
    let want = [pairs.len(), energy_edges.len() - 1, ring_edges.len() - 1];
    if shape.iter().map(|&v| v as usize).collect::<Vec<_>>() != want {
        return Err(RunReadError(format!(
            "{}: shape {shape:?} where {CAMPAIGN_FILE} promises {want:?} (pairs, energy bins, rings)",
            dir.join(&file).display()
        )));
    }
    if tallies.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(RunReadError(format!(
            "{}: a tally that is not a finite rate ≥ 0",
            dir.join(&file).display()
        )));
    }
    let source = &summary["sources"][0];
    let g_agamma = source["magnet"]["g_agamma_per_gev"]
        .as_f64()
        .ok_or_else(|| {
            RunReadError(format!(
                "{}: no magnet's g_agamma_per_gev",
                dir.join(SUMMARY_FILE).display()
            ))
        })?;
    let (emission, g_ae) = emission_of(source);
    let coupling = crate::studies::reach::coupling_of((emission, g_agamma, g_ae), dir)
        .map_err(|e| RunReadError(e.0))?;
    Ok(CampaignRun {
        dir: dir.display().to_string(),
        sensor: name,
        settings,
        masses,
        pairs,
        energy_edges,
        ring_edges,
        centre_mm: [cx, cy],
        tallies,
        coupling,
    })
}

/// campaign.json's settings.
fn settings_of(
    doc: &Value,
    bad: &dyn Fn(String) -> RunReadError,
) -> Result<Vec<CampaignSetting>, RunReadError> {
    doc["settings"]
        .as_array()
        .ok_or_else(|| bad("no settings".into()))?
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let n = |k: &str| {
                s[k].as_f64()
                    .filter(|v| v.is_finite() && *v >= 0.0)
                    .ok_or_else(|| bad(format!("settings[{i}].{k}: a number ≥ 0 expected")))
            };
            Ok(CampaignSetting {
                label: s["label"].as_str().unwrap_or("?").to_string(),
                pressure_mbar: n("pressure_mbar")?,
                photon_mass_ev: n("photon_mass_ev")?,
                tracking_hours: n("tracking_hours")?,
            })
        })
        .collect()
}
