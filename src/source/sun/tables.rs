//! The built-in emission tables of the two standard solar models traxer ships
//! derived tables of: B16-AGSS09met (the default) and B16-GS98 (the other side
//! of the solar abundance problem, for the solar-model systematic of an image).
//! Both are traxer's own computation from the models in `../shared/solar/`
//! (`scripts/solar_table.sh`, data/solar/README.md); the repository carries the
//! derived tables only.
//!
//! Data flow: [`super::builtin`] composes emissions from [`tables`]; a `sun`
//! source's `solar_model` and `traxer solar-flux --solar-model` pick the model.

use super::emission::EmissionTable;
use super::model::SolarDataError;
use std::path::Path;
use std::sync::OnceLock;

/// A standard solar model with built-in tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuiltinModel {
    B16Agss09met,
    B16Gs98,
}

impl BuiltinModel {
    pub const ALL: [BuiltinModel; 2] = [BuiltinModel::B16Agss09met, BuiltinModel::B16Gs98];

    /// Its name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            BuiltinModel::B16Agss09met => "b16_agss09met",
            BuiltinModel::B16Gs98 => "b16_gs98",
        }
    }

    /// The model of a name, or what the names are.
    pub fn parse(name: &str) -> Result<BuiltinModel, String> {
        BuiltinModel::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                format!("\"{name}\": expected \"b16_agss09met\" (the default) or \"b16_gs98\"")
            })
    }

    /// How summaries name it.
    pub fn title(self) -> &'static str {
        match self {
            BuiltinModel::B16Agss09met => "B16-AGSS09met",
            BuiltinModel::B16Gs98 => "B16-GS98",
        }
    }
}

/// One model's built-in tables.
pub struct ModelTables {
    /// Primakoff, g_aγ = 1e-10 GeV⁻¹.
    pub primakoff: EmissionTable,
    /// ABC, g_ae = 1e-13.
    pub abc: EmissionTable,
    /// ABC's spectrum at 1 AU per process on `abc`'s energies.
    pub abc_spectra: [Vec<f64>; 4],
    pub primakoff_description: String,
    pub abc_description: String,
}

/// The files of each model, relative to the repository (embedded at build time).
macro_rules! solar_file {
    ($name:literal) => {
        (
            concat!("data/solar/", $name),
            include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/data/solar/", $name)),
        )
    };
}

/// (primakoff, abc, abc spectrum) files of `model`: (path, text).
fn files(model: BuiltinModel) -> [(&'static str, &'static str); 3] {
    match model {
        BuiltinModel::B16Agss09met => [
            solar_file!("primakoff_b16_agss09met.csv"),
            solar_file!("abc_b16_agss09met.csv"),
            solar_file!("abc_b16_agss09met_spectrum.csv"),
        ],
        BuiltinModel::B16Gs98 => [
            solar_file!("primakoff_b16_gs98.csv"),
            solar_file!("abc_b16_gs98.csv"),
            solar_file!("abc_b16_gs98_spectrum.csv"),
        ],
    }
}

/// The tables of `model`, parsed once.
pub fn tables(model: BuiltinModel) -> &'static ModelTables {
    static TABLES: [OnceLock<ModelTables>; 2] = [OnceLock::new(), OnceLock::new()];
    let k = BuiltinModel::ALL.iter().position(|m| *m == model).unwrap();
    TABLES[k].get_or_init(|| {
        let [(p_path, p_text), (a_path, a_text), (_, s_text)] = files(model);
        let primakoff = EmissionTable::parse_csv(p_text, Path::new(p_path))
            .expect("the shipped Primakoff tables are valid (tested)");
        let abc = EmissionTable::parse_csv(a_text, Path::new(a_path))
            .expect("the shipped ABC tables are valid (tested)");
        let abc_spectra = parse_process_spectra(s_text, &abc.energies)
            .expect("the shipped ABC spectra are valid (tested)");
        let title = model.title();
        ModelTables {
            primakoff,
            abc,
            abc_spectra,
            primakoff_description: format!("Primakoff emission (Raffelt 1986, Debye–Hückel screening) of the {title} standard solar model (Vinyoles et al. 2017), {p_path}"),
            abc_description: format!("axion–electron ABC emission (atomic from Opacity Project cross sections, electron–ion and electron–electron bremsstrahlung, Compton; Redondo 2013) of the {title} standard solar model, {a_path}"),
        }
    })
}

/// Reads the per-process columns `flux_<process>_per_cm2_s_keV` of a
/// `traxer solar-flux` spectrum.csv whose energies are `energies`.
pub fn parse_process_spectra(
    text: &str,
    energies: &[f64],
) -> Result<[Vec<f64>; 4], SolarDataError> {
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| SolarDataError(format!("spectrum: {e}")))?
        .clone();
    let column = |name: &str| {
        headers
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| SolarDataError(format!("spectrum: no column {name}")))
    };
    let energy = column("energy_keV")?;
    let columns: Vec<usize> = super::abc::PROCESSES
        .iter()
        .map(|p| column(&format!("flux_{p}_per_cm2_s_keV")))
        .collect::<Result<_, _>>()?;
    let mut out: [Vec<f64>; 4] = Default::default();
    for (k, record) in reader.records().enumerate() {
        let record = record.map_err(|e| SolarDataError(format!("spectrum: {e}")))?;
        let value = |i: usize| -> Result<f64, SolarDataError> {
            record
                .get(i)
                .and_then(|v| v.parse().ok())
                .ok_or_else(|| SolarDataError(format!("spectrum row {}: not a number", k + 2)))
        };
        let e = value(energy)?;
        if energies.get(k).is_none_or(|x| (x - e).abs() > 1e-9) {
            return Err(SolarDataError(format!(
                "spectrum row {}: energy {e} is not the table's",
                k + 2
            )));
        }
        for (o, &c) in out.iter_mut().zip(&columns) {
            o.push(value(c)?);
        }
    }
    if out[0].len() != energies.len() {
        return Err("spectrum: not one row per energy of the table".into());
    }
    Ok(out)
}
