//! The encircled-energy plot of an image: flux fraction against radius (in
//! arcseconds when the focal length is known, with mm on the top axis, else
//! mm), with the 50/80/90 % radii marked.

use super::plot::{line_plot_with_top_axis, TopAxis};
use super::Series;
use crate::analysis::{arcsec_of_radius, Eef, ImageQuality};
use std::path::Path;

/// Writes the EEF plot (fraction versus radius, in arcsec when the focal length is
/// known, else mm) with the 50/80/90 % radii marked.
pub fn write_eef_plot(
    path: &Path,
    title: &str,
    q: &ImageQuality,
    eef: &Eef,
) -> std::io::Result<()> {
    let to_x = |r_mm: f64| match q.focal_length_mm {
        Some(f) => arcsec_of_radius(r_mm, f),
        None => r_mm,
    };
    // Physicists quote diameters (HPD) while the curve is drawn against the
    // radius around the centroid: the axis and every label say which is which.
    let x_label = if q.focal_length_mm.is_some() {
        "radius r around the centroid [arcsec]  (diameters = 2r)"
    } else {
        "radius r around the centroid [mm]  (diameters = 2r)"
    };
    // Thin the curve to ≤ 2000 points for plotting.
    let step = (eef.radius_mm.len() / 2000).max(1);
    let mut curve: Vec<(f64, f64)> = eef
        .radius_mm
        .iter()
        .zip(&eef.fraction)
        .step_by(step)
        .map(|(&r, &f)| (to_x(r), f))
        .collect();
    curve.insert(0, (0.0, 0.0));
    let mut series = vec![Series::line("fraction of the flux within r", curve).without_markers()];
    for (name, diam) in [
        ("50 % (HPD)", q.hpd_mm),
        ("80 %", q.d80_mm),
        ("90 %", q.d90_mm),
    ] {
        let r = to_x(0.5 * diam);
        let frac = name[..2].parse::<f64>().unwrap_or(0.0) / 100.0;
        let label = match q.focal_length_mm {
            Some(_) => format!("{name} at r = {r:.1}″: diameter 2r = {:.1}″", 2.0 * r),
            None => format!("{name} at r = {r:.4} mm: diameter 2r = {:.4} mm", 2.0 * r),
        };
        series.push(Series::line(label, vec![(r, 0.0), (r, frac), (0.0, frac)]).without_markers());
    }
    // A signal region is a circle on the detector in mm: the top axis gives
    // the radius in mm beside the arcsec (linear: mm = f·tan r, and r is at
    // most minutes of arc, where tan r = r to 1e-7).
    let top = q.focal_length_mm.map(|f| TopAxis {
        label: "radius r [mm on the sensor]",
        scale: f * (1.0 / 3600.0_f64).to_radians(),
    });
    line_plot_with_top_axis(
        path,
        (title, x_label, "fraction of flux"),
        &series,
        (900, 600),
        top,
    )
}
