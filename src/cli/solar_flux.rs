//! `traxer solar-flux`: an axion emission table — computed from a standard solar
//! model (Primakoff, and ABC with the Opacity Project tables), read from a CSV,
//! or a built-in one — with its spectrum at Earth per process and its radial
//! profiles (`traxer::output::write_solar_flux`).

use super::args::{parse_values, OutputArgs};
use super::InputError;
use serde_json::json;
use std::path::{Path, PathBuf};
use traxer::constants::AU_CM;
use traxer::files::sha256_hex;
use traxer::output::{write_solar_flux, Provenance, SolarFluxInfo, SOLAR_FLUX_FILES};
use traxer::source::sun::builtin::{self, model_emission, EmissionPart};
use traxer::source::sun::opacity_project::OpacityTables;
use traxer::source::sun::{EmissionTable, SolarModel};

/// Solar axion emission: the table, the spectrum at Earth per process and where
/// the axions come from.
///
/// --emission chooses primakoff (g_aγ), abc (the axion–electron processes: atomic,
/// electron–ion and electron–electron bremsstrahlung, Compton; g_ae) or
/// primakoff+abc. With --model, computes it from a standard solar model file in
/// the B16 format (e.g. ../shared/solar/SolarModel_B16-AGSS09met.dat) on the
/// --radii × --energies grid (ABC also needs --opacities, the Opacity Project
/// tables, e.g. ../shared/solar/op); with --table, reads an emission table CSV
/// (Radius, Energy [keV], emRates); with neither, takes the built-in tables.
/// Fluxes scale as the couplings squared (--g-agamma, --g-ae). Writes into --out:
/// emission.csv (the table), spectrum.csv and spectrum.png (dΦ/dE at
/// --distance-au, total and per process), radial_profile.csv,
/// projected_profile.csv, profiles.png and solar_flux.json (fluxes, radii holding
/// 50/80/90/99 % of the emission in 3D and on the sky); with --model and ABC
/// also abc_process_shares.csv (each ABC process's share of every cell, which
/// a trace splits ABC images by). The built-in tables are made by
/// scripts/solar_table.sh.
#[derive(clap::Args)]
#[command(mut_arg("out", |a| a.default_value("out/solar").help("Output folder, created if missing")))]
pub struct SolarFluxArgs {
    /// primakoff, abc or primakoff+abc [default: primakoff; with --table, the
    /// table is the emission and --emission is refused].
    #[arg(value_name = "NAME", long)]
    pub emission: Option<String>,
    /// A standard solar model in the B16 format to compute the emission of.
    #[arg(value_name = "FILE", long, conflicts_with = "table")]
    pub model: Option<PathBuf>,
    /// The built-in tables' solar model: b16_agss09met (default) or b16_gs98.
    #[arg(value_name = "NAME", long, conflicts_with_all = ["model", "table"])]
    pub solar_model: Option<String>,
    /// With --model and ABC: the Opacity Project folder (opacity/, ionisation/).
    #[arg(value_name = "DIR", long, requires = "model")]
    pub opacities: Option<PathBuf>,
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
    /// With --model: energies (keV, the centres of the energy cells) as a,b,c or
    /// start:stop:step [default: 0.1:15:0.1 for primakoff, 0.1125:14.9875:0.025
    /// with abc].
    #[arg(value_name = "KEV_LIST", long, requires = "model")]
    pub energies: Option<String>,
    /// The axion–photon coupling g_aγ in GeV⁻¹ (Primakoff) [default: 1e-10];
    /// refused when the emission has no Primakoff part or comes from --table.
    #[arg(value_name = "G", long)]
    pub g_agamma: Option<f64>,
    /// The axion–electron coupling g_ae (ABC) [default: 1e-13]; refused when the
    /// emission has no ABC part or comes from --table.
    #[arg(value_name = "G", long)]
    pub g_ae: Option<f64>,
    /// Sun–Earth distance for the spectrum, astronomical units.
    #[arg(value_name = "AU", long, default_value_t = 1.0)]
    pub distance_au: f64,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// An emission with its parts and what it is.
struct Emission {
    table: EmissionTable,
    parts: Vec<EmissionPart>,
    description: String,
    coupling: String,
    origin: serde_json::Value,
    csv: String,
    /// ABC's process shares per cell ([`SHARES_FILE`]), for an ABC emission
    /// computed from a solar model.
    shares_csv: Option<String>,
}

/// The file of ABC's process shares per cell that `--model` with ABC writes
/// (`scripts/solar_table.sh` ships it as the built-in table's).
const SHARES_FILE: &str = "abc_process_shares.csv";

pub fn run(a: SolarFluxArgs) -> anyhow::Result<()> {
    traxer::source::sun::check_distance_au("--distance-au", a.distance_au).map_err(InputError)?;
    let (g_agamma, g_ae) = couplings(&a)?;
    let out = a.output.folder("solar");
    let mut files = SOLAR_FLUX_FILES.all().to_vec();
    if a.model.is_some() && g_ae.is_some() {
        files.push(SHARES_FILE);
    }
    let folder = traxer::run::results_folder(&out, &files)?;
    let e = emission(&a, g_agamma, g_ae)?;
    let info = SolarFluxInfo {
        description: &e.description,
        coupling: &e.coupling,
        distance_au: a.distance_au,
        table_csv: &e.csv,
        origin: e.origin.clone(),
    };
    let provenance = Provenance::of_table(&super::invocation());
    traxer::run::write_results_folder(folder, |dir| {
        if let Some(csv) = &e.shares_csv {
            traxer::files::atomic_write(&dir.join(SHARES_FILE), csv.as_bytes())?;
        }
        write_solar_flux(dir, &e.table, &e.parts, &info, &provenance)
    })?;
    print_totals(&e, a.distance_au);
    say!("wrote {}", out.display());
    Ok(())
}

/// The couplings (g_aγ, g_ae) of the processes the emission has, checked
/// before anything is read or written: a table carries its own coupling, so
/// --emission, --g-agamma and --g-ae are refused with --table (a flux printed
/// for a coupling the table was not computed for would be wrong); a coupling
/// for a process the emission lacks is refused, never ignored.
fn couplings(a: &SolarFluxArgs) -> anyhow::Result<(Option<f64>, Option<f64>)> {
    if let Some(table) = &a.table {
        let given: Vec<&str> = [
            ("--emission", a.emission.is_some()),
            ("--g-agamma", a.g_agamma.is_some()),
            ("--g-ae", a.g_ae.is_some()),
        ]
        .into_iter()
        .filter_map(|(n, g)| g.then_some(n))
        .collect();
        if !given.is_empty() {
            return Err(InputError(format!(
                "--table {}: {} cannot be used with a table: the table is the emission, computed for its own coupling (its fluxes are printed as they are); scale them yourself by (g/g_table)², or give --model or a built-in --emission instead",
                table.display(),
                given.join(" and ")
            ))
            .into());
        }
        return Ok((None, None));
    }
    let names = builtin::CouplingNames {
        assign: " ",
        emission: "--emission",
        g_agamma: "--g-agamma",
        g_ae: "--g-ae",
    };
    let emission = a.emission.as_deref().unwrap_or("primakoff");
    Ok(builtin::checked_couplings(emission, a.g_agamma, a.g_ae, &names).map_err(InputError)?)
}

/// The total flux and each process's on stdout.
fn print_totals(e: &Emission, distance_au: f64) {
    let d_cm = distance_au * AU_CM;
    let area = 4.0 * std::f64::consts::PI * d_cm * d_cm;
    let total = e.table.luminosity(0.0, f64::INFINITY) / area;
    say!(
        "{}: {total:.4e} axions cm⁻² s⁻¹ at {} AU ({})",
        e.description,
        distance_au,
        e.coupling
    );
    let edges = e.table.energy_edges();
    for p in &e.parts {
        let flux = p.flux_1au(&edges) / (distance_au * distance_au);
        say!("  {:<18} {flux:.4e} cm⁻² s⁻¹", p.name);
    }
}

/// The emission asked for: from a solar model, an emission table, or built in.
fn emission(
    a: &SolarFluxArgs,
    g_agamma: Option<f64>,
    g_ae: Option<f64>,
) -> anyhow::Result<Emission> {
    Ok(if let Some(path) = &a.model {
        from_model(a, path, g_agamma, g_ae)?
    } else if let Some(path) = &a.table {
        let text = std::fs::read_to_string(path)
            .map_err(|e| InputError(format!("{}: cannot read: {e}", path.display())))?;
        let table = EmissionTable::parse_csv(&text, path)?;
        let luminosity = table.luminosity(0.0, f64::INFINITY);
        if !luminosity.is_finite() {
            return Err(InputError(format!(
                "{}: the rates, summed over the Sun's volume, exceed the largest number a double holds: `emRates` are per axion phase-space mode (keV), of order 1e-30 to 1e10 for real emissions: check their unit",
                path.display()
            ))
            .into());
        }
        Emission {
            table,
            parts: Vec::new(),
            description: path.display().to_string(),
            coupling: "the table's coupling".into(),
            origin: json!({"table": path.display().to_string(), "table_sha256": sha256_hex(text.as_bytes())}),
            csv: text,
            shares_csv: None,
        }
    } else {
        let model = match &a.solar_model {
            None => builtin::BuiltinModel::B16Agss09met,
            Some(m) => builtin::BuiltinModel::parse(m)
                .map_err(|e| InputError(format!("--solar-model {e}")))?,
        };
        let b = builtin::builtin_emission_of(model, g_agamma, g_ae)?;
        let csv = b.table.to_csv(&format!(
            "The built-in emission of traxer {}: {} ({})",
            env!("CARGO_PKG_VERSION"),
            b.description,
            b.coupling
        ));
        Emission {
            table: b.table,
            parts: b.parts,
            description: b.description,
            coupling: b.coupling,
            origin: json!({"builtin": a.emission.as_deref().unwrap_or("primakoff"), "solar_model": model.name()}),
            csv,
            shares_csv: None,
        }
    })
}

/// The emission computed from a solar model file (and the OP tables for ABC).
fn from_model(
    a: &SolarFluxArgs,
    path: &Path,
    g_agamma: Option<f64>,
    g_ae: Option<f64>,
) -> anyhow::Result<Emission> {
    let bytes = std::fs::read(path)
        .map_err(|e| InputError(format!("{}: cannot read: {e}", path.display())))?;
    let model = SolarModel::parse(&String::from_utf8_lossy(&bytes), path)?;
    let radii = if a.radii == "model" {
        model.shells.iter().map(|s| s.radius).collect()
    } else {
        parse_values("radii", &a.radii)?
    };
    let energies_text = a.energies.clone().unwrap_or_else(|| {
        if g_ae.is_some() {
            "0.1125:14.9875:0.025".into()
        } else {
            "0.1:15:0.1".into()
        }
    });
    let energies = parse_values("energies", &energies_text)?;
    EmissionTable::check_grid(&radii, &energies)
        .map_err(|e| InputError(format!("--radii/--energies: {e}")))?;
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let op = match (&a.opacities, g_ae) {
        (Some(dir), Some(_)) => Some(OpacityTables::read(dir)?),
        (None, Some(_)) => return Err(InputError("--emission with abc and --model need --opacities DIR (the Opacity Project tables, e.g. ../shared/solar/op)".into()).into()),
        _ => None,
    };
    let e = model_emission(
        &model,
        &name,
        op.as_ref(),
        &radii,
        &energies,
        g_agamma,
        g_ae,
    )?;
    let sha = sha256_hex(&bytes);
    let mut origin = json!({"model": path.display().to_string(), "model_sha256": sha, "radii": a.radii, "energies_keV": energies_text});
    let mut how = Vec::new();
    if let Some(g) = g_agamma {
        how.push(format!("Primakoff (w = 2 Γ_γ→a f_B, Raffelt, Phys. Rev. D 33 (1986) 897, Debye–Hückel screening, full ionisation; src/source/sun/primakoff.rs) for g_aγ = {g:e} GeV⁻¹"));
    }
    if let (Some(g), Some(dir)) = (g_ae, &a.opacities) {
        how.push(format!("ABC (atomic from the Opacity Project tables in {}, electron–ion and electron–electron bremsstrahlung, Compton; Redondo, JCAP 12 (2013) 008; src/source/sun/abc.rs) for g_ae = {g:e}, each rate the average of w E² over its energy cell divided by the cell centre's E²", dir.display()));
        origin["opacities"] = json!(dir.display().to_string());
    }
    // Cite the model the file is, not always the default one.
    let cited = SolarModel::citation(&name);
    let header = format!(
        "Axion emission: rate per axion phase-space mode w (keV); {}.\n\
         Computed by traxer {} (`traxer solar-flux --emission {} --model {name} --radii {} --energies {energies_text}`)\n\
         from the solar model {name} (SHA-256 {sha}):\n\
         {cited}.\n\
         Axions per volume, time and energy: w E²/(2π²) in natural units (see src/source/sun/).",
        how.join("; "),
        env!("CARGO_PKG_VERSION"),
        a.emission.as_deref().unwrap_or("primakoff"),
        a.radii
    );
    let shares_csv = e
        .couplings
        .iter()
        .find_map(|c| c.shares.as_ref())
        .map(|s| {
            traxer::source::sun::shares::to_csv(
                s,
                &format!(
                    "Share of each ABC process (atomic, electron-ion, electron-electron, Compton) in each cell\n\
                     of the ABC table computed with it (`traxer solar-flux --emission {} --model {name} --radii {} --energies {energies_text}`,\n\
                     emission.csv), one row per cell in the table's order (radius-major), four decimals.",
                    a.emission.as_deref().unwrap_or("primakoff"),
                    a.radii
                ),
            )
        });
    Ok(Emission {
        shares_csv,
        csv: e.table.to_csv(&header),
        table: e.table,
        parts: e.parts,
        description: e.description,
        coupling: e.coupling,
        origin,
    })
}
