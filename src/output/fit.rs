//! The files of a figure-error fit: history.csv (every evaluation), fit.json (the
//! best parameters, the seed check, the parameters' errors, the predictions and
//! the provenance) and figure_error.toml (the
//! result as a preset for data/figure_errors.toml or a scene's [figure_errors]).

use super::{write_csv, write_json, Provenance};
use crate::files::atomic_write;
use crate::studies::fit::{FitResult, FitSettings, Spread, PARAMETERS};
use crate::studies::fit_errors::{ParameterErrors, Prediction};
use crate::studies::fit_study::{FitOutput, FitStudy};
use serde_json::json;
use std::path::{Path, PathBuf};

/// A finished fit with what it was asked.
pub struct FitReport<'a> {
    pub result: &'a FitResult,
    pub settings: &'a FitSettings,
    pub spread: &'a Spread,
    /// Extra seeds of the spread check (seed + 1 …).
    pub extra_seeds: u64,
    /// Name of the preset in figure_error.toml.
    pub preset_name: &'a str,
    pub fit_seconds: f64,
    /// The parameters' errors at the best point.
    pub errors: &'a ParameterErrors,
    /// The diameters predicted for other scenes with the best parameters.
    pub predictions: &'a [Prediction],
}

impl<'a> FitReport<'a> {
    /// The report of `study`'s finished `output`.
    pub fn of(study: &'a FitStudy, output: &'a FitOutput) -> FitReport<'a> {
        FitReport {
            result: &output.result,
            settings: &study.settings,
            spread: &output.spread,
            extra_seeds: study.after.check_seeds,
            preset_name: &study.after.preset_name,
            fit_seconds: output.fit_seconds,
            errors: &output.errors,
            predictions: &output.predictions,
        }
    }

    /// How the preset was obtained, for its `source` key: the command, targets,
    /// budget, bounds, version and the result with its spread.
    pub fn source(&self, provenance: &Provenance) -> String {
        let (s, best, sp) = (self.settings, &self.result.best, self.spread);
        let t = &s.target;
        let d =
            |f: fn(&crate::studies::Diameters) -> f64| best.diameters.as_ref().map_or(f64::NAN, f);
        format!(
            "traxer fit-figure-error {} {}(targets HPD {}″, 80 % {}″, 90 % {}″; DIRECT-L {} + {:?} {} evaluations of {} photons, seed {}; bounds {}; traxer {} ({})). Best: HPD {:.1}″, 80 % {:.1}″, 90 % {:.1}″; over {} seeds {:.1} ± {:.1}″, {:.1} ± {:.1}″, {:.1} ± {:.1}″",
            provenance.scene_path.as_deref().unwrap_or(""),
            provenance.overrides.iter().map(|d| format!("-D {d} ")).collect::<String>(),
            t.hpd,
            t.d80,
            t.d90,
            s.global_evaluations,
            s.local_algorithm,
            s.local_evaluations,
            s.run.photons,
            s.run.seed,
            (0..4)
                .map(|i| format!("{}={}:{}", PARAMETERS[i], s.bounds.lower[i], s.bounds.upper[i]))
                .collect::<Vec<_>>()
                .join(" "),
            provenance.traxer_version,
            provenance.git_hash,
            d(|d| d.hpd),
            d(|d| d.d80),
            d(|d| d.d90),
            sp.seeds,
            sp.hpd.0,
            sp.hpd.1,
            sp.d80.0,
            sp.d80.1,
            sp.d90.0,
            sp.d90.1,
        )
    }
}

/// The files of a fit.
pub const FIT_FILES: [&str; 3] = ["history.csv", "figure_error.toml", "fit.json"];

/// The fitted parameters' covariance as the preset's `covariance` table (read
/// back by `xray::figure_covariance`), or nothing without free parameters.
fn covariance_toml(report: &FitReport) -> String {
    let e = report.errors;
    if e.names.is_empty() {
        return String::new();
    }
    let c = crate::xray::figure_covariance::FigureCovariance {
        parameters: e.names.iter().map(|n| n.to_string()).collect(),
        matrix: e.covariance.clone(),
        unconstrained: e.unconstrained(),
    };
    format!(
        "\n# The covariance of the fitted parameters (Monte Carlo and a {:.1} % uncertainty of\n# each target combined), for parameter sets drawn from it.\n[figure_errors.{}.covariance]\n{}",
        100.0 * e.target_fraction,
        report.preset_name,
        toml::to_string(&c).expect("names and numbers serialise")
    )
}

/// Writes history.csv, figure_error.toml and fit.json into `dir`.
pub fn write_fit(
    dir: &Path,
    report: &FitReport,
    provenance: &Provenance,
) -> std::io::Result<Vec<PathBuf>> {
    crate::files::create_dir_all(dir)?;
    let history = dir.join(FIT_FILES[0]);
    let header = [
        "evaluation",
        "stage",
        "in_plane_narrow",
        "in_plane_wide",
        "wide_fraction",
        "out_of_plane",
        "hpd_arcsec",
        "d80_arcsec",
        "d90_arcsec",
        "error",
    ];
    write_csv(
        &history,
        &header,
        report.result.history.iter().map(|e| {
            let p = &e.parameters;
            let d = e.diameters.map_or([f64::NAN; 3], |d| [d.hpd, d.d80, d.d90]);
            vec![
                e.index.to_string(),
                e.stage.to_string(),
                p.in_plane_narrow.to_string(),
                p.in_plane_wide.to_string(),
                p.wide_fraction.to_string(),
                p.out_of_plane.to_string(),
                d[0].to_string(),
                d[1].to_string(),
                d[2].to_string(),
                e.error.to_string(),
            ]
        }),
    )?;
    let toml_path = dir.join(FIT_FILES[1]);
    atomic_write(&toml_path, fit_preset_toml(report, provenance).as_bytes())?;
    let json_path = dir.join(FIT_FILES[2]);
    write_json(&json_path, &fit_json(report, provenance))?;
    Ok(vec![history, toml_path, json_path])
}

/// figure_error.toml: the fitted parameters as a preset, with how they were
/// obtained and their covariance.
pub fn fit_preset_toml(report: &FitReport, provenance: &Provenance) -> String {
    let source = report.source(provenance);
    let p = &report.result.best.parameters;
    let preset = format!(
        "# Written by traxer fit-figure-error; copy into data/figure_errors.toml or a\n# scene's [figure_errors] table.\n\n[figure_errors.{}]\nin_plane_narrow = {:.4}\nin_plane_wide = {:.4}\nwide_fraction = {:.5}\nout_of_plane = {:.4}\nsource = {}\n",
        report.preset_name,
        p.in_plane_narrow,
        p.in_plane_wide,
        p.wide_fraction,
        p.out_of_plane,
        toml::Value::String(source.clone())
    );
    preset + &covariance_toml(report)
}

/// fit.json: the targets, the best evaluation, the seed check, the
/// parameters' errors, the predictions and the provenance.
pub fn fit_json(report: &FitReport, provenance: &Provenance) -> serde_json::Value {
    let source = report.source(provenance);
    let (s, sp) = (report.settings, report.spread);
    json!({
            "provenance": provenance,
            "scene": provenance.scene_path,
            "overrides": provenance.overrides,
            "target_arcsec": s.target,
            "best": report.result.best,
            "evaluations": report.result.history.len(),
            "photons_per_evaluation": s.run.photons,
            "seed": s.run.seed,
            "fit_seconds": report.fit_seconds,
            "evaluations_resumed_from_record": report.result.replayed,
            "seed_check": {
                "seeds": (0..=report.extra_seeds).map(|k| s.run.seed.wrapping_add(k)).collect::<Vec<_>>(),
                "hpd_mean_sd": [sp.hpd.0, sp.hpd.1],
                "d80_mean_sd": [sp.d80.0, sp.d80.1],
                "d90_mean_sd": [sp.d90.0, sp.d90.1],
            },
            "parameter_errors": report.errors,
            "predictions": report.predictions,
            "source": source,
    })
}
