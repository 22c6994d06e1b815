//! The files of `traxer solar-flux`: an emission table's spectrum at Earth, its
//! radial profile in 3D and projected on the solar disk, as CSV and plots, and a
//! JSON summary — what a user checks a table with before tracing it.

use super::{line_plot, write_csv, write_json, Provenance, Series};
use crate::constants::{AU_CM, R_SUN_CM};
use crate::source::sun::builtin::EmissionPart;
use crate::source::sun::{EmissionSampler, EmissionTable};
use serde_json::json;
use std::path::Path;

/// The files `traxer solar-flux` writes, by what they hold.
#[derive(Clone, Copy, Debug)]
pub struct SolarFluxFiles {
    /// The emission table itself.
    pub emission_csv: &'static str,
    /// The spectrum at Earth (and each part's), as CSV and plot.
    pub spectrum_csv: &'static str,
    pub spectrum_png: &'static str,
    /// The radial profile in 3D and projected on the disk, and their plot.
    pub radial_profile_csv: &'static str,
    pub projected_profile_csv: &'static str,
    pub profiles_png: &'static str,
    /// The summary.
    pub summary_json: &'static str,
}

/// Every file `traxer solar-flux` writes.
pub const SOLAR_FLUX_FILES: SolarFluxFiles = SolarFluxFiles {
    emission_csv: "emission.csv",
    spectrum_csv: "spectrum.csv",
    spectrum_png: "spectrum.png",
    radial_profile_csv: "radial_profile.csv",
    projected_profile_csv: "projected_profile.csv",
    profiles_png: "profiles.png",
    summary_json: "solar_flux.json",
};

impl SolarFluxFiles {
    /// Every name, in the order above.
    pub fn all(&self) -> [&'static str; 7] {
        [
            self.emission_csv,
            self.spectrum_csv,
            self.spectrum_png,
            self.radial_profile_csv,
            self.projected_profile_csv,
            self.profiles_png,
            self.summary_json,
        ]
    }
}

/// The CAST 2007 parameterisation of the Primakoff flux at 1 AU for g_aγ =
/// 1e-10 GeV⁻¹ (Andriamonje et al., JCAP 04 (2007) 010), cm⁻² s⁻¹ keV⁻¹.
pub fn cast2007_flux(e_kev: f64) -> f64 {
    6.02e10 * e_kev.powf(2.481) * (-e_kev / 1.205).exp()
}

/// What the table is and where it came from, for the summary.
pub struct SolarFluxInfo<'a> {
    pub description: &'a str,
    pub coupling: &'a str,
    pub distance_au: f64,
    /// The table's CSV text as written to emission.csv.
    pub table_csv: &'a str,
    /// Extra keys for the summary (the model file and its hash, the grid).
    pub origin: serde_json::Value,
}

/// The enclosed fractions asked for in the summary.
const QUANTILES: [(&str, f64); 4] = [("50%", 0.5), ("80%", 0.8), ("90%", 0.9), ("99%", 0.99)];

/// Writes [`SOLAR_FLUX_FILES`] into `dir`: the table `table`, its spectrum and
/// profiles, and those of its `parts` (processes; spectra on the table's
/// energies at 1 AU, profiles for the parts that have a table).
pub fn write_solar_flux(
    dir: &Path,
    table: &EmissionTable,
    parts: &[EmissionPart],
    info: &SolarFluxInfo,
    provenance: &Provenance,
) -> std::io::Result<()> {
    let d_cm = info.distance_au * AU_CM;
    let arcmin_per_rsun = (R_SUN_CM / d_cm).atan().to_degrees() * 60.0;
    crate::files::atomic_write(
        &dir.join(SOLAR_FLUX_FILES.emission_csv),
        info.table_csv.as_bytes(),
    )?;
    write_spectrum(dir, table, parts, info)?;
    let at_1au = 1.0 / (info.distance_au * info.distance_au);
    let (e_lo, e_hi) = (
        table.energy_edges()[0],
        *table.energy_edges().last().unwrap(),
    );
    let sampler_of = |t: &EmissionTable| {
        EmissionSampler::new(t, e_lo, e_hi)
            .ok_or_else(|| std::io::Error::other("the table emits nothing"))
    };
    // The total first, then each part with a table of its own.
    let mut profiled = vec![("total".to_string(), sampler_of(table)?)];
    for p in parts.iter().filter(|p| p.table.is_some()) {
        profiled.push((p.name.clone(), sampler_of(p.table.as_ref().unwrap())?));
    }
    if profiled.len() == 2 {
        profiled.pop(); // one part: the same as the total
    }
    write_profiles(dir, table, &profiled, arcmin_per_rsun)?;
    let area = 4.0 * std::f64::consts::PI * d_cm * d_cm;
    let total = profiled[0].1.luminosity / area;
    let cast_total: f64 = (0..20000)
        .map(|k| cast2007_flux(0.001 * (k as f64 + 0.5)) * 0.001)
        .sum::<f64>()
        * at_1au;
    let edges = table.energy_edges();
    let part_docs: serde_json::Map<String, serde_json::Value> = parts
        .iter()
        .map(|p| {
            let flux = p.flux_1au(&edges) * at_1au;
            let mut doc = json!({"flux_per_cm2_s": flux, "fraction_of_total": flux / total});
            if let Some((_, s)) = profiled.iter().find(|(n, _)| *n == p.name) {
                doc["radius_enclosing_rsun"] = enclosing_radii(&|r| s.enclosed_3d(r));
                doc["projected_radius_enclosing_rsun"] =
                    enclosing_radii(&|r| s.enclosed_projected(r));
            }
            (p.name.clone(), doc)
        })
        .collect();
    let main = &profiled[0].1;
    let doc = json!({
        "provenance": provenance,
        "emission": info.description,
        "coupling": info.coupling,
        "origin": info.origin,
        "distance_au": info.distance_au,
        "energy_range_keV": [e_lo, e_hi],
        "luminosity_axions_per_s": main.luminosity,
        "flux_per_cm2_s": total,
        "parts": part_docs,
        "cast2007_flux_per_cm2_s_0_to_20keV": cast_total,
        "ratio_to_cast2007": total / cast_total,
        "radius_enclosing_rsun": enclosing_radii(&|r| main.enclosed_3d(r)),
        "projected_radius_enclosing_rsun": enclosing_radii(&|r| main.enclosed_projected(r)),
        "arcmin_per_rsun": arcmin_per_rsun,
        "files": SOLAR_FLUX_FILES.all(),
    });
    write_json(&dir.join(SOLAR_FLUX_FILES.summary_json), &doc)
}

/// A sampler per profiled emission (the total first), by name.
type Profiled = [(String, EmissionSampler)];

/// radial_profile.csv, projected_profile.csv and profiles.png.
fn write_profiles(
    dir: &Path,
    table: &EmissionTable,
    profiled: &Profiled,
    arcmin_per_rsun: f64,
) -> std::io::Result<()> {
    let re = table.radius_edges();
    let mut header = vec!["radius_from".to_string(), "radius_to".to_string()];
    for (name, _) in profiled {
        header.push(format!("fraction_of_emission_{name}"));
        header.push(format!("enclosed_fraction_{name}"));
    }
    write_csv(
        &dir.join(SOLAR_FLUX_FILES.radial_profile_csv),
        &header.iter().map(String::as_str).collect::<Vec<_>>(),
        (0..table.radii.len()).map(|i| {
            let mut row = vec![re[i].to_string(), re[i + 1].to_string()];
            for (_, s) in profiled {
                let f = s.enclosed_3d(re[i + 1]) - s.enclosed_3d(re[i]);
                row.push(format!("{f:.6e}"));
                row.push(format!("{:.6}", s.enclosed_3d(re[i + 1])));
            }
            row
        }),
    )?;
    let rhos: Vec<f64> = (0..=400).map(|k| k as f64 / 400.0).collect();
    let mut header = vec!["projected_radius".to_string(), "arcmin".to_string()];
    for (name, _) in profiled {
        header.push(format!("enclosed_fraction_{name}"));
        header.push(format!("surface_brightness_per_rsun2_{name}"));
    }
    write_csv(
        &dir.join(SOLAR_FLUX_FILES.projected_profile_csv),
        &header.iter().map(String::as_str).collect::<Vec<_>>(),
        rhos.windows(2).map(|w| {
            let (a, b) = (w[0], w[1]);
            let mut row = vec![b.to_string(), format!("{:.4}", b * arcmin_per_rsun)];
            for (_, s) in profiled {
                let ring = s.enclosed_projected(b) - s.enclosed_projected(a);
                let brightness = ring / (std::f64::consts::PI * (b * b - a * a));
                row.push(format!("{:.6}", s.enclosed_projected(b)));
                row.push(format!("{brightness:.6e}"));
            }
            row
        }),
    )?;
    // The x axis ends where every curve has reached 99.9 % (with a margin):
    // the emission is concentrated in the core.
    let end = profiled
        .iter()
        .flat_map(|(_, s)| {
            [
                rhos.iter().find(|&&r| s.enclosed_3d(r) >= 0.999),
                rhos.iter().find(|&&r| s.enclosed_projected(r) >= 0.999),
            ]
        })
        .map(|r| r.copied().unwrap_or(1.0))
        .fold(0.0, f64::max);
    let shown: Vec<f64> = rhos
        .iter()
        .copied()
        .filter(|&r| r <= (1.2 * end).min(1.0))
        .collect();
    let mut curves = Vec::new();
    for (name, s) in profiled {
        let name = process_words(name);
        curves.push(Series::line(
            format!("{name}: within radius r (3D)"),
            shown.iter().map(|&r| (r, s.enclosed_3d(r))).collect(),
        ));
        curves.push(Series::line(
            format!("{name}: within projected radius on the disk"),
            shown
                .iter()
                .map(|&r| (r, s.enclosed_projected(r)))
                .collect(),
        ));
    }
    line_plot(
        &dir.join(SOLAR_FLUX_FILES.profiles_png),
        "Where the axions come from",
        "radius [R_sun]",
        "enclosed fraction of the emission",
        &curves,
        (900, 560),
    )?;
    Ok(())
}

/// The radii (fractions of R_sun) enclosing each of [`QUANTILES`] of an
/// increasing enclosed-fraction function, by bisection.
fn enclosing_radii(f: &dyn Fn(f64) -> f64) -> serde_json::Value {
    let radius_of = |q: f64| {
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if f(mid) < q {
                lo = mid
            } else {
                hi = mid
            }
        }
        hi
    };
    serde_json::Value::Object(
        QUANTILES
            .iter()
            .map(|(k, q)| (k.to_string(), json!(radius_of(*q))))
            .collect(),
    )
}

/// spectrum.csv and spectrum.png: dΦ/dE at the distance, per part, with CAST 2007.
fn write_spectrum(
    dir: &Path,
    table: &EmissionTable,
    parts: &[EmissionPart],
    info: &SolarFluxInfo,
) -> std::io::Result<()> {
    let d_cm = info.distance_au * AU_CM;
    let spectrum = table.spectrum_at(d_cm);
    let at_1au = 1.0 / (info.distance_au * info.distance_au);
    let mut header = vec!["energy_keV".to_string(), "flux_per_cm2_s_keV".to_string()];
    for p in parts {
        header.push(format!("flux_{}_per_cm2_s_keV", p.name));
    }
    header.push("cast2007_at_this_distance_per_cm2_s_keV".into());
    write_csv(
        &dir.join(SOLAR_FLUX_FILES.spectrum_csv),
        &header.iter().map(String::as_str).collect::<Vec<_>>(),
        table.energies.iter().enumerate().map(|(j, e)| {
            let mut row = vec![e.to_string(), format!("{:.6e}", spectrum[j])];
            for p in parts {
                row.push(format!("{:.6e}", p.spectrum_1au[j] * at_1au));
            }
            row.push(format!("{:.6e}", cast2007_flux(*e) * at_1au));
            row
        }),
    )?;
    let curve = |values: &[f64], scale: f64| -> Vec<(f64, f64)> {
        table
            .energies
            .iter()
            .zip(values)
            .map(|(&e, &f)| (e, f * scale))
            .collect()
    };
    // A part equal to the total (within 0.1 % at every energy) would hide
    // under it: the total's label names it instead.
    let same_as_total = |p: &EmissionPart| {
        p.spectrum_1au
            .iter()
            .zip(&spectrum)
            .all(|(a, t)| (a * at_1au - t).abs() <= 1e-3 * t.abs())
    };
    let equal: Vec<String> = parts
        .iter()
        .filter(|p| parts.len() > 1 && same_as_total(p))
        .map(|p| process_words(&p.name))
        .collect();
    let total_label = match equal.as_slice() {
        [] => format!("total ({})", info.coupling),
        e => format!("total = {} ({})", e.join(" = "), info.coupling),
    };
    let mut series = vec![Series::line(total_label, curve(&spectrum, 1.0))];
    if parts.len() > 1 {
        for p in parts.iter().filter(|p| !same_as_total(p)) {
            series.push(Series::line(
                process_words(&p.name),
                curve(&p.spectrum_1au, at_1au),
            ));
        }
    }
    let primakoff_only = parts.iter().all(|p| p.name == "primakoff");
    if primakoff_only {
        series.push(Series::line(
            "CAST 2007 parameterisation (g_aγ = 1e-10 GeV⁻¹)",
            table
                .energies
                .iter()
                .map(|&e| (e, cast2007_flux(e) * at_1au))
                .collect(),
        ));
    }
    line_plot(
        &dir.join(SOLAR_FLUX_FILES.spectrum_png),
        &format!("Axion flux at {} AU", info.distance_au),
        "energy [keV]",
        "dΦ/dE [cm⁻² s⁻¹ keV⁻¹]",
        &series,
        (900, 560),
    )?;
    Ok(())
}

/// An emission process's name as a physicist reads it in a legend.
fn process_words(name: &str) -> String {
    match name {
        "primakoff" => "Primakoff".into(),
        "abc" => "ABC (all axion–electron)".into(),
        "atomic" => "atomic recombination and de-excitation".into(),
        "electron_ion" => "electron–ion bremsstrahlung".into(),
        "electron_electron" => "electron–electron bremsstrahlung".into(),
        "compton" => "Compton".into(),
        other => other.into(),
    }
}
