//! `traxer reflectivity`: R of a coating versus grazing angle or energy, as CSV on
//! stdout and a PNG plot.

use super::args::parse_values;
use super::InputError;
use anyhow::Context;
use serde_json::json;
use std::path::PathBuf;
use traxer::files::atomic_write;
use traxer::files::check_output_file;
use traxer::output::{csv_text, line_plot, sidecar_path, write_sidecar, Provenance, Series};
use traxer::xray::coating_from_spec;
use traxer::xray::elements::OpticalConstants;

fn parse_constants(s: &str) -> Result<OpticalConstants, String> {
    OpticalConstants::parse(s)
}

/// Print the reflectivity of a mirror coating as CSV and plot it.
///
/// One of --energy and --angle is a short list (at most 8 values, one curve each)
/// and the other the plotted axis. Values are comma-separated lists or ranges
/// start:stop:step. Example:
///   traxer reflectivity --coating llnl_recipe_3 --energy 1.49,4.51,6.41 --angle 0:3:0.005
/// CSV columns: energy_keV, angle_deg, R (unpolarised), R_s, R_p. The plot gets a
/// sidecar PLOT.json with the provenance and the coating.
#[derive(clap::Args)]
pub struct ReflectivityArgs {
    /// A coating of data/coatings.toml (e.g. llnl_recipe_3, gold), or FILE or
    /// FILE:NAME for a TOML file with [materials] and [coatings] tables.
    #[arg(value_name = "NAME|FILE", long)]
    pub coating: String,
    /// Photon energies, keV.
    #[arg(value_name = "KEV_LIST", long)]
    pub energy: String,
    /// Grazing angles, degrees.
    #[arg(value_name = "DEG_LIST", long)]
    pub angle: String,
    /// PNG plot to write.
    #[arg(value_name = "PNG", long, default_value = "reflectivity.png")]
    pub plot: PathBuf,
    /// Plot log₁₀ of the reflectivity (the multilayers' Bragg peaks and the
    /// edges show over several decades); the CSV is unchanged.
    #[arg(long)]
    pub log: bool,
    /// The table of atomic scattering factors the layers take: henke, or
    /// chantler (NIST FFAST, a second opinion; data/README.md).
    #[arg(value_name = "TABLE", long, default_value = "henke", value_parser = parse_constants)]
    pub optical_constants: OpticalConstants,
    /// Also write the CSV to this file (atomically) instead of only printing it.
    #[arg(value_name = "FILE", long)]
    pub csv: Option<PathBuf>,
    #[command(flatten)]
    pub quiet: super::args::QuietArg,
}

pub fn run(a: ReflectivityArgs) -> anyhow::Result<()> {
    check_output_file(&a.plot)?;
    check_output_file(&sidecar_path(&a.plot))?;
    if let Some(csv) = &a.csv {
        check_output_file(csv)?;
    }
    let coating = coating_from_spec(&a.coating, a.optical_constants)
        .map_err(|e| InputError(e.to_string()))?;
    let energies = parse_values("energy", &a.energy)?;
    let angles = grazing_angles(&a.angle)?;
    let versus_angle = energies.len() <= 8 && (angles.len() > 8 || angles.len() >= energies.len());
    if !versus_angle && angles.len() > 8 {
        return Err(InputError(
            "give at most 8 values for --energy or for --angle (one curve each)".into(),
        )
        .into());
    }
    let (rows, mut series) = curves(&coating, &energies, &angles, versus_angle)?;
    if a.log {
        // A reflectivity below 1e-12 is shown at -12 (the plot's floor).
        for s in &mut series {
            s.points
                .iter_mut()
                .for_each(|p| p.1 = p.1.max(1e-12).log10());
        }
    }
    let csv = csv_text(&["energy_keV", "angle_deg", "R", "R_s", "R_p"], rows);
    // A closed pipe (`| head`) is not an error worth a message.
    use std::io::Write;
    match std::io::stdout().lock().write_all(csv.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => return Err(e.into()),
        _ => {}
    }
    if let Some(path) = &a.csv {
        atomic_write(path, csv.as_bytes())
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    // The default table is not named in the title: the plots stay as they were.
    let name = match a.optical_constants {
        OpticalConstants::Henke => coating.name.clone(),
        other => format!("{} ({} optical constants)", coating.name, other.name()),
    };
    let (title, x_label, y_label) = labels(&name, versus_angle, a.log);
    line_plot(&a.plot, &title, x_label, y_label, &series, (900, 600))
        .with_context(|| format!("cannot write {}", a.plot.display()))?;
    let details = json!({
        "coating": coating.name,
        "coating_argument": a.coating,
        "energy_keV": a.energy,
        "angle_deg": a.angle,
        "csv": a.csv.as_ref().map(|p| p.display().to_string()),
        "log": a.log,
        "optical_constants": a.optical_constants.name(),
    });
    write_sidecar(
        &a.plot,
        &Provenance::of_table(&super::invocation()),
        details,
    )
    .with_context(|| format!("cannot write the sidecar of {}", a.plot.display()))?;
    if !a.quiet.quiet {
        tell!("wrote {}", a.plot.display());
    }
    Ok(())
}

/// The table's rows (energy, angle, R, R_s, R_p) and one plotted curve per
/// energy (against the angle) or per angle (against the energy).
/// The --angle list, checked: beyond 90° the formulas give numbers (R > 1 at
/// 1e300°) that mean nothing.
fn grazing_angles(text: &str) -> Result<Vec<f64>, InputError> {
    let angles = parse_values("angle", text)?;
    if let Some(th) = angles.iter().find(|th| !(0.0..=90.0).contains(*th)) {
        return Err(InputError(format!(
            "--angle {}: a grazing angle is 0° to 90° (from the surface, in degrees)",
            traxer::text::number(*th)
        )));
    }
    Ok(angles)
}

/// The plot's title and axis labels.
fn labels(coating: &str, versus_angle: bool, log: bool) -> (String, &'static str, &'static str) {
    let y = if log {
        "log₁₀ reflectivity (unpolarised)"
    } else {
        "reflectivity (unpolarised)"
    };
    if versus_angle {
        (
            format!("{coating}: reflectivity vs grazing angle"),
            "grazing angle [°]",
            y,
        )
    } else {
        (
            format!("{coating}: reflectivity vs energy"),
            "energy [keV]",
            y,
        )
    }
}

fn curves(
    coating: &traxer::xray::Coating,
    energies: &[f64],
    angles: &[f64],
    versus_angle: bool,
) -> Result<(Vec<Vec<String>>, Vec<Series>), InputError> {
    let mut rows = Vec::new();
    let mut series = Vec::new();
    let (curves, axis) = if versus_angle {
        (energies, angles)
    } else {
        (angles, energies)
    };
    for &c in curves {
        let mut points = Vec::new();
        for &x in axis {
            let (e, th) = if versus_angle { (c, x) } else { (x, c) };
            let r = coating
                .reflectance(e, th.to_radians())
                .map_err(|err| InputError(err.to_string()))?;
            rows.push(
                [e, th, r.unpolarised(), r.s, r.p]
                    .map(|v| v.to_string())
                    .to_vec(),
            );
            points.push((x, r.unpolarised()));
        }
        let label = if versus_angle {
            format!("{c} keV")
        } else {
            format!("{c}°")
        };
        series.push(Series::line(label, points));
    }
    Ok((rows, series))
}
