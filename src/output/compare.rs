//! The results of an analytic-versus-mesh comparison: a Markdown table for the
//! terminal, compare.csv and compare.json. Diameters are in arcseconds when the
//! sensor knows its focal length, else mm; differences are relative to the first
//! (analytic) row.

use super::{write_csv, write_json, Provenance};
use crate::analysis::ImageQuality;
use crate::studies::compare::Row;
use serde_json::json;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One row's numbers relative to the reference row.
struct Relative {
    diameters: [f64; 3],
    diff_pct: [f64; 3],
    on_sensor_pct: f64,
    time: f64,
}

/// The rows' diameters and differences, and whether they are in arcseconds.
fn relative(rows: &[Row]) -> (Vec<Relative>, bool) {
    let Some(q0) = rows.first().and_then(|r| r.measured.quality.as_ref()) else {
        return (Vec::new(), false);
    };
    let arcsec = q0.hpd_arcsec.is_some();
    let pick = |q: &ImageQuality| -> [f64; 3] {
        if arcsec {
            [q.hpd_arcsec, q.d80_arcsec, q.d90_arcsec].map(|v| v.unwrap_or(f64::NAN))
        } else {
            [q.hpd_mm, q.d80_mm, q.d90_mm]
        }
    };
    let (d0, reference) = (pick(q0), &rows[0].measured);
    let pct = |x: f64, x0: f64| 100.0 * (x / x0 - 1.0);
    let out = rows
        .iter()
        .map(|r| {
            let d = r.measured.quality.as_ref().map_or([f64::NAN; 3], pick);
            Relative {
                diameters: d,
                diff_pct: [pct(d[0], d0[0]), pct(d[1], d0[1]), pct(d[2], d0[2])],
                on_sensor_pct: pct(r.measured.on_sensor as f64, reference.on_sensor as f64),
                time: r.measured.seconds / reference.seconds,
            }
        })
        .collect();
    (out, arcsec)
}

/// The comparison as a Markdown table.
pub fn compare_markdown(rows: &[Row]) -> String {
    let (rel, arcsec) = relative(rows);
    let unit = if arcsec { "″" } else { " mm" };
    let mut md = String::from(
        "| representation | triangles | HPD | ΔHPD | 80 % | Δ80 | 90 % | Δ90 | on sensor | Δ on sensor | photons/s | time vs analytic |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for (r, x) in rows.iter().zip(&rel) {
        let (d, diff) = (x.diameters, x.diff_pct);
        let _ = writeln!(
            md,
            "| {} | {} | {:.1}{unit} | {:+.2} % | {:.1}{unit} | {:+.2} % | {:.1}{unit} | {:+.2} % | {} | {:+.2} % | {:.2} M | {:.2} |",
            r.label,
            r.triangles,
            d[0],
            diff[0],
            d[1],
            diff[1],
            d[2],
            diff[2],
            r.measured.on_sensor,
            x.on_sensor_pct,
            r.measured.photons_per_second() / 1e6,
            x.time
        );
    }
    md.trim_end().to_string()
}

/// The files of a comparison.
pub const COMPARE_FILES: [&str; 2] = ["compare.csv", "compare.json"];

/// Writes compare.csv and compare.json into `dir` (created if needed).
pub fn write_compare(
    dir: &Path,
    rows: &[Row],
    provenance: &Provenance,
) -> std::io::Result<Vec<PathBuf>> {
    crate::files::create_dir_all(dir)?;
    let (rel, arcsec) = relative(rows);
    let csv = dir.join(COMPARE_FILES[0]);
    let header = [
        "representation",
        "triangles",
        "hpd",
        "d80",
        "d90",
        "diameter_unit",
        "hpd_diff_pct",
        "d80_diff_pct",
        "d90_diff_pct",
        "on_sensor",
        "on_sensor_diff_pct",
        "photons_per_s",
        "seconds",
    ];
    write_csv(
        &csv,
        &header,
        rows.iter().zip(&rel).map(|(r, x)| {
            let (d, diff) = (x.diameters, x.diff_pct);
            vec![
                r.label.clone(),
                r.triangles.to_string(),
                d[0].to_string(),
                d[1].to_string(),
                d[2].to_string(),
                if arcsec { "arcsec" } else { "mm" }.to_string(),
                diff[0].to_string(),
                diff[1].to_string(),
                diff[2].to_string(),
                r.measured.on_sensor.to_string(),
                x.on_sensor_pct.to_string(),
                r.measured.photons_per_second().to_string(),
                r.measured.seconds.to_string(),
            ]
        }),
    )?;
    let json_rows = compare_rows_json(rows);
    let json_path = dir.join(COMPARE_FILES[1]);
    write_json(
        &json_path,
        &json!({
            "provenance": provenance,
            "scene": provenance.scene_path,
            "overrides": provenance.overrides,
            "photons": provenance.photons,
            "seed": provenance.seed,
            "threads": provenance.threads,
            "rows": json_rows,
        }),
    )?;
    Ok(vec![csv, json_path])
}

/// The rows as compare.json holds them: each representation's scene,
/// triangles, image quality, differences to the first row (per cent), photons
/// on the sensor and speed.
pub fn compare_rows_json(rows: &[Row]) -> Vec<serde_json::Value> {
    let (rel, _) = relative(rows);
    rows.iter()
        .zip(&rel)
        .map(|(r, x)| {
            json!({
                "representation": r.label,
                "scene": r.path.display().to_string(),
                "triangles": r.triangles,
                "image_quality": r.measured.quality,
                "diameter_diff_pct": { "hpd": x.diff_pct[0], "d80": x.diff_pct[1], "d90": x.diff_pct[2] },
                "photons_on_sensor": r.measured.on_sensor,
                "photons_on_sensor_diff_pct": x.on_sensor_pct,
                "photons_per_s": r.measured.photons_per_second(),
                "trace_seconds": r.measured.seconds,
            })
        })
        .collect()
}
