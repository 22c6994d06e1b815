//! The files of `traxer solar-flux`: an emission table's spectrum at Earth, its
//! radial profile in 3D and projected on the solar disk, as CSV and plots, and a
//! JSON summary — what a user checks a table with before tracing it.

use super::{line_plot, write_csv, write_json, Provenance, Series};
use crate::source::sun::{EmissionSampler, EmissionTable, AU_CM, R_SUN_CM};
use serde_json::json;
use std::path::Path;

/// Every file `traxer solar-flux` writes.
pub const SOLAR_FLUX_FILES: [&str; 7] = [
    "emission.csv",
    "spectrum.csv",
    "spectrum.png",
    "radial_profile.csv",
    "projected_profile.csv",
    "profiles.png",
    "solar_flux.json",
];

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

/// Writes [`SOLAR_FLUX_FILES`] into `dir`.
pub fn write_solar_flux(
    dir: &Path,
    table: &EmissionTable,
    info: &SolarFluxInfo,
    provenance: &Provenance,
) -> std::io::Result<()> {
    let d_cm = info.distance_au * AU_CM;
    let arcmin_per_rsun = (R_SUN_CM / d_cm).atan().to_degrees() * 60.0;
    crate::files::atomic_write(&dir.join(SOLAR_FLUX_FILES[0]), info.table_csv.as_bytes())?;
    write_spectrum(dir, table, info)?;
    let at_1au = 1.0 / (info.distance_au * info.distance_au);
    let (e_lo, e_hi) = (
        table.energy_edges()[0],
        *table.energy_edges().last().unwrap(),
    );
    let sampler = EmissionSampler::new(table, e_lo, e_hi)
        .ok_or_else(|| std::io::Error::other("the table emits nothing"))?;
    let re = table.radius_edges();
    write_csv(
        &dir.join(SOLAR_FLUX_FILES[3]),
        &[
            "radius_from",
            "radius_to",
            "fraction_of_emission",
            "enclosed_fraction",
        ],
        (0..table.radii.len()).map(|i| {
            let f = sampler.enclosed_3d(re[i + 1]) - sampler.enclosed_3d(re[i]);
            vec![
                re[i].to_string(),
                re[i + 1].to_string(),
                format!("{f:.6e}"),
                format!("{:.6}", sampler.enclosed_3d(re[i + 1])),
            ]
        }),
    )?;
    let rhos: Vec<f64> = (0..=400).map(|k| k as f64 / 400.0).collect();
    write_csv(
        &dir.join(SOLAR_FLUX_FILES[4]),
        &[
            "projected_radius",
            "arcmin",
            "enclosed_fraction",
            "surface_brightness_per_rsun2",
        ],
        rhos.windows(2).map(|w| {
            let (a, b) = (w[0], w[1]);
            let ring = sampler.enclosed_projected(b) - sampler.enclosed_projected(a);
            let brightness = ring / (std::f64::consts::PI * (b * b - a * a));
            vec![
                b.to_string(),
                format!("{:.4}", b * arcmin_per_rsun),
                format!("{:.6}", sampler.enclosed_projected(b)),
                format!("{brightness:.6e}"),
            ]
        }),
    )?;
    line_plot(
        &dir.join(SOLAR_FLUX_FILES[5]),
        "Where the axions come from",
        "radius [R_sun]",
        "enclosed fraction of the emission",
        &[
            Series::line(
                "within radius r (3D)",
                rhos.iter().map(|&r| (r, sampler.enclosed_3d(r))).collect(),
            ),
            Series::line(
                "within projected radius on the disk",
                rhos.iter()
                    .map(|&r| (r, sampler.enclosed_projected(r)))
                    .collect(),
            ),
        ],
        (900, 560),
    )?;
    let total = sampler.luminosity / (4.0 * std::f64::consts::PI * d_cm * d_cm);
    let radius_of = |f: &dyn Fn(f64) -> f64, q: f64| {
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
    let quantiles = |f: &dyn Fn(f64) -> f64| {
        json!({
            "50%": radius_of(f, 0.5), "90%": radius_of(f, 0.9), "99%": radius_of(f, 0.99),
        })
    };
    let cast_total: f64 = (0..20000)
        .map(|k| cast2007_flux(0.001 * (k as f64 + 0.5)) * 0.001)
        .sum::<f64>()
        * at_1au;
    let doc = json!({
        "provenance": provenance,
        "emission": info.description,
        "coupling": info.coupling,
        "origin": info.origin,
        "distance_au": info.distance_au,
        "energy_range_keV": [e_lo, e_hi],
        "luminosity_axions_per_s": sampler.luminosity,
        "flux_per_cm2_s": total,
        "cast2007_flux_per_cm2_s_0_to_20keV": cast_total,
        "ratio_to_cast2007": total / cast_total,
        "radius_enclosing_rsun": quantiles(&|r| sampler.enclosed_3d(r)),
        "projected_radius_enclosing_rsun": quantiles(&|r| sampler.enclosed_projected(r)),
        "arcmin_per_rsun": arcmin_per_rsun,
        "files": SOLAR_FLUX_FILES,
    });
    write_json(&dir.join(SOLAR_FLUX_FILES[6]), &doc)
}

/// spectrum.csv and spectrum.png: dΦ/dE at the distance, with CAST 2007.
fn write_spectrum(dir: &Path, table: &EmissionTable, info: &SolarFluxInfo) -> std::io::Result<()> {
    let d_cm = info.distance_au * AU_CM;
    let spectrum = table.spectrum_at(d_cm);
    let at_1au = 1.0 / (info.distance_au * info.distance_au);
    write_csv(
        &dir.join(SOLAR_FLUX_FILES[1]),
        &[
            "energy_keV",
            "flux_per_cm2_s_keV",
            "cast2007_at_this_distance_per_cm2_s_keV",
        ],
        table.energies.iter().zip(&spectrum).map(|(e, f)| {
            vec![
                e.to_string(),
                format!("{f:.6e}"),
                format!("{:.6e}", cast2007_flux(*e) * at_1au),
            ]
        }),
    )?;
    line_plot(
        &dir.join(SOLAR_FLUX_FILES[2]),
        &format!("Axion flux at {} AU", info.distance_au),
        "energy [keV]",
        "dΦ/dE [cm⁻² s⁻¹ keV⁻¹]",
        &[
            Series::line(
                info.coupling,
                table
                    .energies
                    .iter()
                    .copied()
                    .zip(spectrum.iter().copied())
                    .collect(),
            ),
            Series::line(
                "CAST 2007 parameterisation (g_aγ = 1e-10 GeV⁻¹)",
                table
                    .energies
                    .iter()
                    .map(|&e| (e, cast2007_flux(e) * at_1au))
                    .collect(),
            ),
        ],
        (900, 560),
    )?;
    Ok(())
}
