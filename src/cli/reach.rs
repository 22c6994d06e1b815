//! `traxer reach`: the median expected upper limit on the coupling versus the
//! axion mass from finished magnet runs.

use super::signal::RegionArgs;
use super::InputError;
use anyhow::Context;
use serde_json::json;
use std::path::PathBuf;
use traxer::analysis::reach::{limit, Coupling, Exposure};
use traxer::analysis::signal::{RunSignal, Signal};
use traxer::files::OutputFolder;
use traxer::output::{write_reach, Provenance, ReachCurve, REACH_FILES};

/// The expected sensitivity: limit on g_aγ (or g_ae·g_aγ) versus m_a.
///
/// For each run (a finished `traxer trace` of a Sun scene with its magnet on,
/// e.g. one per buffer-gas setting, each with a --masses scan) takes the
/// signal in a signal region (as `traxer signal`) and an energy window, and
/// gives the median expected 95 % CL upper limit under the background-only
/// hypothesis: CLs, exact Poisson, one bin; with no background 3.0 counts.
/// The signal scales as g_aγ⁴ for a Primakoff run and as (g_ae·g_aγ)² for an
/// ABC run, so the limit on the counts gives the coupling's. Writes reach.csv,
/// reach.png (log m_a against log coupling, a curve per run, the vacuum
/// plateau dashed) and reach.json into --out (default FIRST_RUN/reach).
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
    /// Hours of tracking the Sun (per run).
    #[arg(value_name = "H", long)]
    pub tracking_hours: f64,
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

impl ReachArgs {
    fn exposure(&self) -> Result<Exposure, InputError> {
        let positive = |v: f64, what: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(InputError(format!("{what} {v}: expected a number > 0")))
            }
        };
        if !(self.background.is_finite() && self.background >= 0.0) {
            return Err(InputError(format!(
                "--background {}: counts per keV per cm² per second, ≥ 0",
                self.background
            )));
        }
        if !(self.efficiency > 0.0 && self.efficiency <= 1.0) {
            return Err(InputError(format!(
                "--efficiency {}: in (0, 1]",
                self.efficiency
            )));
        }
        Ok(Exposure {
            tracking_hours: positive(self.tracking_hours, "--tracking-hours")?,
            bores: positive(self.bores, "--bores")?,
            efficiency: self.efficiency,
            background: self.background,
        })
    }
}

/// The bands of `s` inside `window` (their edges), or why not.
fn window_bands(s: &Signal, window: &[f64]) -> Result<(usize, usize), InputError> {
    let e = &s.band_edges;
    let n = e.len() - 1;
    let [lo, hi] = match window {
        [] => return Ok((0, n)),
        [lo, hi] if lo < hi => [*lo, *hi],
        _ => {
            return Err(InputError(
                "--window LO,HI: two energies (keV), LO < HI".into(),
            ))
        }
    };
    let at = |v: f64| {
        e.iter()
            .position(|x| (x - v).abs() <= 1e-9 * x.abs().max(1.0))
    };
    match (at(lo), at(hi)) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => Err(InputError(format!(
            "--window {lo},{hi}: the window's edges must be edges of the run's energy bands ({} keV); trace with -D energy_bins=[LO,HI,COUNT] for others",
            e.iter().map(|x| traxer::text::number(*x)).collect::<Vec<_>>().join(", ")
        ))),
    }
}

/// What a run's signal limits.
fn coupling_of(run: &RunSignal, dir: &std::path::Path) -> Result<Coupling, InputError> {
    match (run.emission.as_str(), run.g_ae) {
        ("primakoff", _) => Ok(Coupling::GAgamma(run.g_agamma)),
        ("abc", Some(g_ae)) => Ok(Coupling::GAeGAgamma(g_ae * run.g_agamma)),
        (e, _) => Err(InputError(format!(
            "{}: the run's emission is {e}: its signal does not scale as one coupling; trace -D emission=primakoff for the reach in g_aγ, or -D emission=abc for g_ae·g_aγ",
            dir.display()
        ))),
    }
}

/// Each run's curve, what they limit and the energy window.
fn curves(
    a: &ReachArgs,
    exposure: &Exposure,
) -> Result<(Vec<ReachCurve>, &'static str, [f64; 2]), InputError> {
    let mut curves = Vec::new();
    let mut kind = None;
    let mut window = [0.0; 2];
    for dir in &a.runs {
        let (run, s) = a.region.measure(dir)?;
        let coupling = coupling_of(&run, dir)?;
        if kind.is_some_and(|k: &'static str| k != coupling.name()) {
            return Err(InputError("the runs limit different couplings (Primakoff and ABC runs): give runs of one emission".into()));
        }
        kind = Some(coupling.name());
        let (b0, b1) = window_bands(&s, &a.window)?;
        window = [s.band_edges[b0], s.band_edges[b1]];
        let limits = s
            .masses
            .iter()
            .map(|m| {
                let rate: f64 = m.spectrum[b0..b1].iter().sum();
                limit(
                    m.mass_ev,
                    rate,
                    coupling,
                    (s.area_cm2, window[1] - window[0]),
                    exposure,
                )
            })
            .collect();
        curves.push(ReachCurve {
            label: run.gas.as_ref().map_or("vacuum".into(), |g| format!("He {g}")),
            run: dir.display().to_string(),
            limits,
            region: json!({"centre_mm": s.centre_mm, "radius_mm": s.radius_mm, "area_cm2": s.area_cm2, "fraction": s.fraction}),
        });
    }
    Ok((curves, kind.unwrap_or("g_agamma"), window))
}

pub fn run(a: ReachArgs) -> anyhow::Result<()> {
    let exposure = a.exposure()?;
    let (curves, kind, window) = curves(&a, &exposure)?;
    let out = a
        .output
        .out
        .clone()
        .unwrap_or_else(|| a.runs[0].join("reach"));
    let folder = OutputFolder::prepare(&out, &REACH_FILES)?;
    let provenance = Provenance::of_table(&super::invocation());
    write_reach(
        folder.path(),
        &curves,
        kind,
        (&exposure, window),
        &provenance,
    )
    .and_then(|_| folder.commit())
    .with_context(|| format!("cannot write the reach into {}", out.display()))?;
    say!(
        "{:<28} {:>10} {:>12} {:>12} {:>10} {:>12}",
        "setting",
        "m_a (eV)",
        "signal",
        "background",
        "limit",
        kind
    );
    for c in &curves {
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
    if !a.output.quiet.quiet {
        tell!("wrote {} to {}", REACH_FILES.join(", "), out.display());
    }
    Ok(())
}
