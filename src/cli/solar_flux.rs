//! `traxer solar-flux`: an axion emission table — computed from a standard solar
//! model, read from a CSV, or the built-in one — with its spectrum at Earth and
//! its radial profiles (`traxer::output::write_solar_flux`).

use super::args::{parse_values, OutputArgs};
use super::InputError;
use serde_json::json;
use std::path::PathBuf;
use traxer::files::{sha256_hex, OutputFolder};
use traxer::output::{write_solar_flux, Provenance, SolarFluxInfo, SOLAR_FLUX_FILES};
use traxer::source::sun::primakoff::emission_table;
use traxer::source::sun::{
    builtin_table, EmissionTable, SolarModel, BUILTIN_COUPLING, BUILTIN_DESCRIPTION,
};

/// Solar axion emission: the table, the spectrum at Earth and where it comes from.
///
/// With --model, computes the Primakoff emission (g_aγ = 1e-10 GeV⁻¹, Debye–Hückel
/// screening) of a standard solar model file in the B16 format (e.g.
/// ../shared/solar/SolarModel_B16-AGSS09met.dat) on the --radii × --energies grid;
/// with --table, reads an emission table CSV (Radius, Energy [keV], emRates);
/// with neither, takes the built-in table. Writes into --out: emission.csv (the
/// table), spectrum.csv and spectrum.png (dΦ/dE at --distance-au, with the CAST
/// 2007 parameterisation), radial_profile.csv, projected_profile.csv, profiles.png
/// and solar_flux.json (total flux, ratio to CAST 2007, radii holding 50/90/99 %).
/// The built-in table was made with:
///   traxer solar-flux --model ../shared/solar/SolarModel_B16-AGSS09met.dat --out out/solar
#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("out/solar")))]
pub struct SolarFluxArgs {
    /// A standard solar model in the B16 format to compute the Primakoff emission of.
    #[arg(value_name = "FILE", long, conflicts_with = "table")]
    pub model: Option<PathBuf>,
    /// An emission table CSV to check and describe.
    #[arg(value_name = "CSV", long)]
    pub table: Option<PathBuf>,
    /// With --model: radii (fractions of R_sun) as a,b,c or start:stop:step, or
    /// "model" for every row of the model file.
    #[arg(
        value_name = "LIST",
        long,
        default_value = "0.0025:0.6975:0.005",
        requires = "model"
    )]
    pub radii: String,
    /// With --model: energies (keV) as a,b,c or start:stop:step.
    #[arg(
        value_name = "KEV_LIST",
        long,
        default_value = "0.1:15:0.1",
        requires = "model"
    )]
    pub energies: String,
    /// Sun–Earth distance for the spectrum, astronomical units.
    #[arg(value_name = "AU", long, default_value_t = 1.0)]
    pub distance_au: f64,
    #[command(flatten)]
    pub output: OutputArgs,
}

pub fn run(a: SolarFluxArgs) -> anyhow::Result<()> {
    if !(a.distance_au.is_finite() && a.distance_au > 0.0) {
        return Err(InputError(format!(
            "--distance-au {}: expected a positive distance",
            a.distance_au
        ))
        .into());
    }
    let folder = OutputFolder::prepare(&a.output.out, &SOLAR_FLUX_FILES)?;
    let version = env!("CARGO_PKG_VERSION");
    let (table, description, coupling, origin, csv) = if let Some(path) = &a.model {
        let bytes = std::fs::read(path)
            .map_err(|e| InputError(format!("{}: cannot read: {e}", path.display())))?;
        let model = SolarModel::parse(&String::from_utf8_lossy(&bytes), path)?;
        let radii = if a.radii == "model" {
            model.shells.iter().map(|s| s.radius).collect()
        } else {
            parse_values("radii", &a.radii)?
        };
        let energies = parse_values("energies", &a.energies)?;
        EmissionTable::check_grid(&radii, &energies)
            .map_err(|e| InputError(format!("--radii/--energies: {e}")))?;
        let table = emission_table(&model, &radii, &energies);
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let sha = sha256_hex(&bytes);
        let comment = format!(
            "Primakoff axion emission (rate per axion phase-space mode w = 2 Γ_γ→a f_B, keV) for g_aγ = 1e-10 GeV⁻¹,\n\
             Γ_γ→a from Raffelt, Phys. Rev. D 33 (1986) 897 with Debye–Hückel screening (full ionisation),\n\
             computed by traxer {version} (`traxer solar-flux --model {name} --radii {} --energies {}`)\n\
             from the solar model {name} (SHA-256 {sha}):\n\
             B16-AGSS09met, N. Vinyoles et al., ApJ 835 (2017) 202, arXiv:1611.09867.\n\
             Axions per volume, time and energy: w E²/(2π²) in natural units (see src/source/sun/primakoff.rs).",
            a.radii, a.energies
        );
        let csv = table.to_csv(&comment);
        let origin = json!({"model": path.display().to_string(), "model_sha256": sha, "radii": a.radii, "energies_keV": a.energies});
        (
            table,
            format!("Primakoff emission of {name}"),
            BUILTIN_COUPLING.to_string(),
            origin,
            csv,
        )
    } else if let Some(path) = &a.table {
        let text = std::fs::read_to_string(path)
            .map_err(|e| InputError(format!("{}: cannot read: {e}", path.display())))?;
        let table = EmissionTable::parse_csv(&text, path)?;
        let origin = json!({"table": path.display().to_string(), "table_sha256": sha256_hex(text.as_bytes())});
        (
            table,
            path.display().to_string(),
            "the table's coupling".to_string(),
            origin,
            text,
        )
    } else {
        let table = builtin_table().clone();
        let csv = table.to_csv(&format!(
            "The built-in table of traxer {version}: {BUILTIN_DESCRIPTION}"
        ));
        (
            table,
            BUILTIN_DESCRIPTION.to_string(),
            BUILTIN_COUPLING.to_string(),
            json!({"builtin": true}),
            csv,
        )
    };
    let info = SolarFluxInfo {
        description: &description,
        coupling: &coupling,
        distance_au: a.distance_au,
        table_csv: &csv,
        origin,
    };
    write_solar_flux(folder.path(), &table, &info, &Provenance::new(None))?;
    folder.commit()?;
    let d_cm = a.distance_au * traxer::source::sun::AU_CM;
    let total: f64 =
        table.luminosity(0.0, f64::INFINITY) / (4.0 * std::f64::consts::PI * d_cm * d_cm);
    say!(
        "{description}: {total:.4e} axions cm⁻² s⁻¹ at {} AU ({coupling})",
        a.distance_au
    );
    say!("wrote {}", a.output.out.display());
    Ok(())
}
