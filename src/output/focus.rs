//! The files of a focus scan: focus.csv (one row per position), focus.json (the
//! fits and the provenance) and focus.png (measured diameters and fitted curves,
//! in arcseconds when the sensor knows its focal length).

use super::{line_plot, write_csv, write_json, Provenance, Series};
use crate::analysis::arcsec_of_diameter;
use crate::studies::focus::{FocusScan, DIAMETERS};
use serde_json::json;
use std::path::{Path, PathBuf};

/// The files of a focus scan.
pub const FOCUS_FILES: [&str; 3] = ["focus.csv", "focus.json", "focus.png"];

/// Writes focus.csv, focus.json and focus.png into `dir` (created if needed);
/// `var` is the swept variable, `range` its first and last value.
pub fn write_focus(
    dir: &Path,
    scan: &FocusScan,
    var: &str,
    range: (f64, f64),
    provenance: &Provenance,
) -> std::io::Result<Vec<PathBuf>> {
    crate::files::create_dir_all(dir)?;
    let csv = dir.join(FOCUS_FILES[0]);
    let header = [var, "hpd_mm", "d80_mm", "d90_mm", "photons_on_sensor"];
    write_csv(
        &csv,
        &header,
        scan.steps.iter().map(|s| {
            let q = s.quality.as_ref();
            let d = |f: fn(&crate::analysis::ImageQuality) -> f64| q.map_or(f64::NAN, f);
            vec![
                s.value.to_string(),
                d(|q| q.hpd_mm).to_string(),
                d(|q| q.d80_mm).to_string(),
                d(|q| q.d90_mm).to_string(),
                s.on_sensor.to_string(),
            ]
        }),
    )?;
    let fit_json = |k: usize| match &scan.fits[k].1 {
        Ok(f) => json!(f),
        Err(e) => json!({ "error": e.to_string() }),
    };
    let json_path = dir.join(FOCUS_FILES[1]);
    write_json(
        &json_path,
        &json!({
            "provenance": provenance,
            "scene": provenance.scene_path,
            "variable": var,
            "overrides": provenance.overrides,
            "sensor": scan.sensor,
            "photons_per_position": provenance.photons,
            "seed": provenance.seed,
            "clipped_positions": scan.clipped,
            "model": "D(z)^2 = d0^2 + slope^2 (z - z0)^2, weighted least squares on D^2 with weights 1/D^2; diameters in mm",
            "fit_hpd": fit_json(0),
            "fit_d80": fit_json(1),
            "fit_d90": fit_json(2),
        }),
    )?;
    let png = dir.join(FOCUS_FILES[2]);
    plot(&png, scan, var, range, provenance)?;
    Ok(vec![csv, json_path, png])
}

/// Diameters (mm) as plotted: arcseconds when the focal length is known.
pub fn plotted_diameter(d_mm: f64, focal_length: Option<f64>) -> f64 {
    match focal_length {
        Some(f) => arcsec_of_diameter(d_mm, f),
        None => d_mm,
    }
}

fn plot(
    path: &Path,
    scan: &FocusScan,
    var: &str,
    (from, to): (f64, f64),
    provenance: &Provenance,
) -> std::io::Result<()> {
    let to_unit = |d: f64| plotted_diameter(d, scan.focal_length);
    let mut series = Vec::new();
    for (k, ((label, diameter), (_, fit))) in DIAMETERS.iter().zip(&scan.fits).enumerate() {
        let points = scan.points(*diameter);
        series.push(
            Series::dots(
                format!("{label} traced"),
                points.iter().map(|&(z, d)| (z, to_unit(d))).collect(),
            )
            .with_color(k),
        );
        if let Ok(f) = fit {
            let curve = (0..=200)
                .map(|k| {
                    let z = from + (to - from) * k as f64 / 200.0;
                    (z, to_unit(f.diameter_at(z)))
                })
                .collect();
            series.push(
                Series::line(format!("{label} fit: best at {:.2} mm", f.z0), curve)
                    .with_color(k)
                    .without_markers(),
            );
        }
    }
    line_plot(
        path,
        &format!(
            "focus sweep: {}",
            provenance
                .scene_path
                .as_deref()
                .map_or("", |p| p.rsplit('/').next().unwrap_or(p))
        ),
        &format!("{var} (scene variable placing the sensor) [mm]"),
        if scan.focal_length.is_some() {
            "diameter around the centroid [arcsec]"
        } else {
            "diameter around the centroid [mm]"
        },
        &series,
        (900, 600),
    )
}
