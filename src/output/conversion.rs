//! The files of a gas detector's conversions: `NAME_conversion_depth.csv` (the
//! flux-weighted histogram of conversion depths, with the cumulative fraction),
//! its plot, `NAME_conversion_spectrum.csv` (the spectrum of the converted photons
//! per depth slice), and the numbers for `NAME.json` (mean, quantiles, converted
//! fraction, and where the median depth lies in the world).

use super::{line_plot, write_csv, Series};
use crate::sensor::conversion::ConversionTally;
use crate::sensor::{ConversionFiles, SensorSpec};
use glam::DVec3;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Writes the conversion files of sensor `spec` into `dir`; `to_world` maps the
/// sensor's local frame to the world, `scale` turns weights into the image's
/// units. Returns the JSON entry and the paths.
pub fn write_conversion(
    dir: &Path,
    spec: &SensorSpec,
    tally: &ConversionTally,
    to_world: &glam::DAffine3,
    scale: f64,
) -> std::io::Result<(Value, Vec<PathBuf>)> {
    let names = ConversionFiles::of(&spec.name);
    let hist = tally.depth_histogram();
    let total: f64 = hist.iter().sum();
    let mut cumulative = 0.0;
    let edges = tally.depth_edges_mm();
    let edge = |i: usize| edges[i];
    write_csv(
        &dir.join(&names.depth_csv),
        &[
            "depth_lo_mm",
            "depth_hi_mm",
            "flux",
            "fraction",
            "cumulative_fraction",
        ],
        hist.iter().enumerate().map(|(i, f)| {
            cumulative += f;
            let share = |v: f64| if total > 0.0 { v / total } else { 0.0 };
            vec![
                format!("{:.6}", edge(i)),
                format!("{:.6}", edge(i + 1)),
                (f * scale).to_string(),
                share(*f).to_string(),
                share(cumulative).to_string(),
            ]
        }),
    )?;
    // The histogram as steps from (0, 0), so that both axes start at zero.
    let mut density = vec![(0.0, 0.0)];
    for (i, f) in hist.iter().enumerate() {
        let share = if total > 0.0 { f / total } else { 0.0 };
        density.push((edge(i), share / tally.step_mm));
        density.push((edge(i + 1), share / tally.step_mm));
    }
    let summary = tally.summary();
    let top = density.iter().map(|p| p.1).fold(0.0, f64::max);
    let mut series = vec![Series::line("flux per mm of depth", density)];
    for (q, name) in [(0.1, "10 %"), (0.5, "median"), (0.9, "90 %")] {
        let d = summary
            .quantiles_mm
            .iter()
            .find(|(k, _)| *k == q)
            .map_or(f64::NAN, |p| p.1);
        if d.is_finite() {
            let mut s = Series::line(format!("{name} {d:.2} mm"), vec![(d, 0.0), (d, top)]);
            s.markers = false;
            series.push(s);
        }
    }
    line_plot(
        &dir.join(&names.depth_png),
        &format!(
            "{}: where X-rays convert (median {:.2} mm)",
            spec.name,
            summary.median_mm()
        ),
        "depth below the gas entrance [mm]",
        "fraction of converted flux per mm",
        &series,
        (900, 560),
    )?;
    write_spectrum(&dir.join(&names.spectrum_csv), tally, scale)?;
    // The plane of the median depth, and the point where the sensor's axis
    // (local x = y = 0) crosses it: the plane one image plane would take.
    let drift = tally.drift_mm;
    let at_depth = |d: f64| to_world.transform_point3(DVec3::new(0.0, 0.0, drift - d));
    let entrance = at_depth(0.0);
    let median = at_depth(summary.median_mm());
    let entry = json!({
        "gas": spec.gas.as_ref().map(|g| json!({
            "mixture_by_volume": g.desc.mixture,
            "pressure_mbar": g.desc.pressure_mbar,
            "temperature_k": g.desc.temperature_k,
            "drift_mm": g.desc.drift_mm,
            "density_g_cm3": g.material.density,
            "molar_mass_g_mol": g.molar_mass,
        })),
        "depths": "below the gas entrance, along the sensor's normal; flux-weighted over the photons converting over the active area",
        "entered_flux": summary.entered_flux * scale,
        "converted_flux": summary.converted_flux * scale,
        "converted_fraction": summary.converted_fraction,
        "transmitted_fraction": 1.0 - summary.converted_fraction,
        "mean_depth_mm": summary.mean_depth_mm,
        "median_depth_mm": summary.median_mm(),
        "depth_quantiles_mm": summary.quantiles_mm.iter()
            .map(|(q, d)| (format!("{q}"), json!(d)))
            .collect::<serde_json::Map<_, _>>(),
        "entrance_on_axis_world_mm": entrance.to_array(),
        "median_depth_on_axis_world_mm": median.to_array(),
        "files": {"depth_csv": names.depth_csv, "depth_png": names.depth_png, "spectrum_csv": names.spectrum_csv},
    });
    Ok((entry, names.all().iter().map(|n| dir.join(n)).collect()))
}

/// The depth-resolved spectrum as CSV, one row per (depth slice, energy bin).
fn write_spectrum(path: &Path, tally: &ConversionTally, scale: f64) -> std::io::Result<()> {
    let spectrum = tally.spectrum();
    let (depths, energies) = (
        tally.spectrum_depth_edges_mm(),
        tally.spectrum_energy_edges_kev(),
    );
    let slices = depths.len() - 1;
    let n = energies.len() - 1;
    write_csv(
        path,
        &[
            "depth_lo_mm",
            "depth_hi_mm",
            "energy_lo_keV",
            "energy_hi_keV",
            "flux",
        ],
        (0..slices * n).map(|k| {
            let (s, e) = (k / n, k % n);
            vec![
                format!("{:.6}", depths[s]),
                format!("{:.6}", depths[s + 1]),
                format!("{:.6}", energies[e]),
                format!("{:.6}", energies[e + 1]),
                (spectrum[k] * scale).to_string(),
            ]
        }),
    )
}
