//! The files of an effective-area sweep: effective_area.csv (one row per angle and
//! energy, with errors and the area by path class), off_axis.csv (image quality
//! per angle), effective_area.json (provenance, settings, results) and the plots
//! effective_area.png (area against energy, one curve per angle), vignetting.png
//! (area against angle, a few energies) and off_axis.png (HPD, 80 %, 90 % against
//! angle), and one OGIP ARF per angle (`output::arf`).

use super::{line_plot, write_csv, write_json, Provenance, Series};
use crate::history::PathClass;
use crate::studies::effective_area::AreaResult;
use serde_json::json;
use std::path::{Path, PathBuf};

/// The files of a sweep.
pub const EFFECTIVE_AREA_FILES: EffectiveAreaFiles = EffectiveAreaFiles {
    area_csv: "effective_area.csv",
    off_axis_csv: "off_axis.csv",
    summary_json: "effective_area.json",
    area_png: "effective_area.png",
    vignetting_png: "vignetting.png",
    off_axis_png: "off_axis.png",
    vignetting_fits: "vignetting.fits",
};

/// A sweep's files, by what they hold.
#[derive(Clone, Copy, Debug)]
pub struct EffectiveAreaFiles {
    /// Area by energy and angle, with the path classes' shares.
    pub area_csv: &'static str,
    /// Image quality off axis.
    pub off_axis_csv: &'static str,
    pub summary_json: &'static str,
    pub area_png: &'static str,
    pub vignetting_png: &'static str,
    pub off_axis_png: &'static str,
    /// The vignetting as an OGIP table.
    pub vignetting_fits: &'static str,
}

impl EffectiveAreaFiles {
    /// Every name, in the order above.
    pub fn all(&self) -> [&'static str; 7] {
        [
            self.area_csv,
            self.off_axis_csv,
            self.summary_json,
            self.area_png,
            self.vignetting_png,
            self.off_axis_png,
            self.vignetting_fits,
        ]
    }
}

/// Every file of a sweep over these angles and energies: the seven above and,
/// with at least two energies, one OGIP ARF per angle ([`super::arf_name`])
/// and, if the angles start on the axis and none is negative, SIXTE's
/// vignetting file ([`super::SIXTE_VIGNETTING`]).
pub fn effective_area_files(angles_arcmin: &[f64], energies: &[f64]) -> Vec<String> {
    let mut names: Vec<String> = EFFECTIVE_AREA_FILES
        .all()
        .iter()
        .map(|s| s.to_string())
        .collect();
    if super::energy_bins(energies).is_some() {
        names.extend(angles_arcmin.iter().map(|&a| super::arf_name(a)));
        if super::sixte_vignetting_refused(angles_arcmin).is_none() {
            names.push(super::SIXTE_VIGNETTING.to_string());
        }
    }
    names
}

/// Writes every file of the sweep into `dir` (the ARFs too,
/// [`effective_area_files`]); returns their paths.
pub fn write_effective_area(
    dir: &Path,
    r: &AreaResult,
    radius_mm: Option<f64>,
    provenance: &Provenance,
) -> std::io::Result<Vec<PathBuf>> {
    crate::files::create_dir_all(dir)?;
    let files = EFFECTIVE_AREA_FILES;
    let mut header = vec![
        "off_axis_arcmin".to_string(),
        "energy_keV".into(),
        "area_cm2".into(),
        "error_cm2".into(),
    ];
    header.extend(
        PathClass::ALL
            .iter()
            .map(|c| format!("area_{}_cm2", c.name())),
    );
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    write_csv(
        &dir.join(files.area_csv),
        &header,
        r.angles.iter().flat_map(|a| {
            a.points.iter().map(move |p| {
                let mut row = vec![
                    a.off_axis_arcmin.to_string(),
                    p.energy_kev.to_string(),
                    p.area_cm2.to_string(),
                    p.error_cm2.to_string(),
                ];
                row.extend(p.by_class_cm2.iter().map(|v| v.to_string()));
                row
            })
        }),
    )?;
    let q = |a: &crate::studies::effective_area::AngleResult,
             f: fn(&crate::analysis::ImageQuality) -> Option<f64>| {
        a.quality
            .as_ref()
            .and_then(f)
            .map_or(String::new(), |v| v.to_string())
    };
    write_csv(
        &dir.join(files.off_axis_csv),
        &[
            "off_axis_arcmin",
            "centroid_x_mm",
            "centroid_y_mm",
            "hpd_mm",
            "d80_mm",
            "d90_mm",
            "hpd_arcsec",
            "d80_arcsec",
            "d90_arcsec",
            "photons_on_sensor",
            "geometric_area_cm2",
        ],
        r.angles.iter().map(|a| {
            vec![
                a.off_axis_arcmin.to_string(),
                q(a, |q| Some(q.centroid_mm[0])),
                q(a, |q| Some(q.centroid_mm[1])),
                q(a, |q| Some(q.hpd_mm)),
                q(a, |q| Some(q.d80_mm)),
                q(a, |q| Some(q.d90_mm)),
                q(a, |q| q.hpd_arcsec),
                q(a, |q| q.d80_arcsec),
                q(a, |q| q.d90_arcsec),
                a.on_sensor.to_string(),
                a.geometric_area_cm2.to_string(),
            ]
        }),
    )?;
    write_json(
        &dir.join(files.summary_json),
        &json!({
            "provenance": provenance,
            "sensor": r.sensor,
            "counts": r.counts,
            "radius_mm": radius_mm,
            "aperture_cm2": r.aperture_cm2,
            "photons_per_angle": provenance.photons,
            "method": "each photon traced once per angle (once per energy and angle with rough mirrors or a gas detector); its weight at every energy is the product of R(E, θ) and T(E, θ) along its path; area = beam cross-section × Σw / N, error = cross-section × s/√N",
            "image_weights": "off-axis image quality from the image weighted by each photon's mean weight over the energies (a flat spectrum over them); the counting region's centre is the photons' centroid",
            "seconds": r.seconds,
            "threads": r.threads,
            "angles": r.angles,
        }),
    )?;
    write_plots(dir, r)?;
    super::arf::write_vignetting(&dir.join(files.vignetting_fits), r, provenance)?;
    super::arf::write_responses(dir, r, provenance)?;
    Ok(files.all().iter().map(|name| dir.join(name)).collect())
}

/// The effective-area curves (one per angle, ±1σ bands) and the on-axis
/// geometric area as a dashed reference; the plot's title.
fn area_curves(r: &AreaResult) -> (Vec<Series>, String) {
    let mut by_energy: Vec<Series> = r
        .angles
        .iter()
        .map(|a| {
            Series::line(
                format!("{}′ off axis", a.off_axis_arcmin),
                a.points
                    .iter()
                    .map(|p| (p.energy_kev, p.area_cm2))
                    .collect(),
            )
            .with_band(
                a.points
                    .iter()
                    .map(|p| (p.area_cm2 - p.error_cm2, p.area_cm2 + p.error_cm2))
                    .collect(),
            )
        })
        .collect();
    // The area every reflectivity and transmission 1 would give: what the
    // mirrors' geometry collects, the ceiling of the first angle's curve.
    let first = &r.angles[0];
    let energies = || first.points.iter().map(|p| p.energy_kev);
    let (e0, e1) = (
        energies().fold(f64::INFINITY, f64::min),
        energies().fold(f64::NEG_INFINITY, f64::max),
    );
    if e0 < e1 && first.geometric_area_cm2 > 0.0 {
        by_energy.push(
            Series::line(
                format!(
                    "geometric area at {}′ (R = T = 1): {:.4} cm²",
                    first.off_axis_arcmin, first.geometric_area_cm2
                ),
                vec![
                    (e0, first.geometric_area_cm2),
                    (e1, first.geometric_area_cm2),
                ],
            )
            .with_color(0)
            .dashed(),
        );
    }
    let title = match r.counts.starts_with("X-rays converting") {
        true => format!(
            "effective area for X-rays converting in the gas of {}",
            r.sensor
        ),
        false => format!("effective area on {}", r.sensor),
    };
    let title = format!("{}: {title} (bands: ±1σ Monte Carlo)", r.optic);
    (by_energy, title)
}

fn write_plots(dir: &Path, r: &AreaResult) -> std::io::Result<()> {
    let files = EFFECTIVE_AREA_FILES;
    let (by_energy, title) = area_curves(r);
    line_plot(
        &dir.join(files.area_png),
        &title,
        "energy [keV]",
        "effective area [cm²]",
        &by_energy,
        (800, 500),
    )?;
    let (by_angle, title) = vignetting_curves(r);
    line_plot(
        &dir.join(files.vignetting_png),
        &title,
        "off-axis angle [arcmin]",
        &format!(
            "vignetting: area / area at {}′",
            r.angles[0].off_axis_arcmin
        ),
        &by_angle,
        (800, 500),
    )?;
    let arcsec = r
        .angles
        .iter()
        .any(|a| a.quality.as_ref().is_some_and(|q| q.hpd_arcsec.is_some()));
    let diameters: Vec<Series> = [("HPD", 0), ("80 %", 1), ("90 %", 2)]
        .iter()
        .map(|&(label, i)| {
            Series::line(
                label,
                r.angles
                    .iter()
                    .filter_map(|a| {
                        let q = a.quality.as_ref()?;
                        let v = match (i, arcsec) {
                            (0, true) => q.hpd_arcsec?,
                            (1, true) => q.d80_arcsec?,
                            (2, true) => q.d90_arcsec?,
                            (0, false) => q.hpd_mm,
                            (1, false) => q.d80_mm,
                            _ => q.d90_mm,
                        };
                        Some((a.off_axis_arcmin, v))
                    })
                    .collect(),
            )
        })
        .collect();
    let unit = if arcsec {
        "diameter around the centroid [arcsec]"
    } else {
        "diameter around the centroid [mm]"
    };
    let title = format!("{}: off-axis image quality on {}", r.optic, r.sensor);
    line_plot(
        &dir.join(files.off_axis_png),
        &title,
        "off-axis angle [arcmin]",
        unit,
        &diameters,
        (800, 500),
    )
}

/// Energies a physicist plots vignetting at: the X-ray lines of calibration
/// sources (Al Kα 1.49, Ti Kα 4.51, Fe Kα 6.41, Cu Kα 8.05 keV) and round
/// numbers; the sweep's nearest energy to each is taken.
const VIGNETTING_KEV: [f64; 6] = [1.0, 1.49, 3.0, 4.51, 6.41, 8.05];

/// The vignetting curves, the area at each angle over the area at the first
/// (smallest) angle, at the sweep's energies nearest [`VIGNETTING_KEV`] (all
/// of them when there are at most six); energies without area at the first
/// angle are left out and named in the title.
/// The largest relative error of the on-axis area a vignetting curve is drawn
/// with.
const MAX_ON_AXIS_ERROR: f64 = 0.1;

fn vignetting_curves(r: &AreaResult) -> (Vec<Series>, String) {
    let energies: Vec<f64> = r.angles[0].points.iter().map(|p| p.energy_kev).collect();
    let mut picks: Vec<usize> = if energies.len() <= 6 {
        (0..energies.len()).collect()
    } else {
        let (lo, hi) = (energies[0], energies[energies.len() - 1]);
        VIGNETTING_KEV
            .iter()
            .filter(|&&e| e >= lo - 0.25 && e <= hi + 0.25)
            .map(|&e| {
                (0..energies.len())
                    .min_by(|&a, &b| (energies[a] - e).abs().total_cmp(&(energies[b] - e).abs()))
                    .expect("a sweep has energies")
            })
            .collect()
    };
    picks.dedup();
    let (mut no_area, mut noisy) = (Vec::new(), Vec::new());
    let mut curves = Vec::new();
    for k in picks {
        let (on_axis, on_axis_error) = (
            r.angles[0].points[k].area_cm2,
            r.angles[0].points[k].error_cm2,
        );
        if on_axis <= 0.0 {
            no_area.push(format!("{} keV", energies[k]));
            continue;
        }
        // A ratio to an on-axis area known to worse than 10 % is noise, not
        // vignetting: left out and named.
        if on_axis_error > MAX_ON_AXIS_ERROR * on_axis {
            noisy.push(format!("{} keV", energies[k]));
            continue;
        }
        // ±1σ of the ratio, the two areas' errors taken as independent.
        let ratio = |a: &crate::studies::effective_area::AreaPoint| {
            let v = a.area_cm2 / on_axis;
            let rel = (a.error_cm2 / on_axis).hypot(v * on_axis_error / on_axis);
            (v, rel)
        };
        curves.push(
            Series::line(
                format!("{} keV", energies[k]),
                r.angles
                    .iter()
                    .map(|a| (a.off_axis_arcmin, ratio(&a.points[k]).0))
                    .collect(),
            )
            .with_band(
                r.angles
                    .iter()
                    .map(|a| {
                        let (v, s) = ratio(&a.points[k]);
                        (v - s, v + s)
                    })
                    .collect(),
            ),
        );
    }
    let mut title = format!("{}: vignetting on {} (bands: ±1σ)", r.optic, r.sensor);
    if !no_area.is_empty() {
        title.push_str(&format!("; {} left out: no area", no_area.join(", ")));
    }
    if !noisy.is_empty() {
        title.push_str(&format!(
            "; {} left out: on-axis area uncertain by over {:.0} %",
            noisy.join(", "),
            100.0 * MAX_ON_AXIS_ERROR
        ));
    }
    (curves, title)
}
