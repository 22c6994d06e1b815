//! traxer's built-in solar axion emissions and their sum for chosen couplings:
//! Primakoff (g_aγ) and the axion–electron ABC processes (g_ae), both computed
//! from the B16-AGSS09met solar model (data/solar/README.md says how). Each
//! table is for a reference coupling; rates scale as the coupling squared.
//!
//! Data flow: a `sun` source (`emission = "primakoff" | "abc" | "primakoff+abc"`)
//! and `traxer solar-flux` ask [`builtin_emission`] for the table they sample
//! and report; the per-process split of ABC (atomic, electron–ion,
//! electron–electron, Compton) comes with it for spectra.

use super::emission::EmissionTable;
use super::model::{SolarDataError, SolarModel};
use super::opacity_project::OpacityTables;
use crate::constants::AU_CM;

/// The reference coupling of the Primakoff table, GeV⁻¹.
pub const G_AGAMMA_REFERENCE_PER_GEV: f64 = 1e-10;
/// The reference coupling of the ABC table.
pub use super::abc::G_AE_REFERENCE;
pub use super::tables::BuiltinModel;

/// The built-in Primakoff table of B16-AGSS09met (g_aγ = 1e-10 GeV⁻¹).
pub fn primakoff_table() -> &'static EmissionTable {
    &super::tables::tables(BuiltinModel::B16Agss09met).primakoff
}

/// The built-in ABC table of B16-AGSS09met (g_ae = 1e-13).
pub fn abc_table() -> &'static EmissionTable {
    &super::tables::tables(BuiltinModel::B16Agss09met).abc
}

/// The ABC spectrum of B16-AGSS09met at 1 AU per process on the ABC table's
/// energies (cm⁻² s⁻¹ keV⁻¹, g_ae = 1e-13), in the order of
/// [`super::abc::PROCESSES`].
pub fn abc_process_spectra() -> &'static [Vec<f64>; 4] {
    &super::tables::tables(BuiltinModel::B16Agss09met).abc_spectra
}

/// Which built-in emission a name asks for: (Primakoff, ABC).
pub fn parse_name(name: &str) -> Option<(bool, bool)> {
    match name {
        "primakoff" => Some((true, false)),
        "abc" => Some((false, true)),
        "primakoff+abc" | "abc+primakoff" => Some((true, true)),
        _ => None,
    }
}

/// The names of the built-in emissions, for messages.
pub const BUILTIN_NAMES: &str = "\"primakoff\", \"abc\" or \"primakoff+abc\"";

/// How a front end spells the emission and its two couplings (the scene's keys,
/// the CLI's options, Python's arguments), so that its messages name what the
/// user wrote.
pub struct CouplingNames {
    /// Between a name and its value: " = " in a scene, " " on the command line.
    pub assign: &'static str,
    pub emission: &'static str,
    pub g_agamma: &'static str,
    pub g_ae: &'static str,
}

/// The couplings of built-in emission `emission`, checked for every front end:
/// a coupling given for a process the emission does not have is refused (never
/// ignored), one not given takes the table's reference value, and one whose
/// square would make the table's rates underflow to zero in double precision is
/// refused by name (an emission of exactly zero is not what anyone asked for).
/// Returns (g_aγ, g_ae), `None` for a process left out.
pub fn checked_couplings(
    emission: &str,
    g_agamma: Option<f64>,
    g_ae: Option<f64>,
    names: &CouplingNames,
) -> Result<(Option<f64>, Option<f64>), String> {
    let Some((primakoff, abc)) = parse_name(emission) else {
        return Err(unknown_emission(emission, names.emission, names.assign));
    };
    for (name, g) in [(names.g_agamma, g_agamma), (names.g_ae, g_ae)] {
        if let Some(g) = g.filter(|g| !(g.is_finite() && *g > 0.0)) {
            return Err(format!(
                "{name}{}{}: expected a positive coupling",
                names.assign,
                crate::text::number(g)
            ));
        }
    }
    if g_agamma.is_some() && !primakoff {
        return Err(format!(
            "{} is the coupling of the Primakoff emission, but {}{}\"{emission}\" has none (use \"primakoff+abc\" for both)",
            names.g_agamma, names.emission, names.assign
        ));
    }
    if g_ae.is_some() && !abc {
        return Err(format!(
            "{} is the coupling of the ABC emission, but {}{}\"{emission}\" has none (use \"abc\" or \"primakoff+abc\")",
            names.g_ae, names.emission, names.assign
        ));
    }
    let g_agamma = primakoff.then(|| g_agamma.unwrap_or(G_AGAMMA_REFERENCE_PER_GEV));
    let g_ae = abc.then(|| g_ae.unwrap_or(G_AE_REFERENCE));
    if let Some(g) = g_agamma {
        check_representable(
            &format!("{}{}", names.g_agamma, names.assign),
            g,
            G_AGAMMA_REFERENCE_PER_GEV,
            primakoff_table(),
        )?;
    }
    if let Some(g) = g_ae {
        check_representable(
            &format!("{}{}", names.g_ae, names.assign),
            g,
            G_AE_REFERENCE,
            abc_table(),
        )?;
    }
    Ok((g_agamma, g_ae))
}

/// The message for an emission name that is none of the built-in ones.
pub fn unknown_emission(emission: &str, key: &str, assign: &str) -> String {
    let hint = match parse_name(&emission.to_lowercase()) {
        Some(_) => format!(" (names are lower case: \"{}\")", emission.to_lowercase()),
        None => String::new(),
    };
    format!("{key}{assign}\"{emission}\": expected {BUILTIN_NAMES}{hint}")
}

/// Refuses coupling `g` (reference `g_ref` of `table`) if scaling the table by
/// (g/g_ref)² makes any of its non-zero rates zero or subnormal. `name` is
/// what precedes the value in the message ("g_ae = ").
fn check_representable(
    name: &str,
    g: f64,
    g_ref: f64,
    table: &EmissionTable,
) -> Result<(), String> {
    let smallest = table
        .rates
        .iter()
        .copied()
        .filter(|w| *w > 0.0)
        .fold(f64::INFINITY, f64::min);
    let factor = (g / g_ref).powi(2);
    // (NaN never comes here: g is checked finite and positive.)
    if smallest.is_finite() && smallest * factor < f64::MIN_POSITIVE {
        let lowest = g_ref * (f64::MIN_POSITIVE / smallest).sqrt();
        return Err(format!(
            "{name}{g:e}: the emission scales as the coupling squared, ({g:e}/{g_ref:e})² = {factor:.3e}, and its rates would underflow to zero in double precision (the emission would come out zero, or with its weakest parts missing); give a coupling of at least {lowest:.1e}"
        ));
    }
    Ok(())
}

/// One part of an emission: a name and its dΦ/dE at 1 AU on the emission's
/// energies (cm⁻² s⁻¹ keV⁻¹), and (for radial profiles) its table.
#[derive(Clone, Debug)]
pub struct EmissionPart {
    pub name: String,
    pub spectrum_1au: Vec<f64>,
    pub table: Option<EmissionTable>,
}

impl EmissionPart {
    /// The part's flux at 1 AU, cm⁻² s⁻¹: its spectrum integrated over the energy
    /// cells between `energy_edges` (those of the emission's table).
    pub fn flux_1au(&self, energy_edges: &[f64]) -> f64 {
        self.spectrum_1au
            .iter()
            .zip(energy_edges.windows(2))
            .map(|(f, w)| f * (w[1] - w[0]))
            .sum()
    }
}

/// One coupling's share of an emission: its table at the reference coupling (on
/// the emission's energies) and the factor (g/g_ref)² that scales it to the
/// chosen coupling. A trace draws its photons from these tables, not from their
/// sum, so that where a photon goes does not depend on the couplings (see
/// [`super::SunEmission`]).
#[derive(Clone, Debug)]
pub struct CouplingPart {
    /// "primakoff" (∝ g_aγ²) or "abc" (∝ g_ae²).
    pub name: String,
    pub reference: EmissionTable,
    pub factor: f64,
    /// ABC's four processes' shares in each cell of `reference`, if known.
    pub shares: Option<super::shares::ProcessShares>,
}

/// An emission for chosen couplings: the table to sample, its parts (Primakoff,
/// the four ABC processes, ABC), its parts by coupling, and what it is.
#[derive(Clone, Debug)]
pub struct AxionEmission {
    pub table: EmissionTable,
    pub parts: Vec<EmissionPart>,
    pub couplings: Vec<CouplingPart>,
    pub description: String,
    pub coupling: String,
}

/// ABC at its reference coupling: the table, its spectrum per process and its
/// processes' shares in each cell.
pub struct AbcAtReference<'a> {
    pub table: &'a EmissionTable,
    pub process_spectra_1au: &'a [Vec<f64>; 4],
    pub description: &'a str,
    pub shares: Option<super::shares::ProcessShares>,
}

/// Primakoff (table at g_aγ = 1e-10 GeV⁻¹, description, coupling in GeV⁻¹) and/or
/// ABC (at g_ae = 1e-13, with g_ae) summed for those couplings. With both, the
/// Primakoff table is resampled onto the ABC table's energy cells when they
/// differ (the same radii), keeping its rate between common cell edges.
pub fn compose(
    primakoff: Option<(&EmissionTable, &str, f64)>,
    abc: Option<(AbcAtReference, f64)>,
) -> Result<AxionEmission, SolarDataError> {
    let valid = |g: f64| g.is_finite() && g > 0.0;
    if primakoff.as_ref().is_some_and(|p| !valid(p.2)) || abc.as_ref().is_some_and(|a| !valid(a.1))
    {
        return Err("couplings must be finite and positive".into());
    }
    let mut tables = Vec::new();
    let mut parts = Vec::new();
    let mut couplings = Vec::new();
    let mut what = Vec::new();
    let mut coupling = Vec::new();
    if let Some((table, _, g)) = &primakoff {
        check_representable("g_aγ = ", *g, G_AGAMMA_REFERENCE_PER_GEV, table)?;
    }
    if let Some((a, g)) = &abc {
        check_representable("g_ae = ", *g, G_AE_REFERENCE, a.table)?;
    }
    if let Some((table, description, g)) = primakoff {
        let factor = (g / G_AGAMMA_REFERENCE_PER_GEV).powi(2);
        let mut t = table.scaled(factor);
        let mut reference = table.clone();
        if let Some((a, _)) = &abc {
            if a.table.radii != t.radii {
                return Err("Primakoff and ABC tables to be added need the same radii".into());
            }
            if a.table.energies != t.energies {
                t = t.resampled(&a.table.energies)?;
                reference = reference.resampled(&a.table.energies)?;
            }
        }
        couplings.push(CouplingPart {
            name: "primakoff".into(),
            reference,
            factor,
            shares: None,
        });
        parts.push(EmissionPart {
            name: "primakoff".into(),
            spectrum_1au: t.spectrum_at(AU_CM),
            table: Some(t.clone()),
        });
        tables.push(t);
        what.push(description.to_string());
        coupling.push(format!("g_aγ = {g:e} GeV⁻¹"));
    }
    if let Some((a, g)) = abc {
        let factor = (g / G_AE_REFERENCE).powi(2);
        let t = a.table.scaled(factor);
        couplings.push(CouplingPart {
            name: "abc".into(),
            reference: a.table.clone(),
            factor,
            shares: a.shares.clone(),
        });
        for (name, s) in super::abc::PROCESSES.iter().zip(a.process_spectra_1au) {
            parts.push(EmissionPart {
                name: (*name).into(),
                spectrum_1au: s.iter().map(|x| x * factor).collect(),
                table: None,
            });
        }
        parts.push(EmissionPart {
            name: "abc".into(),
            spectrum_1au: t.spectrum_at(AU_CM),
            table: Some(t.clone()),
        });
        tables.push(t);
        what.push(a.description.to_string());
        coupling.push(format!("g_ae = {g:e}"));
    }
    if tables.is_empty() {
        return Err("an emission needs Primakoff, ABC or both".into());
    }
    let table = EmissionTable::sum(&tables)?;
    if !table.rates.iter().all(|w| w.is_finite())
        || !table.luminosity(0.0, f64::INFINITY).is_finite()
    {
        return Err(format!(
            "{}: the emission overflows the numbers a computer holds (couplings this large are far beyond what the Sun allows)",
            coupling.join(", ")
        )
        .into());
    }
    Ok(AxionEmission {
        table,
        parts,
        couplings,
        description: what.join(" + "),
        coupling: coupling.join(", "),
    })
}

/// The built-in emission with Primakoff at g_aγ = `g_agamma` GeV⁻¹ and/or ABC at
/// g_ae = `g_ae` (None: left out).
pub fn builtin_emission(
    g_agamma: Option<f64>,
    g_ae: Option<f64>,
) -> Result<AxionEmission, SolarDataError> {
    builtin_emission_of(BuiltinModel::B16Agss09met, g_agamma, g_ae)
}

/// As [`builtin_emission`], from the built-in tables of `model`. ABC's
/// process shares are shipped for B16-AGSS09met only: with B16-GS98 a trace
/// records no images of ABC's four processes.
pub fn builtin_emission_of(
    model: BuiltinModel,
    g_agamma: Option<f64>,
    g_ae: Option<f64>,
) -> Result<AxionEmission, SolarDataError> {
    let t = super::tables::tables(model);
    let shares = match model {
        BuiltinModel::B16Agss09met => Some(super::shares::builtin_shares().clone()),
        BuiltinModel::B16Gs98 => None,
    };
    compose(
        g_agamma.map(|g| (&t.primakoff, t.primakoff_description.as_str(), g)),
        g_ae.map(|g| {
            (
                AbcAtReference {
                    table: &t.abc,
                    process_spectra_1au: &t.abc_spectra,
                    description: &t.abc_description,
                    shares,
                },
                g,
            )
        }),
    )
}

/// How far beyond its first and last rows (fractions of R_sun) a model is
/// taken as it is: the centre below B16's first row (r = 0.0045), the
/// surface at its last.
const MODEL_EDGE: f64 = 0.01;

/// The emission is computed only where the model has rows: a model of a few
/// rows would otherwise stand for the whole Sun (a plausible flux, wrong by
/// any factor).
fn check_coverage(model: &SolarModel, name: &str, radii: &[f64]) -> Result<(), SolarDataError> {
    let (first, last) = (
        model.shells[0].radius,
        model.shells[model.shells.len() - 1].radius,
    );
    let (lo, hi) = radii
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(*r), b.max(*r))
        });
    if lo < first - MODEL_EDGE || hi > last + MODEL_EDGE {
        return Err(SolarDataError(format!(
            "{name}: the model's rows reach r = {first} … {last} R_sun, but the emission is asked for r = {lo} … {hi}: traxer does not extrapolate a solar model; give the whole model, or radii within its rows"
        )));
    }
    Ok(())
}

/// The emission computed from a standard solar model (`name` for descriptions)
/// on `radii` × `energies`; ABC needs the Opacity Project tables `op`.
pub fn model_emission(
    model: &SolarModel,
    name: &str,
    op: Option<&OpacityTables>,
    radii: &[f64],
    energies: &[f64],
    g_agamma: Option<f64>,
    g_ae: Option<f64>,
) -> Result<AxionEmission, SolarDataError> {
    EmissionTable::check_grid(radii, energies)?;
    check_coverage(model, name, radii)?;
    let primakoff = match g_agamma {
        Some(_) => Some(super::primakoff::emission_table(model, radii, energies)?),
        None => None,
    };
    let abc = match g_ae {
        Some(_) => {
            let op = op.ok_or("the ABC emission needs the Opacity Project tables")?;
            Some(super::abc::emission_tables(model, op, radii, energies)?)
        }
        None => None,
    };
    let spectra = abc.as_ref().map(|a| {
        let s: [Vec<f64>; 4] = std::array::from_fn(|k| a.processes[k].spectrum_at(AU_CM));
        s
    });
    let p_description = format!("Primakoff emission of {name}");
    let a_description = format!("ABC emission of {name}");
    compose(
        primakoff
            .as_ref()
            .zip(g_agamma)
            .map(|(t, g)| (t, p_description.as_str(), g)),
        abc.as_ref()
            .zip(spectra.as_ref())
            .zip(g_ae)
            .map(|((a, s), g)| {
                (
                    AbcAtReference {
                        table: &a.total,
                        process_spectra_1au: s,
                        description: &a_description,
                        shares: Some(std::sync::Arc::new(super::shares::shares_of(&a.processes))),
                    },
                    g,
                )
            }),
    )
}

#[cfg(test)]
mod coverage_tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn a_model_of_a_few_rows_does_not_stand_for_the_whole_sun() {
        // Before: two rows at r = 0.1 and 0.3 gave a Primakoff flux for the
        // whole Sun, the outer rows repeated out to the surface.
        let row = super::super::model::test_row;
        let model =
            SolarModel::parse(&format!("{}\n{}\n", row(0.1), row(0.3)), Path::new("m")).unwrap();
        let energies = [1.0, 2.0];
        let asked = [0.15, 0.25, 0.9];
        let Err(e) = model_emission(&model, "m", None, &asked, &energies, Some(1e-10), None) else {
            panic!("refused")
        };
        assert!(
            e.0.contains("does not extrapolate") && e.0.contains("0.1 … 0.3"),
            "{e:?}"
        );
        assert!(model_emission(
            &model,
            "m",
            None,
            &[0.15, 0.25],
            &energies,
            Some(1e-10),
            None
        )
        .is_ok());
        let Err(one) = SolarModel::parse(&format!("{}\n", row(0.1)), Path::new("one.dat")) else {
            panic!("refused")
        };
        assert!(one.0.contains("1 model row(s)"), "{one:?}");
    }
}
