//! The reach study: from finished magnet runs (one per buffer-gas setting,
//! each with its masses) to the expected limit on the coupling versus the
//! axion mass, in one signal region and energy window: measure each run's
//! signal (`analysis::signal`) and turn the counts in the window into limits
//! (`analysis::reach`).
//!
//! Data flow: `traxer reach` and Python's `traxer.reach` read the runs
//! (`output::run_read`) and call [`reach`]; `output::reach` writes what it
//! returns.

use crate::analysis::reach::{limit, Background, Coupling, Exposure, Limit, MAX_BACKGROUND_COUNTS};
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
    /// What the inputs make doubtful, for the front end to show.
    pub warnings: Vec<String>,
}

/// The most hours of tracking one exposure takes: 11 years of the Sun
/// around the clock (a helioscope tracks it some 12 h a day).
pub const MAX_TRACKING_HOURS: f64 = 1e5;

/// Below this many hours in all an exposure is warned about: a helioscope's
/// campaign is thousands of hours (BabyIAXO's plan: about 1.5 years of
/// tracking; CAST's vacuum phases, some 1 000 h each).
pub const FEW_TRACKING_HOURS: f64 = 100.0;

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
        if tracking_hours > MAX_TRACKING_HOURS {
            return Err(ReachError(format!(
                "tracking hours {}: more than {MAX_TRACKING_HOURS:e} h, 11 years of the Sun around the clock (the option takes hours)",
                crate::text::number(tracking_hours)
            )));
        }
        if bores > 100.0 {
            return Err(ReachError(format!(
                "bores {}: more than 100 identical bores (IAXO has 8)",
                crate::text::number(bores)
            )));
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
    let mut edges: Option<[f64; 2]> = None;
    let mut warnings = Vec::new();
    let total_hours: f64 = match exposures {
        [one] => one.tracking_hours,
        each => each.iter().map(|e| e.tracking_hours).sum(),
    };
    if total_hours < FEW_TRACKING_HOURS {
        warnings.push(format!(
            "--tracking-hours: the whole exposure is {} h of tracking the Sun, where a helioscope's campaign is thousands (BabyIAXO plans about 1.5 years of tracking): the option takes hours",
            crate::text::number(total_hours)
        ));
    }
    for (k, (dir, run)) in runs.iter().enumerate() {
        let exposure = &exposures[k.min(exposures.len() - 1)];
        let s =
            signal(run, region).map_err(|e| ReachError(format!("{}: {}", dir.display(), e.0)))?;
        let coupling = coupling_of((&run.emission, run.g_agamma, run.g_ae), dir)?;
        if kind.is_some_and(|k: &'static str| k != coupling.name()) {
            return Err(ReachError("the runs limit different couplings (Primakoff and ABC runs): give runs of one emission".into()));
        }
        kind = Some(coupling.name());
        let (b0, b1) = window_bands(&s, window)
            .map_err(|e| ReachError(format!("{}: {}", dir.display(), e.0)))?;
        let these = [s.band_edges[b0], s.band_edges[b1]];
        if let Some(first) = edges.filter(|e| *e != these) {
            return Err(ReachError(format!(
                "the runs' energy windows differ ({}: {}–{} keV, {}: {}–{} keV): give --window LO,HI with edges of every run's energy bands, so that every limit counts the same window",
                dirs[0].display(),
                crate::text::number(first[0]),
                crate::text::number(first[1]),
                dir.display(),
                crate::text::number(these[0]),
                crate::text::number(these[1])
            )));
        }
        edges = Some(these);
        let counts = exposure.background_counts((s.area_cm2, these[1] - these[0]));
        if counts > MAX_BACKGROUND_COUNTS {
            return Err(ReachError(format!(
                "{}: the background is {counts:.3e} counts in the region and window (background × area × width × time × bores), more than {MAX_BACKGROUND_COUNTS:e}: is --background in counts per keV per cm² per second?",
                dir.display()
            )));
        }
        let background = Background::new(counts);
        let limits = s
            .masses
            .iter()
            .map(|m| {
                let rate: f64 = m.spectrum[b0..b1].iter().sum();
                limit(m.mass_ev, rate, coupling, background, exposure)
            })
            .collect();
        curves.push(ReachCurve {
            label: run.gas.as_ref().map_or("vacuum".into(), |g| format!("He {g}")),
            run: dir.display().to_string(),
            limits,
            region: json!({"center_mm": s.centre_mm, "radius_mm": s.radius_mm, "area_cm2": s.area_cm2, "placed_on_mass_ev": s.placed_on_mass_ev, "fraction": s.fraction}),
            tracking_hours: exposure.tracking_hours,
        });
    }
    // Curves of the same setting (runs of other scenes) are told apart by
    // their runs.
    let labels: Vec<String> = curves.iter().map(|c| c.label.clone()).collect();
    for c in &mut curves {
        if labels.iter().filter(|l| **l == c.label).count() > 1 {
            let name = Path::new(&c.run)
                .file_name()
                .map_or(c.run.clone(), |n| n.to_string_lossy().into_owned());
            c.label = format!("{} ({name})", c.label);
        }
    }
    Ok(Reach {
        curves,
        coupling: kind.unwrap_or("g_agamma"),
        window: edges.unwrap_or([0.0; 2]),
        warnings,
    })
}

/// The bands of `s` inside `window` (their edges), or why not.
fn window_bands(s: &Signal, window: Option<[f64; 2]>) -> Result<(usize, usize), ReachError> {
    band_range(&s.band_edges, window)
}

/// The first and past-the-last energy bands between `window`'s edges
/// (edges of `e`), or why not.
pub fn band_range(e: &[f64], window: Option<[f64; 2]>) -> Result<(usize, usize), ReachError> {
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

/// What a run limits, from its emission, g_aγ and g_ae.
pub fn coupling_of(
    (emission, g_agamma, g_ae): (&str, f64, Option<f64>),
    dir: &Path,
) -> Result<Coupling, ReachError> {
    match (emission, g_ae) {
        ("primakoff", _) => Ok(Coupling::GAgamma(g_agamma)),
        ("abc", Some(g_ae)) => Ok(Coupling::GAeGAgamma(g_ae * g_agamma)),
        (e, _) => Err(ReachError(format!(
            "{}: the run's emission is {e}: its signal does not scale as one coupling; trace -D emission=primakoff for the reach in g_aγ, or -D emission=abc for g_ae·g_aγ",
            dir.display()
        ))),
    }
}
