//! The reach study: from finished magnet runs (one per buffer-gas setting,
//! each with its masses) to the expected limit on the coupling versus the
//! axion mass, in one signal region and energy window: measure each run's
//! signal (`analysis::signal`) and turn the counts in the window into limits
//! (`analysis::reach`).
//!
//! Data flow: `traxer reach` and Python's `traxer.reach` read the runs
//! (`output::run_read`) and call [`reach`]; `output::reach` writes what it
//! returns.

use crate::analysis::reach::{limit, Coupling, Exposure, Limit};
use crate::analysis::signal::{signal, Region, RunSignal, Signal};
use serde_json::{json, Value};
use std::path::Path;

/// One run's curve.
pub struct ReachCurve {
    /// "vacuum", or the buffer gas.
    pub label: String,
    pub run: String,
    pub limits: Vec<Limit>,
    /// The region the counts are in.
    pub region: Value,
    /// The run's hours of tracking.
    pub tracking_hours: f64,
}

/// Every run's curve, what they limit ("g_agamma" or "g_ae_g_agamma") and
/// the energy window (keV).
pub struct Reach {
    pub curves: Vec<ReachCurve>,
    pub coupling: &'static str,
    pub window: [f64; 2],
}

/// Why the reach cannot be computed.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct ReachError(pub String);

impl Exposure {
    /// The exposure, its numbers checked (named as the CLI's options).
    pub fn checked(
        tracking_hours: f64,
        bores: f64,
        efficiency: f64,
        background: f64,
    ) -> Result<Exposure, ReachError> {
        let positive = |v: f64, what: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(ReachError(format!("{what} {v}: expected a number > 0")))
            }
        };
        if !(background.is_finite() && background >= 0.0) {
            return Err(ReachError(format!(
                "background {background}: counts per keV per cm² per second, ≥ 0"
            )));
        }
        if !(efficiency > 0.0 && efficiency <= 1.0) {
            return Err(ReachError(format!("efficiency {efficiency}: in (0, 1]")));
        }
        Ok(Exposure {
            tracking_hours: positive(tracking_hours, "tracking hours")?,
            bores: positive(bores, "bores")?,
            efficiency,
            background,
        })
    }
}

/// The reach of the runs (each read from its folder, named by it), with one
/// exposure for all or one per run.
pub fn reach(
    runs: &[(&Path, RunSignal)],
    region: &Region,
    window: Option<[f64; 2]>,
    exposures: &[Exposure],
) -> Result<Reach, ReachError> {
    let dirs: Vec<&Path> = runs.iter().map(|r| r.0).collect();
    if exposures.len() != 1 && exposures.len() != dirs.len() {
        return Err(ReachError(format!(
            "{} tracking times for {} runs: give one for all, or one per run",
            exposures.len(),
            dirs.len()
        )));
    }
    let mut curves = Vec::new();
    let mut kind = None;
    let mut edges = [0.0; 2];
    for (k, (dir, run)) in runs.iter().enumerate() {
        let exposure = &exposures[k.min(exposures.len() - 1)];
        let s = signal(run, region).map_err(|e| ReachError(e.0))?;
        let coupling = coupling_of(run, dir)?;
        if kind.is_some_and(|k: &'static str| k != coupling.name()) {
            return Err(ReachError("the runs limit different couplings (Primakoff and ABC runs): give runs of one emission".into()));
        }
        kind = Some(coupling.name());
        let (b0, b1) = window_bands(&s, window)?;
        edges = [s.band_edges[b0], s.band_edges[b1]];
        let limits = s
            .masses
            .iter()
            .map(|m| {
                let rate: f64 = m.spectrum[b0..b1].iter().sum();
                let region = (s.area_cm2, edges[1] - edges[0]);
                limit(m.mass_ev, rate, coupling, region, exposure)
            })
            .collect();
        curves.push(ReachCurve {
            label: run.gas.as_ref().map_or("vacuum".into(), |g| format!("He {g}")),
            run: dir.display().to_string(),
            limits,
            region: json!({"center_mm": s.centre_mm, "radius_mm": s.radius_mm, "area_cm2": s.area_cm2, "fraction": s.fraction}),
            tracking_hours: exposure.tracking_hours,
        });
    }
    Ok(Reach {
        curves,
        coupling: kind.unwrap_or("g_agamma"),
        window: edges,
    })
}

/// The bands of `s` inside `window` (their edges), or why not.
fn window_bands(s: &Signal, window: Option<[f64; 2]>) -> Result<(usize, usize), ReachError> {
    let e = &s.band_edges;
    let Some([lo, hi]) = window else {
        return Ok((0, e.len() - 1));
    };
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return Err(ReachError(format!(
            "window {lo},{hi}: two energies (keV), LO < HI"
        )));
    }
    let at = |v: f64| {
        e.iter()
            .position(|x| (x - v).abs() <= 1e-9 * x.abs().max(1.0))
    };
    match (at(lo), at(hi)) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => Err(ReachError(format!(
            "window {lo},{hi}: the window's edges must be edges of the run's energy bands ({} keV); trace with -D energy_bins=[LO,HI,COUNT] for others",
            e.iter().map(|x| crate::text::number(*x)).collect::<Vec<_>>().join(", ")
        ))),
    }
}

/// What a run's signal limits.
fn coupling_of(run: &RunSignal, dir: &Path) -> Result<Coupling, ReachError> {
    match (run.emission.as_str(), run.g_ae) {
        ("primakoff", _) => Ok(Coupling::GAgamma(run.g_agamma)),
        ("abc", Some(g_ae)) => Ok(Coupling::GAeGAgamma(g_ae * run.g_agamma)),
        (e, _) => Err(ReachError(format!(
            "{}: the run's emission is {e}: its signal does not scale as one coupling; trace -D emission=primakoff for the reach in g_aγ, or -D emission=abc for g_ae·g_aγ",
            dir.display()
        ))),
    }
}
