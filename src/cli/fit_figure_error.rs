//! `traxer fit-figure-error`: fit the figure-error parameters of a scene's mirrors
//! to measured HPD / 80 % / 90 % diameters (see `traxer::fit`), with progress, a
//! CSV history and the result as a preset file.

use super::measure::{pick_sensor, run_config};
use super::{load_xray_scene, parse_define, InputError};
use anyhow::Context;
use serde_json::json;
use std::fmt::Write as _;
use std::path::PathBuf;
use traxer::files::atomic_write;
use traxer::fit::{
    fit, measure, set_figure_error, Bounds, Diameters, FitSettings, LocalAlgorithm, PARAMETERS,
};
use traxer::output::write_json;
use traxer::trace::RunConfig;

/// Fit the mirrors' figure errors to measured image quality.
///
/// Every mirror of the scene gets the same parameters (in_plane_narrow,
/// in_plane_wide, wide_fraction, out_of_plane; widths in arcsec). Each candidate is
/// traced with the same photons (--seed), so the objective — the sum of squared
/// relative errors of HPD, 80 % and 90 % diameters — is smooth; NLopt's DIRECT-L
/// searches the bounds globally, Sbplx polishes the best point. Writes
/// history.csv, fit.json and figure_error.toml (a preset for data/figure_errors.toml
/// or a scene's [figure_errors]) into --out. Example (PANTER Al Kα):
///   traxer fit-figure-error scenes/panter_al_ka.toml --target-hpd 206 --target-c80 397 --target-c90 549
#[derive(clap::Args)]
pub struct FitFigureErrorArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Measured half-power diameter (arcsec).
    #[arg(long)]
    pub target_hpd: f64,
    /// Measured 80 % diameter (arcsec).
    #[arg(long)]
    pub target_c80: f64,
    /// Measured 90 % diameter (arcsec).
    #[arg(long)]
    pub target_c90: f64,
    /// Search range NAME=LOW:HIGH, or NAME=VALUE to hold it fixed (repeatable).
    /// Defaults: in_plane_narrow=0:120, in_plane_wide=0:900, wide_fraction=0:0.6,
    /// out_of_plane=0.
    #[arg(long = "bound", value_name = "NAME=LOW:HIGH")]
    pub bounds: Vec<String>,
    /// Photons per evaluation.
    #[arg(short = 'n', long, default_value_t = 1_000_000)]
    pub photons: u64,
    /// Random seed of every evaluation (common random numbers).
    #[arg(short, long, default_value_t = 1)]
    pub seed: u64,
    /// Evaluations of the global search (DIRECT-L).
    #[arg(long, default_value_t = 150)]
    pub global_evals: u32,
    /// Evaluations of the local polish.
    #[arg(long, default_value_t = 60)]
    pub local_evals: u32,
    /// Local optimiser of the polish.
    #[arg(long, value_enum, default_value = "sbplx")]
    pub local_algorithm: LocalAlgorithm,
    /// Extra seeds traced with the best parameters to show the Monte Carlo spread.
    #[arg(long, default_value_t = 3)]
    pub check_seeds: u64,
    /// Worker threads (0 = one per core).
    #[arg(short = 'j', long, default_value_t = 0, value_parser = super::parse_threads)]
    pub threads: usize,
    /// Sensor to measure (default: the scene's only sensor).
    #[arg(long)]
    pub sensor: Option<String>,
    /// Name of the preset written to figure_error.toml.
    #[arg(long, default_value = "fitted")]
    pub name: String,
    /// Output folder.
    #[arg(short, long, default_value = "out/fit_figure_error")]
    pub out: PathBuf,
    /// Override a scene variable: -D name=value (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<String>,
    /// No line per evaluation.
    #[arg(short, long)]
    pub quiet: bool,
}

fn parse_bounds(specs: &[String]) -> Result<Bounds, InputError> {
    let mut b = Bounds::default();
    for spec in specs {
        let bad = |why: &str| InputError(format!("--bound {spec}: {why}"));
        let (name, range) = spec
            .split_once('=')
            .ok_or_else(|| bad("expected NAME=LOW:HIGH or NAME=VALUE"))?;
        let i = PARAMETERS
            .iter()
            .position(|p| *p == name.trim())
            .ok_or_else(|| {
                bad(&format!(
                    "unknown parameter (known: {})",
                    PARAMETERS.join(", ")
                ))
            })?;
        let number = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| bad("expected non-negative numbers"))
        };
        let (lo, hi) = match range.split_once(':') {
            Some((l, h)) => (number(l)?, number(h)?),
            None => {
                let v = number(range)?;
                (v, v)
            }
        };
        if lo > hi {
            return Err(bad("LOW must not exceed HIGH"));
        }
        if i == 2 && hi > 1.0 {
            return Err(bad("wide_fraction is a probability (0 to 1)"));
        }
        b.lower[i] = lo;
        b.upper[i] = hi;
    }
    Ok(b)
}

pub fn run(a: FitFigureErrorArgs) -> anyhow::Result<()> {
    let target = Diameters {
        hpd: a.target_hpd,
        d80: a.target_c80,
        d90: a.target_c90,
    };
    if ![target.hpd, target.d80, target.d90]
        .iter()
        .all(|v| v.is_finite() && *v > 0.0)
    {
        return Err(InputError("the targets must be positive diameters (arcsec)".into()).into());
    }
    let bounds = parse_bounds(&a.bounds)?;
    let (_device, mut scene) = load_xray_scene(&a.scene, &a.define)?;
    let sensor = pick_sensor(&scene, a.sensor.as_deref())?;
    if scene.sensors[sensor].focal_length.is_none() {
        return Err(InputError(format!(
            "sensor `{}` has no focal_length: the diameters in arcseconds need one",
            scene.sensors[sensor].name
        ))
        .into());
    }
    let run = run_config(a.photons, a.seed, a.threads)?;
    let settings = FitSettings {
        bounds,
        target,
        run: run.clone(),
        sensor,
        global_evaluations: a.global_evals,
        local_evaluations: a.local_evals,
        local_algorithm: a.local_algorithm,
    };
    let started = std::time::Instant::now();
    let quiet = a.quiet;
    let result = fit(&mut scene, &settings, |e, best| {
        if quiet {
            return;
        }
        let p = &e.parameters;
        let d = e
            .diameters
            .map_or("no image".into(), |d| format!("{:.1}″ {:.1}″ {:.1}″", d.hpd, d.d80, d.d90));
        eprintln!(
            "eval {:>4} ({}, {:.0} s): narrow {:.2}″ wide {:.2}″ fraction {:.4} out {:.2}″ → {d}, error {:.3e} | best {:.3e} (eval {})",
            e.index,
            e.stage,
            started.elapsed().as_secs_f64(),
            p.in_plane_narrow,
            p.in_plane_wide,
            p.wide_fraction,
            p.out_of_plane,
            e.error,
            best.error,
            best.index
        );
    })
    .map_err(anyhow::Error::msg)?;
    let best = &result.best;
    let fit_seconds = started.elapsed().as_secs_f64();

    // Monte Carlo spread: the best parameters with other seeds (the fit saw one).
    let mut spread = Vec::new();
    set_figure_error(&mut scene, Some(best.parameters));
    for k in 1..=a.check_seeds {
        let cfg = RunConfig {
            seed: a.seed.wrapping_add(k),
            ..run.clone()
        };
        if let Some(d) = measure(&scene, sensor, &cfg)? {
            spread.push(d);
        }
    }
    let stats = |f: fn(&Diameters) -> f64| -> (f64, f64) {
        let all: Vec<f64> = std::iter::once(best.diameters.as_ref().map_or(f64::NAN, f))
            .chain(spread.iter().map(f))
            .collect();
        let n = all.len() as f64;
        let mean = all.iter().sum::<f64>() / n;
        let sd = if all.len() > 1 {
            (all.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
        } else {
            f64::NAN
        };
        (mean, sd)
    };
    let (hpd, d80, d90) = (stats(|d| d.hpd), stats(|d| d.d80), stats(|d| d.d90));

    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let mut csv = String::from(
        "evaluation,stage,in_plane_narrow,in_plane_wide,wide_fraction,out_of_plane,hpd_arcsec,d80_arcsec,d90_arcsec,error\n",
    );
    for e in &result.history {
        let p = &e.parameters;
        let d = e.diameters.map_or([f64::NAN; 3], |d| [d.hpd, d.d80, d.d90]);
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{}",
            e.index,
            e.stage,
            p.in_plane_narrow,
            p.in_plane_wide,
            p.wide_fraction,
            p.out_of_plane,
            d[0],
            d[1],
            d[2],
            e.error
        );
    }
    atomic_write(&a.out.join("history.csv"), csv.as_bytes())?;
    let p = &best.parameters;
    let source = format!(
        "traxer fit-figure-error {} {}(targets HPD {}″, 80 % {}″, 90 % {}″; DIRECT-L {} + {:?} {} evaluations of {} photons, seed {}; bounds {}; traxer {} ({})). Best: HPD {:.1}″, 80 % {:.1}″, 90 % {:.1}″; over {} seeds {:.1} ± {:.1}″, {:.1} ± {:.1}″, {:.1} ± {:.1}″",
        a.scene.display(),
        a.define.iter().map(|d| format!("-D {d} ")).collect::<String>(),
        target.hpd,
        target.d80,
        target.d90,
        a.global_evals,
        a.local_algorithm,
        a.local_evals,
        a.photons,
        a.seed,
        (0..4)
            .map(|i| format!("{}={}:{}", PARAMETERS[i], bounds.lower[i], bounds.upper[i]))
            .collect::<Vec<_>>()
            .join(" "),
        env!("CARGO_PKG_VERSION"),
        traxer::output::git_hash(),
        best.diameters.map_or(f64::NAN, |d| d.hpd),
        best.diameters.map_or(f64::NAN, |d| d.d80),
        best.diameters.map_or(f64::NAN, |d| d.d90),
        spread.len() + 1,
        hpd.0,
        hpd.1,
        d80.0,
        d80.1,
        d90.0,
        d90.1,
    );
    let preset = format!(
        "# Written by traxer fit-figure-error; copy into data/figure_errors.toml or a\n# scene's [figure_errors] table.\n\n[figure_errors.{}]\nin_plane_narrow = {:.4}\nin_plane_wide = {:.4}\nwide_fraction = {:.5}\nout_of_plane = {:.4}\nsource = {}\n",
        a.name,
        p.in_plane_narrow,
        p.in_plane_wide,
        p.wide_fraction,
        p.out_of_plane,
        toml::Value::String(source.clone())
    );
    atomic_write(&a.out.join("figure_error.toml"), preset.as_bytes())?;
    write_json(
        &a.out.join("fit.json"),
        &json!({
            "scene": a.scene.display().to_string(),
            "overrides": a.define,
            "target_arcsec": target,
            "best": best,
            "evaluations": result.history.len(),
            "photons_per_evaluation": a.photons,
            "seed": a.seed,
            "fit_seconds": fit_seconds,
            "seed_check": {
                "seeds": (0..=a.check_seeds).map(|k| a.seed.wrapping_add(k)).collect::<Vec<_>>(),
                "hpd_mean_sd": [hpd.0, hpd.1],
                "d80_mean_sd": [d80.0, d80.1],
                "d90_mean_sd": [d90.0, d90.1],
            },
            "source": source,
        }),
    )?;
    say!(
        "best after {} evaluations ({:.0} s): in_plane_narrow {:.2}″, in_plane_wide {:.2}″, wide_fraction {:.4}, out_of_plane {:.2}″",
        result.history.len(),
        fit_seconds,
        p.in_plane_narrow,
        p.in_plane_wide,
        p.wide_fraction,
        p.out_of_plane
    );
    say!(
        "  HPD {:.1} ± {:.1}″ (target {}), 80 % {:.1} ± {:.1}″ (target {}), 90 % {:.1} ± {:.1}″ (target {}); mean ± sd over {} seeds",
        hpd.0, hpd.1, target.hpd, d80.0, d80.1, target.d80, d90.0, d90.1, target.d90, spread.len() + 1
    );
    say!(
        "wrote history.csv, fit.json, figure_error.toml to {}",
        a.out.display()
    );
    Ok(())
}
